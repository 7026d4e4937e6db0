// tests/compute/test_coarse_first_session.hpp - a coarse-first start-up driven as the sculpt thread drives it
// (StartupRefiner, TileSurfaceCache::expect_tiles), shared by the tests of the coarse levels and their passes.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/startup_refine.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute::testing {

// Regions of 2x2x2 tiles: the sphere's 8x8x8 tiles are one depth-3 region, sessions refine by depth-3 groups.
inline constexpr int kRegionDepth = 1;

inline TriDexel sphere_model() { return off_centre_sphere(); }

// Levels of detail on `cache` at `model`'s cell size, with coarse group levels (`coarse_first`: a coarse-first
// start-up, TileSurfaceCache::use_coarse_groups).
inline void use_coarse_lod(TileSurfaceCache& cache, const TriDexel& model, const CoarseLevelOptions& levels = {},
                           bool coarse_first = false) {
    TileLodOptions o;
    o.cell_m = model.lattice.cell_m;
    cache.enable_lod(o);
    cache.use_coarse_groups(model, levels, coarse_first);
}

// Groups take every level until none waits, and the errors of the coarse-first levels are measured.
inline void settle(TileSurfaceCache& cache) {
    for (int i = 0; i < 400; ++i) cache.collect_lods();
    EXPECT_EQ(cache.coarse_waiting(), 0u);
}

// The coarse-first start-up, as the sculpt thread runs it.
struct CoarseFirst {
    TriDexel model;
    Contourer contourer{model};
    TileSurfaceCache cache;
    std::unique_ptr<StartupRefiner> refiner;
    CoarseFirst() : CoarseFirst(sphere_model()) {}
    explicit CoarseFirst(TriDexel m, const CoarseLevelOptions& levels = {}) : model(std::move(m)) {
        use_coarse_lod(cache, model, levels, true);
        refiner = std::make_unique<StartupRefiner>(model, kRegionDepth, model.lattice.to_world(Vec3(0.0)));
        cache.expect_tiles(refiner->pending_tiles());
        refresh();
    }
    void refresh() {
        cache.arrive(refiner->take_newly_publishable());
        cache.refresh(StartupRefiner::Source(contourer, *refiner));
    }
    // What SculptThread::contour_changed does for a change during the refinement.
    void contour_change() {
        const std::vector<std::uint32_t> d = model.tiles.dirty_tiles();
        const std::vector<std::uint64_t> dirty(d.begin(), d.end());
        cache.stop_expecting(refiner->pending_among(dirty));
        refiner->contour_with_change(model, dirty);
        contourer.update(model);
        refresh();
    }
    void refine_all() {
        while (cache.build_coarse_depth()) {}
        while (refiner->refine_next(model, contourer) > 0) refresh();
        refresh();
        settle(cache);
    }
};

}  // namespace tridex::compute::testing
