// compute/contour/tile_group_box.hpp - the tiles of a group of tiles, grown by the one tile whose vertices they share.
#pragma once

#include <array>

namespace tridex::compute {

/// The tiles of the depth-`depth` tile group at group coordinates `coords` (2^depth tiles along each axis,
/// TileGroupSurface::coords) grown by one tile, as an inclusive box of tile coordinates in `lo`, `hi` (not clamped to
/// the grid: the caller clamps). Returns false, leaving them as they were, when the depth is outside 1..6 or the group
/// lies outside a grid of `dims` tiles.
inline bool group_tiles_grown(const std::array<int, 3>& dims, int depth, const std::array<int, 3>& coords,
                              std::array<int, 3>& lo, std::array<int, 3>& hi) {
    if (depth < 1 || depth > 6) return false;
    const int span = 1 << depth;
    for (int a = 0; a < 3; ++a)
        if (coords[a] < 0 || coords[a] * span >= dims[a]) return false;
    for (int a = 0; a < 3; ++a) {
        lo[a] = coords[a] * span - 1;
        hi[a] = (coords[a] + 1) * span;
    }
    return true;
}

}  // namespace tridex::compute
