// compute/tools/sweep_parallel.cpp - ray tiles of the batch's footprint shared out on the task pool.
#include "compute/tools/sweep_parallel.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "compute/parallel/task_pool.hpp"

namespace tridex::compute {
namespace {

constexpr int kTileRays = 8;  // ray tiles are kTileRays x kTileRays rays of one set

/// One ray tile of a set's footprint union: its set and tile coordinates, and its sweeps (in batch order)
/// as a range of the flat sweep-index list.
struct RayTile {
    int axis, tu, tv;
    std::size_t first, count;
};

/// A sweep's footprint on one ray set (node ranges, inclusive).
struct Footprint {
    bool any = false;
    int u_lo = 0, u_hi = -1, v_lo = 0, v_hi = -1;
};

}  // namespace

BooleanStats apply_sweeps_parallel(TriDexel& model, std::span<const Sweep> batch, int threads) {
    BooleanStats stats;
    const GridBatch converted = to_grid_batch(model.lattice, batch);  // throws before anything changes
    const std::vector<GridSweep>& grid = converted.sweeps;
    if (grid.empty()) return stats;

    // Per set: the tiles the sweeps' footprints cover, each listing its sweeps in batch order (a dense
    // per-set grid over the union's tile range collects them; sweeps are visited in order).
    std::vector<RayTile> tiles;
    std::vector<std::uint32_t> members;
    std::vector<Footprint> fp(grid.size() * 3);
    // Per sweep and set: its chords' constants, and per footprint row the rays it can reach (SweepShadow;
    // rows[row_first[s * 3 + a] + v - v_lo], empty as {1, 0}), filled on the pool.
    std::vector<std::size_t> row_first(grid.size() * 3, 0);
    std::size_t row_count = 0;
    for (std::size_t s = 0; s < grid.size(); ++s)
        for (int a = 0; a < 3; ++a) {
            Footprint& f = fp[s * 3 + static_cast<std::size_t>(a)];
            f.any = sweep_footprint(grid[s], model.sets[a], f.u_lo, f.u_hi, f.v_lo, f.v_hi);
            if (!f.any) continue;
            stats.rays_visited += static_cast<std::size_t>(f.u_hi - f.u_lo + 1) * static_cast<std::size_t>(f.v_hi - f.v_lo + 1);
            row_first[s * 3 + static_cast<std::size_t>(a)] = row_count;
            row_count += static_cast<std::size_t>(f.v_hi - f.v_lo + 1);
        }
    std::vector<SweepBallRays> caps(grid.size() * 3);
    std::vector<std::array<int, 2>> rows(row_count);
    pool_for(grid.size(), 4, [&](const Chunk& chunk) {
        for (std::size_t s = chunk.first; s < chunk.last; ++s)
            for (int a = 0; a < 3; ++a) {
                const std::size_t fs = s * 3 + static_cast<std::size_t>(a);
                caps[fs] = SweepBallRays(grid[s], a);
                const Footprint& f = fp[fs];
                if (!f.any) continue;
                const SweepShadow shadow(grid[s], a);
                for (int v = f.v_lo; v <= f.v_hi; ++v) {
                    std::array<int, 2> r{f.u_lo, f.u_hi};
                    if (!shadow.row(v, r[0], r[1])) r = {1, 0};
                    rows[row_first[fs] + static_cast<std::size_t>(v - f.v_lo)] = r;
                }
            }
    }, threads);
    struct Band {
        std::uint32_t s;
        int tv, tu0, tu1;  // tile row and tile columns, relative to the set's box of tiles
    };
    std::vector<Band> bands;
    std::vector<std::size_t> slot;
    for (int a = 0; a < 3; ++a) {
        int tu0 = model.sets[a].nu, tu1 = -1, tv0 = model.sets[a].nv, tv1 = -1;
        for (std::size_t s = 0; s < grid.size(); ++s) {
            const Footprint& f = fp[s * 3 + static_cast<std::size_t>(a)];
            if (!f.any) continue;
            tu0 = std::min(tu0, f.u_lo / kTileRays);
            tu1 = std::max(tu1, f.u_hi / kTileRays);
            tv0 = std::min(tv0, f.v_lo / kTileRays);
            tv1 = std::max(tv1, f.v_hi / kTileRays);
        }
        if (tu1 < tu0) continue;
        // The tiles each sweep reaches, band of tile rows by band (bands[], in batch order), counted per tile, then
        // listed per tile in batch order (a counting sort over the set's box of tiles).
        bands.clear();
        for (std::size_t s = 0; s < grid.size(); ++s) {
            const Footprint& f = fp[s * 3 + static_cast<std::size_t>(a)];
            if (!f.any) continue;
            for (int tv = f.v_lo / kTileRays; tv <= f.v_hi / kTileRays; ++tv) {
                int lo = INT32_MAX, hi = -1;
                for (int v = std::max(f.v_lo, tv * kTileRays); v <= std::min(f.v_hi, tv * kTileRays + kTileRays - 1); ++v) {
                    const std::array<int, 2>& r = rows[row_first[s * 3 + static_cast<std::size_t>(a)] + static_cast<std::size_t>(v - f.v_lo)];
                    if (r[0] > r[1]) continue;
                    lo = std::min(lo, r[0]);
                    hi = std::max(hi, r[1]);
                }
                if (lo <= hi) bands.push_back({static_cast<std::uint32_t>(s), tv - tv0, lo / kTileRays - tu0, hi / kTileRays - tu0});
            }
        }
        const std::size_t bw = static_cast<std::size_t>(tu1 - tu0 + 1);
        slot.assign(bw * static_cast<std::size_t>(tv1 - tv0 + 1), 0u);
        for (const Band& b : bands)
            for (int tu = b.tu0; tu <= b.tu1; ++tu) ++slot[static_cast<std::size_t>(tu) + bw * static_cast<std::size_t>(b.tv)];
        for (std::size_t i = 0; i < slot.size(); ++i) {  // slot[i]: the tile's count -> where its next sweep goes
            if (slot[i] == 0) continue;
            tiles.push_back({a, tu0 + static_cast<int>(i % bw), tv0 + static_cast<int>(i / bw), members.size(), slot[i]});
            slot[i] = members.size();
            members.resize(members.size() + tiles.back().count);
        }
        for (const Band& b : bands)
            for (int tu = b.tu0; tu <= b.tu1; ++tu) members[slot[static_cast<std::size_t>(tu) + bw * static_cast<std::size_t>(b.tv)]++] = b.s;
    }
    if (tiles.empty()) return stats;

    // Each tile's rays get, in batch order, the sweeps whose footprint holds them: no two tasks touch the
    // same ray, and every ray sees the operations of the sequential path in the same order.
    // The changed interval ends per (ray tile, member sweep), gathered per sweep below: the same boxes as
    // apply_sweep one by one, so both paths mark the same cells.
    std::vector<std::size_t> tile_changed(tiles.size(), 0);
    std::vector<ChangedBox> member_box(members.size());
    pool_for(tiles.size(), 1, [&](const Chunk& chunk) {
        for (std::size_t i = chunk.first; i < chunk.last; ++i) {
            const RayTile& t = tiles[i];
            RaySet& set = model.sets[t.axis];
            const float depth_cells = static_cast<float>(model.lattice.cells[t.axis]);
            const int u0 = t.tu * kTileRays, u1 = std::min(set.nu - 1, u0 + kTileRays - 1);
            const int v0 = t.tv * kTileRays, v1 = std::min(set.nv - 1, v0 + kTileRays - 1);
            std::size_t changed = 0;
            // Row by row, each member sweep over the rays of the row it can reach, in batch order: every ray still
            // sees its sweeps in batch order, and rays are independent.
            for (int v = v0; v <= v1; ++v)
                for (std::size_t k = t.first; k < t.first + t.count; ++k) {
                    const std::uint32_t s = members[k];
                    const std::size_t fs = s * 3u + static_cast<std::size_t>(t.axis);
                    const Footprint& f = fp[fs];
                    if (v < f.v_lo || v > f.v_hi) continue;
                    const std::array<int, 2>& r = rows[row_first[fs] + static_cast<std::size_t>(v - f.v_lo)];
                    for (int u = std::max(u0, r[0]); u <= std::min(u1, r[1]); ++u) {
                        ChangedSpan span;
                        if (apply_sweep_to_ray(grid[s], t.axis, u, v, set.ray(u, v), depth_cells, converted.tools,
                                               &caps[fs], &span)) {
                            ++changed;
                            member_box[k].add_ray(t.axis, u, v, span);
                        }
                    }
                }
            tile_changed[i] = changed;
        }
    }, threads);
    for (std::size_t c : tile_changed) stats.rays_changed += c;
    std::vector<ChangedBox> sweep_box(grid.size());
    for (std::size_t k = 0; k < members.size(); ++k) sweep_box[members[k]].add(member_box[k]);
    for (const ChangedBox& box : sweep_box) box.mark(model);
    return stats;
}

}  // namespace tridex::compute
