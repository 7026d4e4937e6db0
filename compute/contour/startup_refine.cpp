// compute/contour/startup_refine.cpp - start-up's full-resolution contour, one region of tiles at a time.
#include "compute/contour/startup_refine.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "compute/contour/deferred_contour.hpp"
#include "compute/contour/tile_group_box.hpp"
#include "core/error.hpp"

namespace tridex::compute {

StartupRefiner::StartupRefiner(TriDexel& model, int region_depth, const Vec3& near_m)
    : dims_(model.tiles.tiles), depth_(region_depth) {
    if (region_depth < 1 || region_depth > 6)
        throw Error("StartupRefiner: region depth " + std::to_string(region_depth) + " is not in 1..6");
    const std::size_t n = model.tiles.count();
    pending_.assign(n, 0);
    near_pending_.assign(n, 0);
    reported_.assign(n, 0);
    changes_ = TileChangeLog(TileChangeLog::entries_for(n));
    for (int a = 0; a < 3; ++a) region_dims_[a] = (dims_[a] + (1 << depth_) - 1) >> depth_;
    std::vector<std::uint8_t> has_pending(
        static_cast<std::size_t>(region_dims_[0]) * region_dims_[1] * region_dims_[2], 0);
    const std::vector<std::uint8_t> near = near_surface(model);
    for (std::size_t t = 0; t < n; ++t) {
        if (!model.tiles.dirty[t] || !near[t]) continue;
        pending_[t] = 1;
        ++pending_count_;
        const std::array<int, 3> c = coords(t);
        for_neighbourhood(c, [&](std::size_t k) { ++near_pending_[k]; });
        has_pending[static_cast<std::size_t>(c[0] >> depth_) +
                    static_cast<std::size_t>(region_dims_[0]) *
                        (static_cast<std::size_t>(c[1] >> depth_) + static_cast<std::size_t>(region_dims_[1]) * (c[2] >> depth_))] = 1;
    }
    model.clear_dirty();
    // Regions nearest near_m first (their centres, in cells; ties by index, so the order is deterministic).
    const Vec3 g = model.lattice.to_grid(near_m);
    const double span = static_cast<double>(TileGrid::kTileCells << depth_);
    std::vector<std::pair<double, std::size_t>> by_distance;
    for (std::size_t r = 0; r < has_pending.size(); ++r) {
        if (!has_pending[r]) continue;
        const auto rx = static_cast<int>(r % static_cast<std::size_t>(region_dims_[0]));
        const auto ry = static_cast<int>(r / static_cast<std::size_t>(region_dims_[0]) % static_cast<std::size_t>(region_dims_[1]));
        const auto rz = static_cast<int>(r / (static_cast<std::size_t>(region_dims_[0]) * static_cast<std::size_t>(region_dims_[1])));
        const Vec3 centre((rx + 0.5) * span, (ry + 0.5) * span, (rz + 0.5) * span);
        const Vec3 d = centre - g;
        by_distance.emplace_back(d.x * d.x + d.y * d.y + d.z * d.z, r);
    }
    std::sort(by_distance.begin(), by_distance.end());
    for (const auto& [d2, r] : by_distance) order_.push_back(r);
    // Tiles with no pending tile around them are publishable from the start (nothing to contour there).
    for (std::size_t t = 0; t < n; ++t) reported_[t] = near_pending_[t] == 0;
}

std::vector<std::uint8_t> StartupRefiner::near_surface(const TriDexel& model) const {
    // A tile without an interval end in it has the same occupancy at every node (a change between two rays would
    // put an interval end of the ray between them in the tile): no surface. One pass over the rays marks the tiles
    // holding an end; the neighbours of those count too (ends on a tile's border, cells reaching one node out).
    constexpr int kT = TileGrid::kTileCells;
    const std::size_t n = model.tiles.count();
    std::vector<std::uint8_t> ends(n, 0), near(n, 0);
    const auto tile_at = [&](int axis, double t) {
        return std::clamp(static_cast<int>(std::floor(t / kT)), 0, dims_[axis] - 1);
    };
    for (int a = 0; a < 3; ++a) {
        const RaySet& s = model.sets[a];
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        std::array<int, 3> tc{};
        for (int v = 0; v < s.nv; ++v) {
            tc[c] = tile_at(c, v);
            for (int u = 0; u < s.nu; ++u) {
                tc[b] = tile_at(b, u);
                for (const Interval& iv : s.ray(u, v))
                    for (const float t : {iv.enter, iv.exit}) {
                        tc[a] = tile_at(a, t);
                        ends[index(tc[0], tc[1], tc[2])] = 1;
                    }
            }
        }
    }
    for (std::size_t t = 0; t < n; ++t) {
        if (!ends[t]) continue;
        const std::array<int, 3> c = coords(t);
        for (int z = std::max(0, c[2] - 1); z <= std::min(dims_[2] - 1, c[2] + 1); ++z)
            for (int y = std::max(0, c[1] - 1); y <= std::min(dims_[1] - 1, c[1] + 1); ++y)
                for (int x = std::max(0, c[0] - 1); x <= std::min(dims_[0] - 1, c[0] + 1); ++x) near[index(x, y, z)] = 1;
    }
    return near;
}

std::array<int, 3> StartupRefiner::coords(std::size_t t) const {
    const auto nx = static_cast<std::size_t>(dims_[0]), ny = static_cast<std::size_t>(dims_[1]);
    return {static_cast<int>(t % nx), static_cast<int>(t / nx % ny), static_cast<int>(t / (nx * ny))};
}

std::size_t StartupRefiner::index(int x, int y, int z) const {
    return static_cast<std::size_t>(x) +
           static_cast<std::size_t>(dims_[0]) * (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims_[1]) * static_cast<std::size_t>(z));
}

std::vector<std::uint64_t> StartupRefiner::pending_tiles() const {
    std::vector<std::uint64_t> out;
    out.reserve(pending_count_);
    for (std::size_t t = 0; t < pending_.size(); ++t)
        if (pending_[t]) out.push_back(t);
    return out;
}

void StartupRefiner::contoured(std::size_t t) {
    pending_[t] = 0;
    --pending_count_;
    const std::uint64_t stamp = fresh_tile_version();
    for_neighbourhood(coords(t), [&](std::size_t n) {
        if (near_pending_[n] == 1) changes_.add(stamp, n);  // publishable from now on (recorded first)
        if (--near_pending_[n] != 0) return;
        if (!reported_[n]) {
            reported_[n] = 1;
            fresh_.push_back(n);
        }
    });
}

std::vector<std::uint64_t> StartupRefiner::take_newly_publishable() {
    std::vector<std::uint64_t> out = std::move(fresh_);
    fresh_.clear();
    std::sort(out.begin(), out.end());
    return out;
}

std::size_t StartupRefiner::mark_region(TriDexel& model, std::size_t region) {
    const auto rx = static_cast<int>(region % static_cast<std::size_t>(region_dims_[0]));
    const auto ry = static_cast<int>(region / static_cast<std::size_t>(region_dims_[0]) % static_cast<std::size_t>(region_dims_[1]));
    const auto rz = static_cast<int>(region / (static_cast<std::size_t>(region_dims_[0]) * static_cast<std::size_t>(region_dims_[1])));
    const int span = 1 << depth_;
    return mark_box(model, {rx * span - 1, ry * span - 1, rz * span - 1}, {(rx + 1) * span, (ry + 1) * span, (rz + 1) * span});
}

std::size_t StartupRefiner::mark_box(TriDexel& model, std::array<int, 3> lo, std::array<int, 3> hi) {
    std::size_t marked = 0;
    for (int z = std::max(0, lo[2]); z <= std::min(dims_[2] - 1, hi[2]); ++z)
        for (int y = std::max(0, lo[1]); y <= std::min(dims_[1] - 1, hi[1]); ++y)
            for (int x = std::max(0, lo[0]); x <= std::min(dims_[0] - 1, hi[0]); ++x) {
                const std::size_t t = index(x, y, z);
                if (!pending_[t]) continue;
                if (!model.tiles.dirty[t]) model.tiles.dirty[t] = TileGrid::kWhole;
                contoured(t);
                ++marked;
            }
    return marked;
}

void StartupRefiner::contour(TriDexel& model, Contourer& contourer) {
    if (beside_) beside_->take_dirty(model);  // the deferred tiles beside these go with them, once
    contourer.update(model);
}

std::size_t StartupRefiner::refine_next(TriDexel& model, Contourer& contourer) {
    while (next_ < order_.size()) {
        const std::size_t marked = mark_region(model, order_[next_++]);
        if (marked == 0) continue;  // a change refined it already
        contour(model, contourer);
        return marked;
    }
    return 0;
}

std::size_t StartupRefiner::refine_group(TriDexel& model, Contourer& contourer, int depth, const std::array<int, 3>& coords) {
    std::array<int, 3> lo{}, hi{};
    if (!group_tiles_grown(dims_, depth, coords, lo, hi)) return 0;
    const std::size_t marked = mark_box(model, lo, hi);
    if (marked > 0) contour(model, contourer);
    return marked;
}

std::vector<std::uint64_t> StartupRefiner::pending_among(const std::vector<std::uint64_t>& tiles) const {
    std::vector<std::uint64_t> out;
    for (const std::uint64_t t : tiles)
        if (t < pending_.size() && pending_[t]) out.push_back(t);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

std::size_t StartupRefiner::contour_with_change(TriDexel& model, const std::vector<std::uint64_t>& tiles) {
    // A change drops the levels of the depth-1 groups it reaches (TileSurfaceCache::coarse_reach: kDirtyReachCells
    // fine cells, then kDirtyReachCells + 1 coarse cells of stride 2, short of one tile), so those groups lie among
    // the groups of the changed tiles' 26 neighbours. Each such group's tiles, grown by one, are contoured: its tiles
    // are then publishable and the group is covered by them, so the changed surface is drawn at full resolution,
    // never from a coarser level that must stand in whatever its error.
    static_assert(TriDexel::kDirtyReachCells + 2 * (TriDexel::kDirtyReachCells + 1) < TileGrid::kTileCells,
                  "a change reaches past the depth-1 groups of its tiles' neighbours");
    std::vector<std::uint64_t> groups;  // depth-1 group coordinates packed as tile indices of the even corner tile
    for (const std::uint64_t t : tiles) {
        if (t >= pending_.size()) continue;
        for_neighbourhood(coords(t), [&](std::size_t n) {
            const std::array<int, 3> c = coords(n);
            groups.push_back(index(c[0] & ~1, c[1] & ~1, c[2] & ~1));
        });
    }
    std::sort(groups.begin(), groups.end());
    groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
    std::size_t marked = 0;
    for (const std::uint64_t g : groups) {
        const std::array<int, 3> c = coords(g);
        marked += mark_box(model, {c[0] - 1, c[1] - 1, c[2] - 1}, {c[0] + 2, c[1] + 2, c[2] + 2});
    }
    return marked;
}

std::size_t StartupRefiner::finish(TriDexel& model, Contourer& contourer) {
    std::size_t marked = 0;
    for (std::size_t t = 0; t < pending_.size(); ++t)
        if (pending_[t]) {
            if (!model.tiles.dirty[t]) model.tiles.dirty[t] = TileGrid::kWhole;
            contoured(t);
            ++marked;
        }
    next_ = order_.size();
    if (marked > 0) contour(model, contourer);
    return marked;
}

}  // namespace tridex::compute
