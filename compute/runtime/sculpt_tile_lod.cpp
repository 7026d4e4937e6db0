// compute/runtime/sculpt_tile_lod.cpp - the sculpt thread's levels of detail: the tile cache's worker, and the
// coarse-first start-up (finer coarse depths and regions of full-resolution tiles after a first mesh of coarse group
// levels; docs/design/lod.md, "Coarse first at start-up").
#include <algorithm>
#include <chrono>

#include "compute/contour/held_tiles.hpp"
#include "compute/contour/refine_wanted.hpp"
#include "compute/contour/sorted_ids.hpp"
#include "compute/runtime/gpu_contour_share.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"

namespace tridex::app {

void SculptThread::use_tile_lod(const compute::LodWorkerOptions& options) {
    if (thread_.joinable()) throw Error("SculptThread::use_tile_lod: call it before start()");
    if (mesh_out_) throw Error("SculptThread::use_tile_lod: call it before publish_mesh_to()");
    lod_options_ = options;
    arm_tile_lod(options);
}

namespace {
// The deepest group a coarse-first start-up refines as one region (8x8x8 tiles), whatever the coarsest depth.
constexpr int kStartupRegionDepth = 3;
// While a stroke is open the refinement yields sooner, in smaller blocks (2x2x2 tiles): the stroke's samples wait
// for it, and the cut is drawn only after them.
constexpr double kRefineStrokeSliceS = 0.02;
constexpr int kRefineStrokeBlockDepth = 1;
}  // namespace

void SculptThread::arm_tile_lod(const compute::LodWorkerOptions& options) {
    const bool coarse = !gpu_contour_ && compute::coarse_groups_apply(model_.lattice.cells, options.coarse_groups_from_cells);
    if (options.coarse_first && !coarse)
        throw Error("SculptThread::use_tile_lod: coarse_first needs coarse groups on the CPU contour");
    tile_cache_.enable_lod(options.lod);
    if (coarse) {
        compute::CoarseLevelOptions levels;
        levels.max_depth = options.coarse_max_depth;
        tile_cache_.use_coarse_groups(model_, levels, options.coarse_first);
        if (options.coarse_first) {
            refiner_ = std::make_unique<compute::StartupRefiner>(model_, std::min(levels.max_depth, kStartupRegionDepth),
                                                                 published_centre_m_);
            tile_cache_.expect_tiles(refiner_->pending_tiles());
        }
    }
    compute::LodWorkerOptions worker = options;
    // Coarse first: the groups stand in for the tiles' own levels; the tiles' contour goes first.
    if (refiner_) worker.startup_nice = worker.nice;
    tile_cache_.build_lods_in_background(worker);
    if (gpu_contour_) gpu_contour_->read_back_tiles();
    count_deferred();
    deferral_.reset();
    if (coarse && options.stroke_coarse) deferral_ = std::make_unique<compute::DeferredContour>(model_.tiles.tiles);
    if (refiner_) refiner_->contour_beside(deferral_.get());
}

void SculptThread::refine_on_demand(compute::DetailRequests& requests) {
    if (thread_.joinable()) throw Error("SculptThread::refine_on_demand: call it before start()");
    detail_ = &requests;
}

void SculptThread::collect_lods() {
    if (!tile_cache_.lod_enabled()) return;
    // While a stroke is open no coarse level contours its tiles: the stroke's samples would wait for it.
    const bool stroke = history_ && history_->stroke_open();
    // A cut waiting: no coarse tile is contoured either, as during a stroke (the cut's pass comes first); one that
    // comes meanwhile ends the coarse re-read and contouring after their current batch or level.
    const auto waits = [this] { return !stop_.load(std::memory_order_acquire) && cut_waiting(); };
    const bool yield = !stroke && waits();
    // Levels taken in go out with the next mesh.
    if (tile_cache_.collect_lods(stroke || yield, waits) > 0 && mesh_out_) mesh_pending_ = true;
    const std::size_t pending = tile_cache_.lod_pending();
    if (tile_cache_.startup_lod_pending() == 0 && stats_.lod_all_built_s < 0.0 && mesh_version_ > 0)
        stats_.lod_all_built_s = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    lod_pending_.store(pending, std::memory_order_release);
}

void SculptThread::follow_drawn_groups(compute::DrawnGroups& drawn) {
    if (thread_.joinable()) throw Error("SculptThread::follow_drawn_groups: call it before start()");
    drawn_ = &drawn;
}

std::size_t SculptThread::refine_requested(const std::function<bool()>& in_slice, int block_depth) {
    // The groups the frames asked for, and those whose coarse reads missed a surface that tiles not yet in hold
    // (start-up's, or a stroke's drawn coarse: nothing stands in there).
    std::vector<std::uint64_t> ids = detail_->take();
    compute::merge_ids(ids, tile_cache_.missed_surface_groups());
    const compute::WantedRefined n = compute::refine_wanted_groups(
        ids, tile_cache_.groups(), model_, contourer_, refiner_.get(), deferral_.get(), block_depth, in_slice);
    stats_.startup_tiles_refined += n.startup;
    return n.startup + n.deferred;
}

void SculptThread::refine_startup(bool finish) {
    const bool startup = refiner_ && !refiner_->done();
    const bool deferred = deferral_ && deferral_->count() > 0;
    if (!startup && !deferred) return;
    if (finish) {
        if (startup) stats_.startup_tiles_refined += refiner_->finish(model_, contourer_);
        if (deferred) deferral_->contour_all(model_, contourer_);
    } else if (!startup || history_->stroke_open() || cut_waiting() || !tile_cache_.build_coarse_depth()) {
        // The finer coarse depths first (frames draw their levels once tiles arrive), but never while a stroke is
        // open or a cut waits: reading a finer depth of a fine model holds the thread, and the samples would wait.
        // Regions until kRefineSliceS has passed: a mesh publish per region would cost about as much as the region.
        const auto t0 = std::chrono::steady_clock::now();
        const bool stroke = history_->stroke_open();
        const double slice_s = stroke ? kRefineStrokeSliceS : kRefineSliceS;
        const int block_depth = stroke ? kRefineStrokeBlockDepth : compute::kWantedBlockDepth;
        // A slice ends early when a cutting sample waits (its pass comes first), after one unit of work (a block, a
        // region, a batch of deferred tiles), so that a tool held cutting in air does not stop the work for good.
        bool begun = false, yielded = false;
        const auto in_slice = [&] {
            if (begun && !stroke && cut_waiting()) yielded = true;
            begun = true;
            return !yielded && std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < slice_s;
        };
        std::size_t refined = 0;
        // Only the groups the frames asked for; the rest of start-up's again when a frame asks for it.
        if (detail_) refined += refine_requested(in_slice, block_depth);
        if (!stroke && startup && !detail_) {  // a region (up to 8x8x8 tiles) is not split: it waits for the close
            do {
                const std::size_t n = refiner_->refine_next(model_, contourer_);
                stats_.startup_tiles_refined += n;
                refined += n;
            } while (!refiner_->done() && in_slice());
        }
        // A stroke's deferred tiles once it closed, oldest first, whether or not a frame asks for them: a save or an
        // export of the mesh reads them, and their levels of detail follow.
        while (!stroke && deferral_ && deferral_->count() > 0 && in_slice()) {
            refined += deferral_->contour_oldest(model_, contourer_, compute::DeferredContour::kTilesPerBatch);
        }
        if (yielded) ++stats_.background_yields;
        if (refined == 0 && !(startup && refiner_->done())) return;  // nothing new to publish
    }
    if (mesh_out_) mesh_pending_ = true;
}

void SculptThread::count_deferred() {
    if (deferral_) stats_.deferred_tiles_contoured += deferral_->take_released();
}

void SculptThread::refresh_tile_cache() {
    count_deferred();
    // While a stroke's tiles are hidden, the groups the frames drew over their bound get finer coarse levels.
    if (deferral_ && detail_ && history_ && history_->stroke_open()) tile_cache_.want_detail(detail_->take());
    if (deferral_ && drawn_) tile_cache_.frames_drew(drawn_->take());
    compute::refresh_held_tiles(tile_cache_, contourer_, refiner_.get(), deferral_.get());
    if (refiner_ && refiner_->done()) refiner_.reset();  // every tile is in: the next publish counts as refined
}

}  // namespace tridex::app
