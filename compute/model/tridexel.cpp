// compute/model/tridexel.cpp - allocation, dirty tiles and counts of the tri-dexel model.
#include "compute/model/tridexel.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace tridex::compute {

TriDexel TriDexel::empty(const Lattice& lattice, std::size_t max_bytes) {
    std::size_t rays = 0;
    for (int a = 0; a < 3; ++a)
        rays += static_cast<std::size_t>(lattice.nodes((a + 1) % 3)) * lattice.nodes((a + 2) % 3);
    // A ray costs its vector header plus, for a typical workpiece, about two intervals.
    const std::size_t need = rays * (sizeof(std::vector<Interval>) + 2 * sizeof(Interval));
    if (need > max_bytes) {
        std::ostringstream msg;
        msg << "resolution " << lattice.cells[0] << "x" << lattice.cells[1] << "x" << lattice.cells[2]
            << " cells needs about " << need / (1024 * 1024) << " MiB for " << rays
            << " rays, more than the " << max_bytes / (1024 * 1024) << " MiB available; lower --resolution";
        throw Error(msg.str());
    }
    TriDexel m;
    m.lattice = lattice;
    for (int a = 0; a < 3; ++a) {
        RaySet& s = m.sets[a];
        s.axis = a;
        s.nu = lattice.nodes((a + 1) % 3);
        s.nv = lattice.nodes((a + 2) % 3);
        s.rays.assign(static_cast<std::size_t>(s.nu) * s.nv, {});
    }
    for (int a = 0; a < 3; ++a)
        m.tiles.tiles[a] = (lattice.cells[a] + TileGrid::kTileCells - 1) / TileGrid::kTileCells;
    m.tiles.dirty.assign(static_cast<std::size_t>(m.tiles.tiles[0]) * m.tiles.tiles[1] * m.tiles.tiles[2], 0);
    return m;
}

void TriDexel::mark_dirty(const Aabb& box_m) {
    if (box_m.empty()) return;
    mark_dirty_grid(lattice.to_grid(box_m.lo), lattice.to_grid(box_m.hi));
}

void TriDexel::mark_dirty_grid(const Vec3& glo, const Vec3& ghi) {
    if (!(glo.x <= ghi.x && glo.y <= ghi.y && glo.z <= ghi.z)) return;
    CellBox cells;
    for (int a = 0; a < 3; ++a) {
        // Cells whose mesh items can read a changed ray (kDirtyReachCells). The box is widened by 1e-3
        // cell first: Boolean chords are rounded to float, so a changed end may lie a few 1e-5 cells
        // outside the double-precision box. A cell c spans [c, c+1] in grid units.
        const double l = std::floor(glo[a] - 1e-3) - kDirtyReachCells, h = std::floor(ghi[a] + 1e-3) + kDirtyReachCells;
        const int last_cell = lattice.cells[a] - 1;
        if (!(h >= 0.0 && l <= last_cell)) return;
        cells.lo[a] = static_cast<int>(std::max(0.0, l));
        cells.hi[a] = static_cast<int>(std::min<double>(last_cell, h));
    }
    if (tiles.dirty_cells.size() != tiles.dirty.size()) tiles.dirty_cells.assign(tiles.dirty.size(), CellBox{});
    constexpr int kT = TileGrid::kTileCells;
    for (int z = cells.lo[2] / kT; z <= cells.hi[2] / kT; ++z)
        for (int y = cells.lo[1] / kT; y <= cells.hi[1] / kT; ++y)
            for (int x = cells.lo[0] / kT; x <= cells.hi[0] / kT; ++x) {
                const std::size_t t = tiles.index(x, y, z);
                if (tiles.dirty[t] == TileGrid::kWhole) continue;
                const std::array<int, 3> tile{x, y, z};
                CellBox& box = tiles.dirty_cells[t];
                bool whole = true;
                for (int a = 0; a < 3; ++a) {
                    const int first = tile[a] * kT, last = std::min(first + kT, lattice.cells[a]) - 1;
                    int lo = std::max(first, cells.lo[a]), hi = std::min(last, cells.hi[a]);
                    if (tiles.dirty[t] == TileGrid::kPartial) {
                        lo = std::min(lo, box.lo[a]);
                        hi = std::max(hi, box.hi[a]);
                    }
                    box.lo[a] = lo;
                    box.hi[a] = hi;
                    whole = whole && lo == first && hi == last;
                }
                tiles.dirty[t] = whole ? TileGrid::kWhole : TileGrid::kPartial;
            }
}

void TriDexel::clear_dirty() { std::fill(tiles.dirty.begin(), tiles.dirty.end(), 0); }

std::size_t TriDexel::interval_count() const {
    std::size_t n = 0;
    for (const RaySet& s : sets)
        for (const auto& r : s.rays) n += r.size();
    return n;
}

}  // namespace tridex::compute
