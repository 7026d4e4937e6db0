// compute/contour/contour_sample.hpp - what contouring reads from the tri-dexel rays: node occupancy (from
// the X rays) and edge crossings (each lattice edge from its own ray). Grid units throughout.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "compute/model/tridexel.hpp"

namespace tridex::compute::contour {

/// Integer lattice node (i, j, k), grid units.
using Node = std::array<int, 3>;

/// Node occupancy of a cubic block of kSpan^3 lattice nodes starting at node `lo`, one bit per node.
///
/// Definition used by all contouring: node (i, j, k) is inside iff x = i lies in an interval of the X
/// ray (u = j, v = k) with enter <= x < exit (half-open). Nodes on the lattice boundary (any index 0 or
/// cells[a]) and outside the lattice count as outside, so the contour is closed even when material
/// touches the border. Only the X ray set is read; intervals with NaN or enter > exit are ignored.
class OccupancyBlock {
public:
    /// Nodes per axis: a tile's kTileCells cells plus one node below and two above (the cells that
    /// contour a tile look one cell beyond it on each side).
    static constexpr int kSpan = TileGrid::kTileCells + 3;
    static_assert(kSpan <= 32, "a block row must fit a 32-bit mask");

    /// Reads the X rays of `model` for nodes lo .. lo + kSpan - 1 on each axis. O(kSpan^2 * intervals).
    void fill(const TriDexel& model, const Node& lo);
    /// Bit mask of row (j, k): bit b is node (lo[0] + b, j, k). j, k must lie in the block.
    std::uint32_t row(int j, int k) const { return rows_[static_cast<std::size_t>(j - lo_[1]) + kSpan * static_cast<std::size_t>(k - lo_[2])]; }
    /// Occupancy of node n (absolute indices, must lie in the block).
    bool inside(const Node& n) const { return ((row(n[1], n[2]) >> (n[0] - lo_[0])) & 1u) != 0; }
    /// Configuration byte of the cell with min node n (bit c = corner c inside; see contour_table.hpp).
    int config(const Node& n) const;

private:
    Node lo_{};
    std::array<std::uint32_t, kSpan * kSpan> rows_{};
};

/// True when depth t (grid units along the ray's axis) lies in an interval of `ray` (enter <= t < exit, the
/// half-open rule of OccupancyBlock); NaN or reversed intervals never hold it. O(intervals).
bool inside_at(const std::vector<Interval>& ray, double t);

/// Occupancy of one lattice node n by OccupancyBlock's definition (read from its X ray; nodes on or beyond the
/// lattice boundary are outside), for nodes beyond a block. O(intervals on the X ray).
bool node_inside(const TriDexel& model, const Node& n);

/// A surface crossing on one lattice edge.
struct EdgeCrossing {
    double t = 0.0;         ///< coordinate along the edge's axis, grid units, within [n_a, n_a + 1]
    bool fallback = false;  ///< true when the edge's own ray had no interval end on the edge
    /// Material id of the interval end the crossing was read from (Interval::enter_material or
    /// exit_material); for a fallback, that of the nearest end used, or 0 when none was near.
    std::uint8_t material = 0;
    /// True when the crossing is an interval exit (leaving material going +axis), false for an enter;
    /// for a fallback, the kind of the nearest end used (false when none). A crossing whose kind is not
    /// the one the occupancy implies (exit when the start node is inside) gets no normal.
    bool exit = false;
};

/// The crossing on the lattice edge from node n to n + e_a (a = 0, 1, 2), read from the ray of set a
/// through n. `start_inside` is the occupancy of node n (the end node has the other occupancy). Takes
/// the first interval end on the closed edge met walking from the inside node, skipping an enter exactly
/// on an inside start node (material touching the node: the crossing is that interval's exit, further
/// on). When the ray has no end
/// on the edge (the ray disagrees with the X-ray occupancy), falls back to the nearest end within half a
/// cell of the edge clamped into it, else the edge midpoint (material 0), and sets `fallback`. The
/// crossing carries the material of the end it came from. Non-finite ends are ignored. O(intervals on ray).
EdgeCrossing edge_crossing(const TriDexel& model, int a, const Node& n, bool start_inside);

/// The crossing point of that edge in grid units (node n with coordinate a replaced by the crossing).
Vec3 crossing_point(const Node& n, int a, const EdgeCrossing& x);

}  // namespace tridex::compute::contour
