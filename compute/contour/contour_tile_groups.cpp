// compute/contour/contour_tile_groups.cpp - TileSurfaceCache's groups of tiles: which exist, which changed, and
// building their levels of detail.
#include <algorithm>
#include <map>
#include <unordered_set>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/sorted_ids.hpp"
#include "compute/contour/tile_group_box.hpp"
#include "compute/contour/tile_group_lod.hpp"

namespace tridex::compute {
namespace {

struct GroupGrid {
    std::array<int, 3> tiles{};

    std::array<int, 3> dims(int depth) const { return group_grid_dims(tiles, depth); }
    std::array<int, 3> tile_coords(std::uint64_t tile) const { return grid_coords(tile, tiles); }
    std::uint64_t group_id(int depth, const std::array<int, 3>& g) const { return tile_group_id(depth, grid_index(g, dims(depth))); }
    std::uint64_t group_of(const std::array<int, 3>& t, int depth) const {
        return tile_group_id(depth, group_index_of(t, tiles, depth));
    }
    std::array<int, 3> group_coords(std::uint64_t id, int depth) const { return grid_coords(tile_group_index(id), dims(depth)); }
};

}  // namespace

std::vector<TileGroupSurface> TileSurfaceCache::all_groups(const std::array<int, 3>& dims, int depth_max) const {
    const GroupGrid grid{dims};
    std::map<std::uint64_t, TileGroupSurface> next;
    const auto add = [&](std::uint64_t tile_id, const Aabb& bounds_m) {
        const std::array<int, 3> tc = grid.tile_coords(tile_id);
        std::uint64_t child = tile_id;
        for (int d = 1; d <= depth_max; ++d) {
            const std::uint64_t id = grid.group_of(tc, d);
            TileGroupSurface& g = next[id];
            if (g.children.empty()) {
                g.id = id;
                g.depth = d;
                for (int a = 0; a < 3; ++a) g.coords[a] = tc[a] >> d;
                g.parent = d < depth_max ? grid.group_of(tc, d + 1) : TileGroupSurface::kNone;
            }
            if (std::find(g.children.begin(), g.children.end(), child) == g.children.end()) g.children.push_back(child);
            g.bounds_m.add(bounds_m.lo);
            g.bounds_m.add(bounds_m.hi);
            child = id;
        }
    };
    for (const TileSurface& tile : tiles_) add(tile.id, tile.bounds_m);
    for (const std::uint64_t id : expected_) add(id, expected_tile_box(id, dims));  // coarse-first start-up
    std::vector<TileGroupSurface> groups;
    groups.reserve(next.size());
    for (auto& [id, g] : next) {
        std::sort(g.children.begin(), g.children.end());
        groups.push_back(std::move(g));
    }
    return groups;
}

std::vector<TileGroupSurface> TileSurfaceCache::regrouped(const std::array<int, 3>& dims, int depth_max,
                                                         const std::vector<std::uint64_t>& ids) const {
    const GroupGrid grid{dims};
    std::vector<TileGroupSurface> next;
    std::size_t finer_begin = 0, finer_end = 0;  // next's groups one depth down
    auto finer_ids_begin = ids.begin();
    for (int d = 1; d <= depth_max; ++d) {
        const auto ids_begin = std::lower_bound(ids.begin(), ids.end(), tile_group_id(d, 0));
        const auto ids_end = std::lower_bound(ids.begin(), ids.end(), tile_group_id(d + 1, 0));
        const std::array<int, 3> below = d == 1 ? dims : grid.dims(d - 1);
        const std::size_t depth_begin = next.size();
        for (auto it = ids_begin; it != ids_end; ++it) {
            TileGroupSurface g;
            g.id = *it;
            g.depth = d;
            g.coords = grid.group_coords(g.id, d);
            g.parent = d < depth_max ? grid.group_id(d + 1, {g.coords[0] >> 1, g.coords[1] >> 1, g.coords[2] >> 1})
                                     : TileGroupSurface::kNone;
            const auto add = [&](std::uint64_t child, const Aabb& b) {
                if (g.children.empty() || g.children.back() != child) g.children.push_back(child);
                g.bounds_m.add(b.lo);
                g.bounds_m.add(b.hi);
            };
            std::array<int, 3> c{};  // z outermost: children come in ascending id
            for (c[2] = 2 * g.coords[2]; c[2] <= 2 * g.coords[2] + 1 && c[2] < below[2]; ++c[2])
                for (c[1] = 2 * g.coords[1]; c[1] <= 2 * g.coords[1] + 1 && c[1] < below[1]; ++c[1])
                    for (c[0] = 2 * g.coords[0]; c[0] <= 2 * g.coords[0] + 1 && c[0] < below[0]; ++c[0]) {
                        if (d == 1) {
                            const std::uint64_t t = grid_index(c, dims);
                            if (const TileSurface* tile = find_by_id(tiles_, t)) add(t, tile->bounds_m);
                            if (expected_.count(t) != 0) add(t, expected_tile_box(t, dims));
                            continue;
                        }
                        const std::uint64_t child = grid.group_id(d - 1, c);
                        const TileGroupSurface* from = nullptr;  // a regrouped child as it is now, else as it was
                        if (std::binary_search(finer_ids_begin, ids_begin, child)) {
                            const auto f = std::lower_bound(next.begin() + static_cast<std::ptrdiff_t>(finer_begin),
                                                            next.begin() + static_cast<std::ptrdiff_t>(finer_end), child,
                                                            [](const TileGroupSurface& x, std::uint64_t v) { return x.id < v; });
                            if (f != next.begin() + static_cast<std::ptrdiff_t>(finer_end) && f->id == child) from = &*f;
                        } else {
                            from = find_by_id(groups_, child);
                        }
                        if (from) add(child, from->bounds_m);
                    }
            if (!g.children.empty()) next.push_back(std::move(g));
        }
        finer_begin = depth_begin;
        finer_end = next.size();
        finer_ids_begin = ids_begin;
    }
    return next;
}

void TileSurfaceCache::update_groups(const std::array<int, 3>& dims, const std::vector<std::uint64_t>& changed_tiles,
                                     const std::vector<std::uint64_t>& touched_tiles) {
    const int depth_max = lod_ ? lod_options_.group_depth : 0;
    if (depth_max <= 0) {
        groups_.clear();
        group_pending_.clear();
        group_queued_.clear();
        group_changed_at_.clear();
        groups_depth_ = 0;
        return;
    }
    const GroupGrid grid{dims};
    // Every group again at the first refresh or when the grid changed; else only those over a touched tile or stale.
    const bool whole = !refreshed_ || groups_depth_ != depth_max || coarse_dims_ != dims;
    coarse_dims_ = dims;
    groups_depth_ = depth_max;
    std::unordered_set<std::uint64_t> stale;
    if (coarse_) stale = coarse_reach(dims, changed_tiles);
    for (const std::uint64_t t : changed_tiles)  // simplified groups: those holding a changed tile
        for (int d = 1; d <= depth_max && (!coarse_ || d < coarse_->min_depth()); ++d)
            stale.insert(grid.group_of(grid.tile_coords(t), d));
    std::vector<std::uint64_t> ids;  // regrouped: sorted, so by depth first
    std::vector<TileGroupSurface> next;
    if (whole) {
        next = all_groups(dims, depth_max);
    } else {
        for (const std::uint64_t t : touched_tiles)
            for (int d = 1; d <= depth_max; ++d) ids.push_back(grid.group_of(grid.tile_coords(t), d));
        for (const std::uint64_t id : stale)
            if (tile_group_depth(id) >= 1 && tile_group_depth(id) <= depth_max) ids.push_back(id);
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
        next = regrouped(dims, depth_max, ids);
    }
    // Start-up's groups are never held back (Clock's epoch); a later change starts the group's settling time.
    const auto now = refreshed_ ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
    struct Kept {  // what a group's entry in group_pending_, group_queued_ and group_changed_at_ becomes
        bool pending = false, queued = false;
        std::chrono::steady_clock::time_point changed_at;
    };
    const auto kept_state = [&](std::size_t at) {
        return Kept{group_pending_[at], at < group_queued_.size() && group_queued_[at],
                    at < group_changed_at_.size() ? group_changed_at_[at] : now};
    };
    // Whether the groups `ids` that exist now are exactly those regrouped (`next`, the same order).
    const auto same_group_ids = [&]() {
        std::size_t n = 0;
        for (const std::uint64_t id : ids) {
            const bool in_next = n < next.size() && next[n].id == id;
            if (in_next) ++n;
            if (in_next != (index_of(groups_, id) < groups_.size())) return false;
        }
        return n == next.size();
    };
    // A regrouped group keeps its levels when it is not stale and has the same children; else they are dropped.
    const auto settle = [&](TileGroupSurface& g, std::size_t old) -> Kept {
        if (old < groups_.size() && !stale.count(g.id) && groups_[old].children == g.children) {
            g.version = groups_[old].version;
            g.lods = std::move(groups_[old].lods);
            g.children_cover = groups_[old].children_cover;
            g.levels_waiting = groups_[old].levels_waiting;
            return kept_state(old);
        }
        // A coarse-first start-up's level rebuilt before its tiles are in keeps its predecessor's error at least.
        if (old < groups_.size() && !groups_[old].lods.empty() && provisional_.count(g.id) != 0)
            dropped_error_[g.id] = groups_[old].lods.front().error_m;
        g.version = fresh_tile_version();
        g.levels_waiting = true;
        Kept k{false, false, now};
        if (coarse_ && g.depth >= coarse_->min_depth()) {  // a coarse level at start-up, or once settled
            coarse_stale_.insert(g.id);  // start-up's are built at once (refresh), a stroke's once settled
        } else {
            if (refreshed_) startup_waiting_.erase(lod_key(true, g.id));  // changed after start-up: a stroke's
            k.pending = true;
        }
        return k;
    };
    if (!whole && same_group_ids()) {  // no group appears or goes: update the regrouped ones where they are
        group_queued_.resize(groups_.size(), false);
        group_changed_at_.resize(groups_.size(), now);
        for (TileGroupSurface& g : next) {
            const std::size_t o = index_of(groups_, g.id);
            const Kept k = settle(g, o);
            groups_[o] = std::move(g);
            group_pending_[o] = k.pending;
            group_queued_[o] = k.queued;
            group_changed_at_[o] = k.changed_at;
        }
        return;
    }
    std::vector<TileGroupSurface> groups;
    std::vector<bool> pending, queued;
    std::vector<std::chrono::steady_clock::time_point> changed_at;
    groups.reserve(std::max(next.size(), groups_.size()));
    const auto push = [&](TileGroupSurface&& g, const Kept& k) {
        pending.push_back(k.pending);
        queued.push_back(k.queued);
        changed_at.push_back(k.changed_at);
        groups.push_back(std::move(g));
    };
    std::size_t o = 0, n = 0;  // both sorted by id: merge them
    while (o < groups_.size() || n < next.size()) {
        const std::uint64_t old_id = o < groups_.size() ? groups_[o].id : TileGroupSurface::kNone;
        const std::uint64_t next_id = n < next.size() ? next[n].id : TileGroupSurface::kNone;
        if (next_id <= old_id) {
            const std::size_t at = next_id == old_id ? o++ : groups_.size();
            const Kept k = settle(next[n], at);
            push(std::move(next[n++]), k);
        } else {  // an old group not regrouped: unchanged, unless every group was regrouped (then it is gone)
            if (!whole && !std::binary_search(ids.begin(), ids.end(), old_id))
                push(std::move(groups_[o]), kept_state(o));
            ++o;
        }
    }
    groups_ = std::move(groups);
    group_pending_ = std::move(pending);
    group_queued_ = std::move(queued);
    group_changed_at_ = std::move(changed_at);
}

bool TileSurfaceCache::group_ready(std::size_t g) const {
    const TileGroupSurface& group = groups_[g];
    for (const std::uint64_t c : group.children) {
        if (group.depth == 1) {
            const auto it = std::lower_bound(tiles_.begin(), tiles_.end(), c,
                                             [](const TileSurface& x, std::uint64_t v) { return x.id < v; });
            if (it != tiles_.end() && it->id == c && pending_[static_cast<std::size_t>(it - tiles_.begin())]) return false;
        } else {
            const auto it = std::lower_bound(groups_.begin(), groups_.end(), c,
                                             [](const TileGroupSurface& x, std::uint64_t v) { return x.id < v; });
            if (it != groups_.end() && it->id == c && group_pending_[static_cast<std::size_t>(it - groups_.begin())])
                return false;
        }
    }
    return true;
}

namespace {

// The coarsest of `levels` whose error is at most limit_m, or nullptr.
const TileLodLevel* level_within(const std::vector<TileLodLevel>& levels, double limit_m) {
    const TileLodLevel* best = nullptr;
    for (const TileLodLevel& l : levels)
        if (l.error_m <= limit_m) best = &l;
    return best;
}

}  // namespace

void TileSurfaceCache::gather_group_parts(const TileGroupSurface& root, std::vector<LodPart>& parts) const {
    // Per child: its coarsest level within the depth's part error (TileLodOptions::group_part_cells), else its
    // full surface (a tile's mesh; a group's own children, recursively). A level keeps its tile's or group's
    // outer border at full resolution, so the pieces weld along the borders they share.
    const double limit_m = lod_options_.group_part_cells * static_cast<double>(1 << (root.depth - 1)) * lod_options_.cell_m;
    std::vector<const TileGroupSurface*> todo{&root};
    while (!todo.empty()) {
        const TileGroupSurface& g = *todo.back();
        todo.pop_back();
        for (const std::uint64_t c : g.children) {
            if (g.depth == 1) {
                const TileSurface* t = find_by_id(tiles_, c);
                if (!t) continue;
                if (const TileLodLevel* l = level_within(t->lods, limit_m))
                    parts.push_back(LodPart{&l->mesh, l->materials, l->normals, l->error_m});
                else
                    parts.push_back(LodPart{&t->mesh, t->materials, t->normals, 0.0});
            } else if (const TileGroupSurface* child = find_by_id(groups_, c)) {
                if (const TileLodLevel* l = level_within(child->lods, limit_m))
                    parts.push_back(LodPart{&l->mesh, l->materials, l->normals, l->error_m});
                else
                    todo.push_back(child);
            }
        }
    }
}

void TileSurfaceCache::build_group_lods(const std::vector<std::size_t>& which) {
    std::vector<std::vector<TileLodLevel>> built(which.size());
    run_lod_jobs(which.size(), [&](std::size_t i) {
        std::vector<LodPart> parts;
        gather_group_parts(groups_[which[i]], parts);
        built[i] = build_group_lod(parts, lod_options_);
    });
    for (std::size_t i = 0; i < which.size(); ++i) {
        TileGroupSurface& g = groups_[which[i]];
        g.lods = std::move(built[i]);
        g.version = fresh_tile_version();
        g.levels_waiting = false;
        group_pending_[which[i]] = false;
    }
    lod_groups_built_ += which.size();
}

}  // namespace tridex::compute
