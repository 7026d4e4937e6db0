// compute/model/tridexel.hpp - the tri-dexel solid: three ray sets of sorted, disjoint solid intervals.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "compute/model/lattice.hpp"

namespace tridex::compute {

/// One solid span [enter, exit] along a ray, in grid units from the lattice origin; enter < exit.
/// Each end is a point of the surface and carries the material id painted there (0 = the
/// workpiece's own material; ids index the renderer's palette and the haptic material table).
struct Interval {
    float enter = 0.0f;
    float exit = 0.0f;
    std::uint8_t enter_material = 0;  ///< material id of the surface point at `enter`
    std::uint8_t exit_material = 0;   ///< material id of the surface point at `exit`
};

/// The rays parallel to one axis `axis`, one through every lattice node (u, v) of the two other
/// axes: u runs along (axis+1)%3, v along (axis+2)%3 (X rays: u=y, v=z; Y: u=z, v=x; Z: u=x, v=y).
/// Each ray holds sorted, disjoint, non-touching intervals (CPU reference layout: a vector per ray).
struct RaySet {
    int axis = 0;  ///< 0 = X rays, 1 = Y rays, 2 = Z rays
    int nu = 0;    ///< rays along u (= lattice nodes along (axis+1)%3)
    int nv = 0;    ///< rays along v (= lattice nodes along (axis+2)%3)
    std::vector<std::vector<Interval>> rays;  ///< index u + nu * v

    std::vector<Interval>& ray(int u, int v) { return rays[static_cast<std::size_t>(u) + static_cast<std::size_t>(nu) * v]; }
    const std::vector<Interval>& ray(int u, int v) const { return rays[static_cast<std::size_t>(u) + static_cast<std::size_t>(nu) * v]; }
};

/// The whole content of one ray: set `axis` (0 X, 1 Y, 2 Z), index u + nu * v in RaySet::rays, and its
/// intervals (undo and redo write rays back whole).
struct RayImage {
    std::uint8_t axis = 0;
    std::uint32_t index = 0;
    std::vector<Interval> intervals;
};

/// An inclusive box of lattice cells, [lo, hi] per axis (cell c spans [c, c+1] in grid units).
struct CellBox {
    std::array<int, 3> lo{};
    std::array<int, 3> hi{};
};

/// Cubic tiles of kTileCells^3 cells with a dirty flag each; Booleans mark the tiles their swept
/// footprint touches, contouring redoes only those. Tile (tx, ty, tz) covers cells
/// [tx*kTileCells, (tx+1)*kTileCells) along x, and so on.
///
/// A flag is 0 (clean), kWhole (redo the whole tile) or kPartial (redo only the cells of dirty_cells[t]:
/// every cell whose mesh items can differ from the tile's last contour lies in that box). Any non-zero flag
/// means dirty; writing kWhole directly is always safe (a change not described by a box).
struct TileGrid {
    static constexpr int kTileCells = 16;
    static constexpr std::uint8_t kWhole = 1;    ///< dirty: redo every cell of the tile
    static constexpr std::uint8_t kPartial = 2;  ///< dirty: redo the cells of dirty_cells[t] only
    std::array<int, 3> tiles{};        ///< tiles along x, y, z
    std::vector<std::uint8_t> dirty;   ///< 0 clean, kWhole or kPartial; index tx + tiles[0]*(ty + tiles[1]*tz)
    /// Per tile, the cells to redo when its flag is kPartial (global cell indices, within the tile);
    /// unused otherwise. May be empty (no tile is then treated as partial).
    std::vector<CellBox> dirty_cells;

    std::size_t index(int tx, int ty, int tz) const {
        return static_cast<std::size_t>(tx) + static_cast<std::size_t>(tiles[0]) * (static_cast<std::size_t>(ty) + static_cast<std::size_t>(tiles[1]) * tz);
    }
    std::size_t count() const { return dirty.size(); }
    /// The indices of the dirty tiles, ascending.
    std::vector<std::uint32_t> dirty_tiles() const {
        std::vector<std::uint32_t> out;
        for (std::size_t t = 0; t < dirty.size(); ++t)
            if (dirty[t]) out.push_back(static_cast<std::uint32_t>(t));
        return out;
    }
    /// The cells tile `t` must redo when partial: dirty_cells[t] when the flag is kPartial and the box is
    /// set, else nullptr (clean tiles, kWhole tiles and out-of-range t: redo the whole tile when dirty).
    const CellBox* partial_cells(std::size_t t) const {
        return t < dirty.size() && dirty[t] == kPartial && dirty_cells.size() == dirty.size() ? &dirty_cells[t]
                                                                                              : nullptr;
    }
};

/// A tri-dexel solid (Peng et al., tri-dexel model): three orthogonal ray sets on one lattice.
/// Every lattice edge lies on exactly one ray, so contouring reads each edge crossing from its own ray.
struct TriDexel {
    Lattice lattice;
    std::array<RaySet, 3> sets;
    TileGrid tiles;

    /// An empty model (no material) on `lattice`, all tiles clean. Throws tridex::Error when the
    /// lattice would need more memory than `max_bytes` (the message gives both numbers).
    static TriDexel empty(const Lattice& lattice, std::size_t max_bytes);
    /// How far (cells) a changed interval end reaches into the contour. Along a ray: a crossing in cell
    /// [c, c+1] reads, for its normal, ends in [c - 2, c + 3] (contour::kNormalWindow = 2), a cell's vertex
    /// reads the crossings of its face-adjacent cells too (contour::kCornerFillReach), and mesh items
    /// anchored at node n read cells n - 1 and n, so 4. Across rays: the normals' neighbour ray (+1), the
    /// crossing's cell (+1), the face-adjacent cell (+1) and the anchor (+1), also 4 (contour_qef.hpp,
    /// contour_tile.hpp).
    static constexpr int kDirtyReachCells = 4;
    /// Marks dirty every tile holding a cell within kDirtyReachCells cells of the world box `box_m`; a tile
    /// clean or already partial becomes kPartial with those cells added to its box (kWhole when the box
    /// then covers the whole tile), a kWhole tile stays whole. An empty box or one off the lattice marks nothing.
    void mark_dirty(const Aabb& box_m);
    /// As mark_dirty, for a box given in grid units (lattice cells from the origin), e.g. the changed interval
    /// ends of a Boolean (ChangedBox in interval_ops.hpp).
    void mark_dirty_grid(const Vec3& lo, const Vec3& hi);
    /// Clears all dirty flags.
    void clear_dirty();
    /// Total number of intervals in all three sets.
    std::size_t interval_count() const;
};

}  // namespace tridex::compute
