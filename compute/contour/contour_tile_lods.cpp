// compute/contour/contour_tile_lods.cpp - TileSurfaceCache's levels of detail built in the background: jobs queued
// on a LodWorker as tiles change, levels taken in when they are done.
#include <algorithm>
#include <string>
#include <utility>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/sorted_ids.hpp"
#include "core/error.hpp"

namespace tridex::compute {

std::uint64_t TileSurfaceCache::lod_key(bool group, std::uint64_t id) {
    constexpr std::uint64_t kGroupBit = std::uint64_t{1} << 63;  // tile and group ids stay below it (tile_group_id)
    return group ? (id | kGroupBit) : id;
}

void TileSurfaceCache::build_lods_in_background(LodWorkerOptions worker) {
    if (!lod_) throw Error("TileSurfaceCache::build_lods_in_background: call enable_lod() first");
    worker.lod = lod_options_;
    worker_ = std::make_unique<LodWorker>(worker);
    group_settle_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(worker.group_settle_s));
    tile_settle_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(worker.tile_settle_s));
}

void TileSurfaceCache::queue_tile_lods(const std::vector<std::size_t>& fresh) {
    const auto now = std::chrono::steady_clock::now();
    for (const std::size_t i : fresh) {
        const TileSurface& t = tiles_[i];
        const bool arrival = startup_arrival(t.id);  // start-up's (expect_tiles), however late
        if (arrival && startup_expected() > 0) {  // the groups stand in meanwhile: the tiles' contour goes first
            deferred_.push_back(t.id);
            continue;
        }
        if (refreshed_ && !arrival && tile_settle_.count() > 0) {  // a stroke's tile: queued once it has been quiet
            worker_->cancel(false, t.id);              // a waiting job for its older mesh would be thrown away
            settling_[t.id] = now;
            tile_due_ = std::min(tile_due_, now + tile_settle_);
            queued_[lod_key(false, t.id)] = Queued{now, true};
            continue;
        }
        worker_->submit(tile_job(i), refreshed_ && !arrival);
        queued_[lod_key(false, t.id)] = Queued{now, refreshed_ && !arrival};
    }
}

void TileSurfaceCache::queue_deferred_tiles() {
    const auto now = std::chrono::steady_clock::now();
    for (const std::uint64_t id : deferred_) {
        const std::size_t i = index_of(tiles_, id);
        if (i == tiles_.size() || !pending_[i] || queued_.count(lod_key(false, id))) continue;  // gone or a stroke's
        worker_->submit(tile_job(i), false);
        queued_[lod_key(false, id)] = Queued{now, false};
    }
    deferred_.clear();
}

LodJob TileSurfaceCache::tile_job(std::size_t i) const {
    LodJob job;
    job.id = tiles_[i].id;
    job.token = contour_versions_[i];
    job.mesh = tiles_[i].mesh;
    job.materials = tiles_[i].materials;
    job.normals = tiles_[i].normals;
    job.levels = tile_levels();
    return job;
}

void TileSurfaceCache::queue_settled_tiles(std::chrono::steady_clock::time_point now) {
    tile_due_ = std::chrono::steady_clock::time_point::max();
    for (auto it = settling_.begin(); it != settling_.end();) {
        if (now - it->second < tile_settle_) {
            tile_due_ = std::min(tile_due_, it->second + tile_settle_);
            ++it;
            continue;
        }
        const std::size_t i = index_of(tiles_, it->first);
        if (i < tiles_.size() && pending_[i]) {
            worker_->submit(tile_job(i), true);
        } else {
            queued_.erase(lod_key(false, it->first));  // gone since
        }
        it = settling_.erase(it);
    }
}

void TileSurfaceCache::queue_ready_groups() {
    const auto now = std::chrono::steady_clock::now();
    settle_due_ = std::chrono::steady_clock::time_point::max();
    for (std::size_t g = 0; g < groups_.size(); ++g) {
        if (!group_pending_[g] || group_queued_[g] || !group_ready(g)) continue;
        if (now - group_changed_at_[g] < group_settle_) {  // its tiles may change again: wait
            settle_due_ = std::min(settle_due_, group_changed_at_[g] + group_settle_);
            continue;
        }
        std::vector<LodPart> parts;
        gather_group_parts(groups_[g], parts);
        LodJob job;
        job.group = true;
        job.id = groups_[g].id;
        job.token = groups_[g].version;
        for (const LodPart& p : parts)
            job.parts.push_back(LodJobPart{*p.mesh, std::vector<std::uint8_t>(p.materials.begin(), p.materials.end()),
                                           std::vector<Vec3>(p.normals.begin(), p.normals.end()), p.error_m});
        worker_->submit(std::move(job), refreshed_);
        group_queued_[g] = true;
        // Start-up's groups are queued after the first refresh too, once their tiles are in: still start-up's.
        const std::uint64_t key = lod_key(true, groups_[g].id);
        queued_[key] = Queued{now, refreshed_ && startup_waiting_.count(key) == 0};
    }
}

std::size_t TileSurfaceCache::collect_lods(bool stroke_open, const std::function<bool()>& yield) {
    const std::size_t coarse = coarse_ ? settle_coarse_levels(std::chrono::steady_clock::now(), stroke_open, yield) : 0;
    // Levels that arrived can stand in now; levels' errors still to measure, but not while a stroke is open.
    if (startup_groups_ && (coarse > 0 || (remeasure_more_ && !stroke_open))) update_startup_groups(!stroke_open);
    if (!worker_) return coarse;
    std::vector<LodResult> results;
    worker_->take(results);
    const auto now = std::chrono::steady_clock::now();
    if (now >= tile_due_) queue_settled_tiles(now);
    std::size_t taken = 0;
    for (LodResult& r : results) {
        bool fits = false;
        if (!r.group) {
            const std::size_t i = index_of(tiles_, r.id);
            if (i < tiles_.size() && pending_[i] && contour_versions_[i] == r.token) {
                tiles_[i].lods = std::move(r.levels);
                tiles_[i].mesh = std::move(r.mesh);  // the same triangles, in vertex-cache order
                tiles_[i].lods_built = true;
                tiles_[i].version = fresh_tile_version();
                pending_[i] = false;
                ++lod_tiles_built_;
                fits = true;
            }
        } else {
            const std::size_t g = index_of(groups_, r.id);
            if (g < groups_.size() && group_pending_[g] && groups_[g].version == r.token) {
                groups_[g].lods = std::move(r.levels);
                groups_[g].version = fresh_tile_version();
                groups_[g].levels_waiting = false;
                group_pending_[g] = false;
                group_queued_[g] = false;
                ++lod_groups_built_;
                fits = true;
            }
        }
        if (!fits) {  // stale: the tile or group changed after its job was queued (a newer job follows) or is gone
            ++lod_discarded_;
            const bool gone = r.group ? index_of(groups_, r.id) == groups_.size() : index_of(tiles_, r.id) == tiles_.size();
            if (gone) {
                queued_.erase(lod_key(r.group, r.id));
                startup_waiting_.erase(lod_key(r.group, r.id));
            }
            continue;
        }
        startup_waiting_.erase(lod_key(r.group, r.id));
        ++taken;
        lod_build_ms_ += r.build_ms;
        const auto q = queued_.find(lod_key(r.group, r.id));
        if (q != queued_.end()) {
            if (q->second.after_start)
                lod_latency_ms_.add(std::chrono::duration<double, std::milli>(now - q->second.at).count());
            queued_.erase(q);
        }
    }
    if (refreshed_ && startup_waiting_.empty() && startup_expected() == 0) worker_->end_startup();  // start-up's all in
    // A result can make a group ready, and time ends a ready group's settling.
    if (!results.empty() || now >= settle_due_) queue_ready_groups();
    return taken + coarse;
}

}  // namespace tridex::compute
