// compute/tools/sweep_parallel.cpp - ray tiles of the batch's footprint shared out on the task pool.
#include "compute/tools/sweep_parallel.hpp"

#include <algorithm>
#include <array>
#include <atomic>
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
    const std::vector<std::size_t>& source = converted.source;
    if (grid.empty()) return stats;

    // Per set: the tiles the sweeps' footprints cover, each listing its sweeps in batch order (a dense
    // per-set grid over the union's tile range collects them; sweeps are visited in order).
    std::vector<RayTile> tiles;
    std::vector<std::uint32_t> members;
    std::vector<Footprint> fp(grid.size() * 3);
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = model.sets[a];
        int tu0 = set.nu, tu1 = -1, tv0 = set.nv, tv1 = -1;
        for (std::size_t s = 0; s < grid.size(); ++s) {
            Footprint& f = fp[s * 3 + static_cast<std::size_t>(a)];
            f.any = sweep_footprint(grid[s], set, f.u_lo, f.u_hi, f.v_lo, f.v_hi);
            if (!f.any) continue;
            stats.rays_visited += static_cast<std::size_t>(f.u_hi - f.u_lo + 1) * static_cast<std::size_t>(f.v_hi - f.v_lo + 1);
            tu0 = std::min(tu0, f.u_lo / kTileRays);
            tu1 = std::max(tu1, f.u_hi / kTileRays);
            tv0 = std::min(tv0, f.v_lo / kTileRays);
            tv1 = std::max(tv1, f.v_hi / kTileRays);
        }
        if (tu1 < tu0) continue;
        const int wu = tu1 - tu0 + 1, wv = tv1 - tv0 + 1;
        std::vector<std::vector<std::uint32_t>> lists(static_cast<std::size_t>(wu) * static_cast<std::size_t>(wv));
        for (std::size_t s = 0; s < grid.size(); ++s) {
            const Footprint& f = fp[s * 3 + static_cast<std::size_t>(a)];
            if (!f.any) continue;
            for (int tv = f.v_lo / kTileRays; tv <= f.v_hi / kTileRays; ++tv)
                for (int tu = f.u_lo / kTileRays; tu <= f.u_hi / kTileRays; ++tu)
                    lists[static_cast<std::size_t>(tu - tu0) + static_cast<std::size_t>(wu) * static_cast<std::size_t>(tv - tv0)]
                        .push_back(static_cast<std::uint32_t>(s));
        }
        for (int tv = 0; tv < wv; ++tv)
            for (int tu = 0; tu < wu; ++tu) {
                const std::vector<std::uint32_t>& l = lists[static_cast<std::size_t>(tu) + static_cast<std::size_t>(wu) * static_cast<std::size_t>(tv)];
                if (l.empty()) continue;
                tiles.push_back({a, tu0 + tu, tv0 + tv, members.size(), l.size()});
                members.insert(members.end(), l.begin(), l.end());
            }
    }
    if (tiles.empty()) return stats;

    // Each tile's rays get, in batch order, the sweeps whose footprint holds them: no two tasks touch the
    // same ray, and every ray sees the operations of the sequential path in the same order.
    std::vector<std::size_t> tile_changed(tiles.size(), 0);
    std::vector<std::atomic<std::uint8_t>> sweep_changed(grid.size());
    for (std::atomic<std::uint8_t>& c : sweep_changed) c.store(0, std::memory_order_relaxed);
    pool_for(tiles.size(), 1, [&](const Chunk& chunk) {
        for (std::size_t i = chunk.first; i < chunk.last; ++i) {
            const RayTile& t = tiles[i];
            RaySet& set = model.sets[t.axis];
            const float depth_cells = static_cast<float>(model.lattice.cells[t.axis]);
            const int u0 = t.tu * kTileRays, u1 = std::min(set.nu - 1, u0 + kTileRays - 1);
            const int v0 = t.tv * kTileRays, v1 = std::min(set.nv - 1, v0 + kTileRays - 1);
            std::size_t changed = 0;
            thread_local std::vector<std::array<int, 2>> row;  // per member sweep: the rays of row v it can reach
            thread_local std::vector<AxisCapsule> caps;        // per member sweep: its chords on this set
            row.resize(t.count);
            caps.clear();
            for (std::size_t k = 0; k < t.count; ++k) caps.push_back(sweep_axis_capsule(grid[members[t.first + k]], t.axis));
            for (int v = v0; v <= v1; ++v) {
                for (std::size_t k = 0; k < t.count; ++k) {
                    const std::uint32_t s = members[t.first + k];
                    const Footprint& f = fp[s * 3u + static_cast<std::size_t>(t.axis)];
                    row[k] = {std::max(u0, f.u_lo), std::min(u1, f.u_hi)};
                    if (v < f.v_lo || v > f.v_hi || !sweep_row_span(grid[s], t.axis, v, row[k][0], row[k][1]))
                        row[k] = {1, 0};
                }
                for (int u = u0; u <= u1; ++u) {
                    std::vector<Interval>* ray = nullptr;
                    for (std::size_t k = t.first; k < t.first + t.count; ++k) {
                        const std::uint32_t s = members[k];
                        const std::array<int, 2>& span = row[k - t.first];
                        if (u < span[0] || u > span[1]) continue;
                        if (ray == nullptr) ray = &set.ray(u, v);
                        if (apply_sweep_to_ray(grid[s], t.axis, u, v, *ray, depth_cells, converted.tools,
                                               &caps[k - t.first])) {
                            ++changed;
                            sweep_changed[s].store(1, std::memory_order_relaxed);
                        }
                    }
                }
            }
            tile_changed[i] = changed;
        }
    }, threads);
    for (std::size_t c : tile_changed) stats.rays_changed += c;
    for (std::size_t s = 0; s < grid.size(); ++s)
        if (sweep_changed[s].load(std::memory_order_relaxed)) model.mark_dirty(sweep_bounds(batch[source[s]]));
    return stats;
}

}  // namespace tridex::compute
