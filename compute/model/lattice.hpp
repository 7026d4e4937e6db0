// compute/model/lattice.hpp - the shared node lattice that the three ray sets of a tri-dexel model use.
#pragma once

#include <array>
#include <cstdint>

#include "core/aabb.hpp"
#include "core/math.hpp"

namespace tridex::compute {

/// Regular lattice of nodes origin_m + cell_m * (i, j, k), 0 <= i <= cells[0], etc.
/// "Grid units" are positions divided by cell_m, measured from origin_m (a local origin, so that
/// 32-bit depths keep their precision wherever the workpiece sits in the world).
struct Lattice {
    Vec3 origin_m{0.0};            ///< world position of node (0,0,0), m
    double cell_m = 1.0;           ///< spacing h, m (> 0)
    std::array<int, 3> cells{};    ///< cells along x, y, z; nodes are cells + 1

    /// Node count along axis a.
    int nodes(int a) const { return cells[a] + 1; }
    /// World (m) -> grid units.
    Vec3 to_grid(const Vec3& world_m) const { return (world_m - origin_m) / cell_m; }
    /// Grid units -> world (m).
    Vec3 to_world(const Vec3& grid) const { return origin_m + grid * cell_m; }
    /// World box covered by the nodes, m.
    Aabb bounds() const {
        return Aabb{origin_m, origin_m + cell_m * Vec3(cells[0], cells[1], cells[2])};
    }

    /// The lattice for a workpiece with bounding box `box` (m): `resolution` cells along the
    /// longest side, of which `margin_cells` on each end are empty margin, so the contoured
    /// surface is closed. Shorter sides get the same spacing and the same margin, centred.
    /// Throws tridex::Error when resolution < 2*margin_cells + 2 or the box is empty/degenerate.
    static Lattice around(const Aabb& box, int resolution, int margin_cells = 2);
};

}  // namespace tridex::compute
