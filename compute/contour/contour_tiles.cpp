// compute/contour/contour_tiles.cpp - per-tile surface cache over a Contourer.
#include "compute/contour/contour_tiles.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <string>
#include <thread>
#include <utility>

#include "compute/contour/sorted_ids.hpp"
#include "compute/parallel/task_pool.hpp"
#include "core/error.hpp"

namespace tridex::compute {

std::size_t TileSurfaceCache::refresh(const Contourer& contourer) { return refresh(ContourerTiles(contourer)); }

TileSurfaceCache::TileRead TileSurfaceCache::read_tile_changes(const TileMeshSource& source) const {
    TileRead read;
    std::size_t old = 0;  // walks tiles_ (sorted by id) alongside the visited tiles, ascending
    const auto visit = [&](std::uint64_t t) {
        ++read.visited;
        while (old < tiles_.size() && tiles_[old].id < t) ++old;
        const bool had = old < tiles_.size() && tiles_[old].id == t;
        if (source.tile_triangle_count(t) == 0) {
            if (had) read.gone.push_back(old);
            return;
        }
        const std::uint64_t version = source.tile_version(t);
        if (had && contour_versions_[old] == version) return;
        TileSurface s;
        s.id = t;
        s.version = version;
        s.source_version = version;
        read.rebuilt.push_back(std::move(s));
    };
    // The tiles that may have changed since the last refresh, when the source can say; else every tile. A tile not
    // among them keeps its entry.
    const std::size_t count = source.tile_count();
    std::vector<std::uint64_t> maybe;
    if (changed_since_last(source, maybe)) {
        for (const std::uint64_t t : maybe)
            if (t < count) visit(t);
    } else {
        for (std::size_t t = 0; t < count; ++t) visit(t);
        for (std::size_t k = old; k < tiles_.size(); ++k)  // past the source's last tile
            if (tiles_[k].id >= count) read.gone.push_back(k);
    }
    return read;
}

std::vector<std::size_t> TileSurfaceCache::place_read_tiles(TileRead&& read, bool pending) {
    std::vector<TileSurface>& rebuilt = read.rebuilt;
    std::vector<std::size_t> fresh;  // where the rebuilt tiles are now in tiles_
    fresh.reserve(rebuilt.size());
    // No tile gone and none new: each rebuilt tile takes its predecessor's place, and the others stay where they are.
    bool in_place = read.gone.empty();
    for (std::size_t r = 0; r < rebuilt.size() && in_place; ++r) {
        fresh.push_back(index_of(tiles_, rebuilt[r].id));
        in_place = fresh.back() < tiles_.size();
    }
    if (in_place) {
        for (std::size_t r = 0; r < rebuilt.size(); ++r) {
            contour_versions_[fresh[r]] = rebuilt[r].version;
            pending_[fresh[r]] = pending;
            tiles_[fresh[r]] = std::move(rebuilt[r]);
        }
        return fresh;
    }
    fresh.clear();
    std::vector<TileSurface> next;
    std::vector<std::uint64_t> next_versions;
    std::vector<bool> next_pending;
    next.reserve(tiles_.size() + rebuilt.size());
    next_versions.reserve(tiles_.size() + rebuilt.size());
    next_pending.reserve(tiles_.size() + rebuilt.size());
    fresh.reserve(rebuilt.size());
    std::size_t r = 0, g = 0;  // both ascending: rebuilt by id, gone by index
    for (std::size_t k = 0; k <= tiles_.size(); ++k) {
        const std::uint64_t id = k < tiles_.size() ? tiles_[k].id : ~std::uint64_t{0};
        bool replaced = false;
        for (; r < rebuilt.size() && rebuilt[r].id <= id; ++r) {
            replaced = replaced || rebuilt[r].id == id;
            fresh.push_back(next.size());
            next_versions.push_back(rebuilt[r].version);
            next_pending.push_back(pending);
            next.push_back(std::move(rebuilt[r]));
        }
        if (k == tiles_.size()) break;
        while (g < read.gone.size() && read.gone[g] < k) ++g;
        if (replaced || (g < read.gone.size() && read.gone[g] == k)) continue;
        next_versions.push_back(contour_versions_[k]);
        next_pending.push_back(pending_[k]);
        next.push_back(std::move(tiles_[k]));
    }
    tiles_ = std::move(next);
    contour_versions_ = std::move(next_versions);
    pending_ = std::move(next_pending);
    return fresh;
}

std::size_t TileSurfaceCache::refresh(const TileMeshSource& contourer) {
    // First build the changed tiles aside, so an exception leaves the cache as it was.
    const std::uint64_t mark = fresh_tile_version();
    TileRead read = read_tile_changes(contourer);
    std::vector<TileSurface>& rebuilt = read.rebuilt;
    const std::size_t visited = read.visited;
    // The changed tiles' meshes on the task pool (a source's tile_mesh only reads); a throw leaves the cache as it was.
    pool_for(rebuilt.size(), 8, [&](const Chunk& chunk) {
        for (std::size_t i = chunk.first; i < chunk.last; ++i) {
            TileSurface& s = rebuilt[i];
            s.mesh = contourer.tile_mesh(s.id, s.materials, s.normals);
            if (!worker_) order_for_vertex_cache(s.mesh);  // else the worker orders it with its levels (collect_lods)
            s.bounds_m = s.mesh.bounds();
        }
    });
    const bool build_now = lod_ && !defer_ && !worker_;
    if (build_now) {
        std::vector<TileSurface*> all;
        for (TileSurface& s : rebuilt) all.push_back(&s);
        build_lods(all);
    }
    // Tiles rebuilt or gone: the groups over them lose their levels.
    // Tiles that arrive in a coarse-first start-up (arrive()) are not changes: no group level is dropped for them.
    std::vector<std::uint64_t> changed = std::move(stroke_changes_);  // hidden by their source meanwhile
    stroke_changes_.clear();
    const bool stroke_hidden = !changed.empty();
    for (const TileSurface& s : rebuilt)
        if (!arrived_.count(s.id)) changed.push_back(s.id);
    for (const std::size_t k : read.gone) changed.push_back(tiles_[k].id);
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
    const std::size_t rebuilt_count = rebuilt.size();
    const std::vector<std::size_t> fresh = place_read_tiles(std::move(read), lod_ && !build_now);
    // Only now that tiles_ holds what was read: a throw before leaves the mark too as it was.
    change_mark_ = mark;
    change_view_ = contourer.change_view();
    last_visited_ = visited;
    if (coarse_ && refreshed_ && !changed.empty()) {  // the coarse models re-read these once they settle
        merge_ids(coarse_changed_, changed);
        coarse_changed_at_ = std::chrono::steady_clock::now();
    }
    std::vector<std::uint64_t> touched = std::move(expected_left_);  // tiles whose groups' children or bounds moved
    expected_left_.clear();
    touched.insert(touched.end(), changed.begin(), changed.end());
    for (const std::size_t i : fresh) touched.push_back(tiles_[i].id);
    update_groups(contourer.tile_dims(), changed, touched);
    if (coarse_ && refreshed_) rebuild_coarsest_now(contourer.tile_dims(), changed, stroke_hidden);
    if (coarse_ && !refreshed_) {  // start-up: the coarser groups' levels now, the finest by collect_lods()
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::uint64_t> ids;
        for (const TileGroupSurface& g : groups_)
            if (g.depth >= coarse_->min_depth() && coarse_->has_depth(g.depth) &&
                (g.depth >= kCoarseStartupDepth || g.depth == coarse_->max_depth()))
                ids.push_back(g.id);
        rebuild_coarse_levels(ids);
        lod_build_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    if (lod_ && worker_) {
        if (!refreshed_) {  // start-up's levels: everything waiting now
            for (std::size_t i = 0; i < tiles_.size(); ++i)
                if (pending_[i]) startup_waiting_.insert(lod_key(false, tiles_[i].id));
            for (std::size_t g = 0; g < groups_.size(); ++g)
                if (group_pending_[g]) startup_waiting_.insert(lod_key(true, groups_[g].id));
        } else {  // changed tiles are a stroke's now (their groups: update_groups); arrived ones start-up's
            for (const std::uint64_t id : changed) startup_waiting_.erase(lod_key(false, id));
            for (const std::size_t i : fresh)
                if (startup_arrival(tiles_[i].id)) startup_waiting_.insert(lod_key(false, tiles_[i].id));
        }
        queue_tile_lods(fresh);
        if (startup_expected() == 0 && !deferred_.empty()) queue_deferred_tiles();
        queue_ready_groups();
    }
    refreshed_ = true;
    arrived_.clear();
    stroke_arrived_.clear();
    // A stroke's step (tiles hidden meanwhile) sets only the cover: its samples wait for this refresh.
    if (startup_groups_) update_startup_groups(!stroke_hidden);
    if (build_now) {  // every group, finest depth first (a group is built from its children's levels)
        const auto t0 = std::chrono::steady_clock::now();
        for (int d = 1; d <= lod_options_.group_depth; ++d) {
            std::vector<std::size_t> at_depth;
            for (std::size_t g = 0; g < groups_.size(); ++g)
                if (group_pending_[g] && groups_[g].depth == d) at_depth.push_back(g);
            build_group_lods(at_depth);
        }
        lod_build_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    return rebuilt_count;
}

bool TileSurfaceCache::changed_since_last(const TileMeshSource& source, std::vector<std::uint64_t>& tiles) const {
    const std::uint64_t view = source.change_view();
    if (!refreshed_ || view == 0 || view != change_view_ || !source.changed_since(change_mark_, tiles)) return false;
    std::sort(tiles.begin(), tiles.end());
    tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
    return true;
}

void TileSurfaceCache::enable_lod(const TileLodOptions& options) {
    if (!std::isfinite(options.cell_m) || !(options.cell_m > 0.0))
        throw Error("TileSurfaceCache::enable_lod: cell_m must be finite and > 0, got " + std::to_string(options.cell_m));
    lod_options_ = options;
    lod_ = true;
}

std::size_t TileSurfaceCache::lod_pending() const {
    return static_cast<std::size_t>(std::count(pending_.begin(), pending_.end(), true) +
                                    std::count(group_pending_.begin(), group_pending_.end(), true));
}

std::size_t TileSurfaceCache::build_pending_lods(std::size_t max_tiles) {
    if (worker_) return 0;  // the worker builds them (collect_lods)
    std::vector<TileSurface*> batch;
    std::vector<std::size_t> at;
    for (std::size_t i = 0; i < tiles_.size() && batch.size() < max_tiles; ++i)
        if (pending_[i]) {
            batch.push_back(&tiles_[i]);
            at.push_back(i);
        }
    if (batch.empty()) {  // no tile waits: one group whose children are built
        for (std::size_t g = 0; g < groups_.size(); ++g)
            if (group_pending_[g] && group_ready(g)) {
                const auto t0 = std::chrono::steady_clock::now();
                build_group_lods({g});
                lod_build_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
                return 1;
            }
        return 0;
    }
    build_lods(batch);
    for (std::size_t k = 0; k < batch.size(); ++k) {
        batch[k]->version = fresh_tile_version();
        pending_[at[k]] = false;
    }
    return batch.size();
}

void TileSurfaceCache::build_lods(const std::vector<TileSurface*>& tiles) {
    const auto t0 = std::chrono::steady_clock::now();
    // Built aside first, so that an exception leaves every tile as it was.
    std::vector<std::vector<TileLodLevel>> built(tiles.size());
    if (tile_levels())
        run_lod_jobs(tiles.size(), [&](std::size_t i) {
            built[i] = build_lod_levels(tiles[i]->mesh, tiles[i]->materials, tiles[i]->normals, 0.0, lod_options_);
        });
    for (std::size_t i = 0; i < tiles.size(); ++i) {
        tiles[i]->lods = std::move(built[i]);
        tiles[i]->lods_built = true;
    }
    lod_tiles_built_ += tiles.size();
    lod_build_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void TileSurfaceCache::run_lod_jobs(std::size_t count, const std::function<void(std::size_t)>& job) {
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    if (count < kParallelLodTiles || cores == 1) {
        for (std::size_t i = 0; i < count; ++i) job(i);
        return;
    }
    // Jobs handed out one at a time from a shared counter; the calling thread works too.
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::atomic<bool> failed{false};
    const auto work = [&] {
        for (std::size_t i; !failed.load() && (i = next.fetch_add(1)) < count;) {
            try {
                job(i);
            } catch (...) {
                if (!failed.exchange(true)) failure = std::current_exception();
            }
        }
    };
    std::vector<std::thread> threads;
    for (unsigned c = 1; c < cores; ++c) threads.emplace_back(work);
    work();
    for (std::thread& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
}

std::size_t TileSurfaceCache::triangle_count() const {
    std::size_t n = 0;
    for (const TileSurface& s : tiles_) n += s.mesh.triangles.size();
    return n;
}

}  // namespace tridex::compute
