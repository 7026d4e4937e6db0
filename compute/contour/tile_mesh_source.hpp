// compute/contour/tile_mesh_source.hpp - where a TileSurfaceCache reads the contoured surface from, tile by tile:
// the CPU Contourer, or the GPU contour read back.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// A tiled contoured surface that TileSurfaceCache::refresh reads: per tile (linear index tx + tiles_x * (ty +
/// tiles_y * tz)) its triangle count, a content version and its mesh in world metres.
class TileMeshSource {
public:
    virtual ~TileMeshSource() = default;
    /// Number of tiles.
    virtual std::size_t tile_count() const = 0;
    /// Tiles along x, y and z.
    virtual std::array<int, 3> tile_dims() const = 0;
    /// Triangles tile `tile` owns (0 = no surface). May throw tridex::Error when tile >= tile_count().
    virtual std::size_t tile_triangle_count(std::size_t tile) const = 0;
    /// Content version of the tile: changes whenever its mesh or materials change; values from
    /// fresh_tile_version() (never 0 once contoured, unique per process).
    virtual std::uint64_t tile_version(std::size_t tile) const = 0;
    /// The triangles tile `tile` owns as a compact mesh (every vertex used), world m, CCW from outside, with
    /// one material id per vertex in `materials`, and in `normals` either one unit normal per vertex (the whole
    /// surface's at that vertex, the neighbour tiles' triangles included, so that tiles sharing a vertex shade it
    /// alike) or nothing (a renderer then takes the mesh's own area-weighted normals). Neighbour tiles give a vertex
    /// they share bit-identical positions. Throws tridex::Error on a bad tile index or an unreadable tile.
    /// TileSurfaceCache::refresh calls it for several tiles at once from the task pool's threads, so it must only
    /// read.
    virtual TriMesh tile_mesh(std::size_t tile, std::vector<std::uint8_t>& materials,
                              std::vector<Vec3>& normals) const = 0;
    /// Appends to `out` (unsorted, with repeats) every tile whose triangle count or version, as this source shows
    /// them, may have changed after `mark` (a fresh_tile_version() value taken while reading a source of the same
    /// change_view()), and returns true; returns false when it cannot tell (changes after `mark` were not all
    /// recorded, or the source keeps no record): the reader then visits every tile. Default: false.
    virtual bool changed_since(std::uint64_t mark, std::vector<std::uint64_t>& out) const {
        (void)mark;
        (void)out;
        return false;
    }
    /// What this source shows, as a value: two sources with the same value show the same tiles (the same Contourer
    /// through the same start-up refiner and stroke deferral), so a mark taken reading one holds for the other.
    /// Default 0: keeps no record (changed_since() is false).
    virtual std::uint64_t change_view() const { return 0; }
};

}  // namespace tridex::compute
