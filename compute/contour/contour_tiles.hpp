// compute/contour/contour_tiles.hpp - the contoured surface as per-tile meshes for a renderer, rebuilt only
// where it changed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "core/aabb.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// One tile's part of the contoured surface, ready for a renderer: the triangles the tile owns, with the
/// vertices they use (its own and its neighbours'), world metres, CCW from outside.
struct TileSurface {
    std::uint64_t id = 0;       ///< tile index in the model's TileGrid (stable across updates)
    std::uint64_t version = 0;  ///< changes whenever this tile's mesh or a vertex it borrows from a neighbour changed
    Aabb bounds_m;              ///< box of mesh.positions, m
    TriMesh mesh;               ///< the tile's triangles (compact vertex list)
    /// Material id per mesh vertex (size = mesh.positions.size(); Contourer::mesh_materials' rule).
    std::vector<std::uint8_t> materials;
};

/// Keeps TileSurfaces for every non-empty tile of a Contourer, rebuilding only tiles whose contour changed
/// (Contourer::tile_version, which also changes when only materials changed). Versions are unique per process, so one cache may follow a new Contourer
/// (e.g. after a reset): its tiles then all count as changed.
class TileSurfaceCache {
public:
    /// Rebuilds the tiles whose version changed since the last refresh (all on the first call) and drops
    /// tiles that became empty. Returns the number of tiles rebuilt. O(changed tiles' triangles) plus a
    /// scan of the tile versions. Throws tridex::Error as Contourer::tile_mesh (the cache is then unchanged).
    std::size_t refresh(const Contourer& contourer);
    /// The current tiles, ordered by id. refresh() may move them: references and pointers into it (e.g. to
    /// a tile's mesh) are valid until the next refresh().
    const std::vector<TileSurface>& tiles() const { return tiles_; }
    /// Total triangles over tiles().
    std::size_t triangle_count() const;

private:
    std::vector<TileSurface> tiles_;
};

}  // namespace tridex::compute
