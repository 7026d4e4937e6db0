// app/tile_view.hpp - the contoured tiles (compute::TileSurface) as the renderer's tile list, with their levels
// of detail.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "compute/contour/contour_tiles.hpp"
#include "renderer/scene/tile_mesh_cache.hpp"

namespace tridex::app {

/// The renderer's view of a list of tiles: `tiles` for SceneView::tiles, whose levels point into `levels`.
/// Both keep pointers into the TileSurfaces, which must outlive the use of the view.
struct TileView {
    std::vector<renderer::TileMesh> tiles;
    std::vector<renderer::TileMeshLevel> levels;
};

/// Fills `out` (reusing its storage) with one renderer::TileMesh per surface (mesh, bounds, version, id,
/// materials) and, when with_lods, its TileSurface::lods as TileMesh::levels (the full mesh's normals at
/// the kept vertices). Null pointers in `surfaces` are skipped.
void tile_view_of(std::span<const std::shared_ptr<const compute::TileSurface>> surfaces, bool with_lods, TileView& out);
/// As above for a TileSurfaceCache's own list.
void tile_view_of(std::span<const compute::TileSurface> surfaces, bool with_lods, TileView& out);

}  // namespace tridex::app
