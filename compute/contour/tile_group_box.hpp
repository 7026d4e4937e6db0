// compute/contour/tile_group_box.hpp - the tiles of a group of tiles, grown by the one tile whose vertices they share.
#pragma once

#include <array>
#include <cstdint>

namespace tridex::compute {

/// The coordinates of cell `index` in a grid of `dims` cells (x fastest, then y, then z): a tile's in the tile grid
/// from its tile id, or a group's in its depth's group grid from its linear index (tile_group_index). No range check.
inline std::array<int, 3> grid_coords(std::uint64_t index, const std::array<int, 3>& dims) {
    const auto nx = static_cast<std::uint64_t>(dims[0]), ny = static_cast<std::uint64_t>(dims[1]);
    return {static_cast<int>(index % nx), static_cast<int>((index / nx) % ny), static_cast<int>(index / (nx * ny))};
}

/// The linear index of the cell at coordinates `c` in a grid of `dims` cells, x fastest: grid_coords' inverse.
inline std::uint64_t grid_index(const std::array<int, 3>& c, const std::array<int, 3>& dims) {
    return static_cast<std::uint64_t>(c[0]) +
           static_cast<std::uint64_t>(dims[0]) *
               (static_cast<std::uint64_t>(c[1]) + static_cast<std::uint64_t>(dims[1]) * static_cast<std::uint64_t>(c[2]));
}

/// The grid of depth-`depth` tile groups (2^depth tiles along each axis) over a grid of `dims` tiles: the group
/// count along each axis, rounded up. depth >= 0; no range check.
inline std::array<int, 3> group_grid_dims(const std::array<int, 3>& dims, int depth) {
    std::array<int, 3> g{};
    for (int a = 0; a < 3; ++a) g[a] = (dims[a] + (1 << depth) - 1) >> depth;
    return g;
}

/// The linear index, in group_grid_dims(dims, depth), of the depth-`depth` group holding the tile at coordinates
/// `tile` of a grid of `dims` tiles (tile_group_id(depth, this) is its id). No range check.
inline std::uint64_t group_index_of(const std::array<int, 3>& tile, const std::array<int, 3>& dims, int depth) {
    return grid_index({tile[0] >> depth, tile[1] >> depth, tile[2] >> depth}, group_grid_dims(dims, depth));
}

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
