// compute/runtime/sculpt_tile_lod.cpp - the sculpt thread's levels of detail: the tile cache's worker, and the
// coarse-first start-up (finer coarse depths and regions of full-resolution tiles after a first mesh of coarse group
// levels; docs/design/lod.md, "Coarse first at start-up").
#include <algorithm>
#include <chrono>

#include "compute/runtime/sculpt_thread.hpp"
#include "compute/runtime/gpu_contour_share.hpp"
#include "core/error.hpp"

namespace tridex::app {

void SculptThread::use_tile_lod(const compute::LodWorkerOptions& options) {
    if (thread_.joinable()) throw Error("SculptThread::use_tile_lod: call it before start()");
    if (mesh_out_) throw Error("SculptThread::use_tile_lod: call it before publish_mesh_to()");
    lod_options_ = options;
    arm_tile_lod(options);
}

void SculptThread::arm_tile_lod(const compute::LodWorkerOptions& options) {
    const bool coarse = !gpu_contour_ && compute::coarse_groups_apply(model_.lattice.cells, options.coarse_groups_from_cells);
    if (options.coarse_first && !coarse)
        throw Error("SculptThread::use_tile_lod: coarse_first needs coarse groups on the CPU contour");
    tile_cache_.enable_lod(options.lod);
    if (coarse) {
        const compute::CoarseLevelOptions levels;
        tile_cache_.use_coarse_groups(model_, levels, options.coarse_first);
        if (options.coarse_first) {
            refiner_ = std::make_unique<compute::StartupRefiner>(model_, levels.max_depth, published_centre_m_);
            tile_cache_.expect_tiles(refiner_->pending_tiles());
        }
    }
    compute::LodWorkerOptions worker = options;
    // Coarse first: the groups stand in for the tiles' own levels; the tiles' contour goes first.
    if (refiner_) worker.startup_nice = worker.nice;
    tile_cache_.build_lods_in_background(worker);
    if (gpu_contour_) gpu_contour_->read_back_tiles();
}

void SculptThread::collect_lods() {
    if (!tile_cache_.lod_enabled()) return;
    if (tile_cache_.collect_lods() > 0 && mesh_out_) mesh_pending_ = true;  // published with the next mesh
    const std::size_t pending = tile_cache_.lod_pending();
    if (tile_cache_.startup_lod_pending() == 0 && stats_.lod_all_built_s < 0.0 && mesh_version_ > 0)
        stats_.lod_all_built_s = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    lod_pending_.store(pending, std::memory_order_release);
}

void SculptThread::refine_startup(bool finish) {
    if (!refiner_ || refiner_->done()) return;
    if (finish) {
        stats_.startup_tiles_refined += refiner_->finish(model_, contourer_);
    } else if (!tile_cache_.build_coarse_depth()) {  // the finer levels first: frames draw them once tiles arrive
        // Regions until kRefineSliceS has passed: a mesh publish per region would cost about as much as the region.
        const auto t0 = std::chrono::steady_clock::now();
        do {
            stats_.startup_tiles_refined += refiner_->refine_next(model_, contourer_);
        } while (!refiner_->done() &&
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < kRefineSliceS);
    }
    if (mesh_out_) mesh_pending_ = true;
}

void SculptThread::refresh_tile_cache() {
    if (!refiner_) {
        tile_cache_.refresh(contourer_);
        return;
    }
    tile_cache_.arrive(refiner_->take_newly_publishable());
    tile_cache_.refresh(compute::StartupRefiner::Source(contourer_, *refiner_));
    if (refiner_->done()) refiner_.reset();  // every tile is in: the next publish counts as refined
}

}  // namespace tridex::app
