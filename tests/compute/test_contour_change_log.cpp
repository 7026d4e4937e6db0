// Tests of the tile change records (compute/contour/tile_change_log.hpp) and of TileSurfaceCache::refresh visiting
// only the tiles its source says may have changed: through a start-up's refinement and a stroke's deferral, a cache
// refreshed after every step holds what a cache refreshed once, over every tile, holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/deferred_contour.hpp"
#include "compute/contour/held_tiles.hpp"
#include "compute/contour/startup_refine.hpp"
#include "compute/contour/tile_change_log.hpp"
#include "compute/tools/boolean.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

TEST(TileChangeLog, ListsTheTilesAfterAMarkAndRefusesAMarkItNoLongerCovers) {
    const std::uint64_t before = fresh_tile_version();
    TileChangeLog log;
    std::vector<std::uint64_t> out;
    EXPECT_FALSE(log.since(before, out)) << "a mark from before the log was made";
    const std::uint64_t start = fresh_tile_version();
    log.add(fresh_tile_version(), 7);
    const std::uint64_t middle = fresh_tile_version();
    const std::uint64_t stamp = fresh_tile_version();
    log.add(stamp, 3);
    log.add(stamp, 7);
    ASSERT_TRUE(log.since(start, out));
    EXPECT_EQ(out, (std::vector<std::uint64_t>{7, 3, 7}));
    out.clear();
    ASSERT_TRUE(log.since(middle, out));
    EXPECT_EQ(out, (std::vector<std::uint64_t>{3, 7}));
    out.clear();
    ASSERT_TRUE(log.since(fresh_tile_version(), out));
    EXPECT_TRUE(out.empty());
    for (std::size_t i = 0; i < TileChangeLog::kMaxEntries; ++i) log.add(fresh_tile_version(), i);
    EXPECT_FALSE(log.since(middle, out)) << "its entries after the mark were dropped";
    EXPECT_TRUE(out.empty());
    const std::uint64_t late = fresh_tile_version();
    log.add(fresh_tile_version(), 1);
    ASSERT_TRUE(log.since(late, out));
    EXPECT_EQ(out, (std::vector<std::uint64_t>{1}));
    EXPECT_NE(log.id(), TileChangeLog().id());
}

// Cut k of a groove across the sphere's +z cap (`side` 0), or across its -y side (`side` 1).
void cut(TriDexel& m, int k, int side = 0) {
    const Lattice& L = m.lattice;
    const double r = kOffCentreRadius - 4.0;
    const auto at = [&](double u) {
        return L.to_world(kOffCentre +
                          (side == 0 ? Vec3(-30.0 + 12.0 * u, 8.0 * u, r) : Vec3(-30.0 + 12.0 * u, -r, 6.0 * u)));
    };
    subtract_capsule(m, Segment{at(k), at(k + 1)}, 6.0 * L.cell_m);
}

// The same tiles, versions and meshes in both caches.
void expect_same_tiles(const TileSurfaceCache& a, const TileSurfaceCache& b) {
    ASSERT_EQ(a.tiles().size(), b.tiles().size());
    for (std::size_t i = 0; i < a.tiles().size(); ++i) {
        const TileSurface& x = a.tiles()[i];
        const TileSurface& y = b.tiles()[i];
        ASSERT_EQ(x.id, y.id);
        EXPECT_EQ(x.source_version, y.source_version) << "tile " << x.id;
        EXPECT_EQ(x.mesh.positions, y.mesh.positions) << "tile " << x.id;
        EXPECT_EQ(x.normals, y.normals) << "tile " << x.id;
    }
}

// Strokes deferred and their tiles contoured later, changes contoured at once (beside them and away from them), with
// a coarse-first start-up refined region by region (`startup`) or after it; the cache refreshed through the held
// tiles (as the sculpt thread does) after every step, and compared with a cache that reads every tile once.
void run_session(bool startup) {
    TriDexel model = off_centre_sphere();
    Contourer contourer(model);
    std::unique_ptr<StartupRefiner> refiner;
    if (startup)
        refiner = std::make_unique<StartupRefiner>(model, 1, model.lattice.to_world(Vec3(0.0)));
    else
        contourer.update(model);
    DeferredContour deferral(model.tiles.tiles);
    if (refiner) refiner->contour_beside(&deferral);
    TileSurfaceCache cache;
    std::size_t visits = 0, refreshes = 0, first = 0;
    const auto check = [&] {
        refresh_held_tiles(cache, contourer, refiner.get(), &deferral);
        if (refreshes++ > 0) visits += cache.last_refresh_visits();  // the first reads every tile
        TileSurfaceCache whole;                                      // every tile read once, through the same view
        if (refiner) {
            const StartupRefiner::Source source(contourer, *refiner);
            whole.refresh(DeferredContour::Source(source, deferral));
        } else {
            whole.refresh(DeferredContour::Source(ContourerTiles(contourer), deferral));
        }
        expect_same_tiles(cache, whole);
        if (refreshes == 1) first = cache.tiles().size();
    };
    check();
    for (int step = 0; step < 24; ++step) {
        SCOPED_TRACE("step " + std::to_string(step));
        if (refiner && step % 3 == 0) refiner->refine_next(model, contourer);
        if (step % 4 == 1) {  // a stroke's step: deferred
            cut(model, step / 4);
            deferral.defer(model);
        }
        if (step % 4 == 3) deferral.contour_oldest(model, contourer, 5);  // between strokes
        if (step % 8 == 6) {  // changes contoured at once, taking the deferred tiles they reach
            cut(model, 2 + step / 8);
            cut(model, step / 8, 1);
            deferral.take_dirty(model);
            contourer.update(model);
        }
        check();
    }
    deferral.contour_all(model, contourer);
    if (refiner) refiner->finish(model, contourer);
    check();
    if (startup) {
        EXPECT_GT(cache.tiles().size(), first) << "the refinement's tiles arrived";
    }
    // The records answered: the refreshes after the first visited a small part of the tiles.
    EXPECT_LT(visits, (refreshes - 1) * contourer.tile_count() / 4) << visits << " visits in " << refreshes;
    EXPECT_GT(visits, 0u);
}

TEST(TileChangeLog, ACacheVisitingOnlyTheChangedTilesHoldsWhatAWholeScanReads) {
    {
        SCOPED_TRACE("during a coarse-first start-up");
        run_session(true);
    }
    {
        SCOPED_TRACE("after start-up");
        run_session(false);
    }
}

TEST(TileChangeLog, AMarkFromBeforeTheRecordsGetsNoAnswer) {
    TriDexel model = off_centre_sphere();
    const std::uint64_t before = fresh_tile_version();
    Contourer contourer(model);
    StartupRefiner refiner(model, 1, model.lattice.to_world(Vec3(0.0)));
    DeferredContour deferral(model.tiles.tiles);
    const StartupRefiner::Source startup(contourer, refiner);
    const DeferredContour::Source source(startup, deferral);
    std::vector<std::uint64_t> out;
    EXPECT_FALSE(source.changed_since(before, out));
    EXPECT_TRUE(source.changed_since(fresh_tile_version(), out));
    EXPECT_TRUE(out.empty());
    EXPECT_NE(source.change_view(), 0u);
    EXPECT_NE(source.change_view(), DeferredContour::Source(ContourerTiles(contourer), deferral).change_view());
    EXPECT_EQ(TileSurfaceCache().last_refresh_visits(), 0u);
}

}  // namespace
}  // namespace tridex::compute
