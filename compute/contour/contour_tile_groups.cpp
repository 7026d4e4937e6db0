// compute/contour/contour_tile_groups.cpp - TileSurfaceCache's groups of tiles: which exist, which changed, and
// building their levels of detail.
#include <algorithm>
#include <map>
#include <unordered_set>

#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/sorted_ids.hpp"
#include "compute/contour/tile_group_lod.hpp"

namespace tridex::compute {
namespace {

struct GroupGrid {
    std::array<int, 3> tiles{};

    std::array<int, 3> dims(int depth) const {
        std::array<int, 3> g{};
        for (int a = 0; a < 3; ++a) g[a] = (tiles[a] + (1 << depth) - 1) >> depth;
        return g;
    }
    std::array<int, 3> tile_coords(std::uint64_t tile) const {
        const auto nx = static_cast<std::uint64_t>(tiles[0]), ny = static_cast<std::uint64_t>(tiles[1]);
        return {static_cast<int>(tile % nx), static_cast<int>((tile / nx) % ny), static_cast<int>(tile / (nx * ny))};
    }
    std::uint64_t group_of(const std::array<int, 3>& t, int depth) const {
        const std::array<int, 3> g = dims(depth);
        const auto x = static_cast<std::uint64_t>(t[0] >> depth), y = static_cast<std::uint64_t>(t[1] >> depth),
                   z = static_cast<std::uint64_t>(t[2] >> depth);
        return tile_group_id(depth, x + static_cast<std::uint64_t>(g[0]) * (y + static_cast<std::uint64_t>(g[1]) * z));
    }
};

}  // namespace

void TileSurfaceCache::update_groups(const std::array<int, 3>& dims, const std::vector<std::uint64_t>& changed_tiles) {
    const int depth_max = lod_ ? lod_options_.group_depth : 0;
    if (depth_max <= 0) {
        groups_.clear();
        group_pending_.clear();
        group_queued_.clear();
        group_changed_at_.clear();
        return;
    }
    const GroupGrid grid{dims};
    coarse_dims_ = dims;
    std::unordered_set<std::uint64_t> stale;
    if (coarse_) stale = coarse_reach(dims, changed_tiles);
    for (const std::uint64_t t : changed_tiles)  // simplified groups: those holding a changed tile
        for (int d = 1; d <= depth_max && (!coarse_ || d < coarse_->min_depth()); ++d)
            stale.insert(grid.group_of(grid.tile_coords(t), d));
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
    std::vector<bool> pending, queued;
    std::vector<std::chrono::steady_clock::time_point> changed_at;
    // Start-up's groups are never held back (Clock's epoch); a later change starts the group's settling time.
    const auto now = refreshed_ ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
    groups.reserve(next.size());
    for (auto& [id, g] : next) {
        std::sort(g.children.begin(), g.children.end());
        const auto old = std::lower_bound(groups_.begin(), groups_.end(), id,
                                          [](const TileGroupSurface& x, std::uint64_t v) { return x.id < v; });
        const bool found = old != groups_.end() && old->id == id;
        if (found && !stale.count(id) && old->children == g.children) {
            g.version = old->version;
            g.lods = std::move(old->lods);
            g.children_cover = old->children_cover;
            const auto at = static_cast<std::size_t>(old - groups_.begin());
            pending.push_back(group_pending_[at]);
            queued.push_back(at < group_queued_.size() && group_queued_[at]);
            changed_at.push_back(at < group_changed_at_.size() ? group_changed_at_[at] : now);
        } else if (coarse_ && g.depth >= coarse_->min_depth()) {  // a coarse level at start-up, or once settled
            g.version = fresh_tile_version();
            pending.push_back(false);
            queued.push_back(false);
            changed_at.push_back(now);
            coarse_stale_.insert(id);  // start-up's are built at once (refresh), a stroke's once settled
        } else {
            if (refreshed_) startup_waiting_.erase(lod_key(true, id));  // changed after start-up: a stroke's
            g.version = fresh_tile_version();
            pending.push_back(true);
            queued.push_back(false);
            changed_at.push_back(now);
        }
        groups.push_back(std::move(g));
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
                    parts.push_back(LodPart{&t->mesh, t->materials, {}, 0.0});
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
        group_pending_[which[i]] = false;
    }
    lod_groups_built_ += which.size();
}

}  // namespace tridex::compute
