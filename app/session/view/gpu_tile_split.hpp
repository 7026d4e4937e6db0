// app/session/view/gpu_tile_split.hpp - which tiles of the GPU contour a frame draws from their read-back meshes and
// levels of detail, and which from the GPU buffers.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "compute/contour/contour_tiles.hpp"
#include "gpu/indirect_workpiece.hpp"

namespace tridex::app {

/// The published tiles and groups that a frame draws in place of the GPU contour's indirect draws.
struct GpuTileSplit {
    std::vector<std::shared_ptr<const compute::TileSurface>> tiles;        ///< ordered by id
    std::vector<std::shared_ptr<const compute::TileGroupSurface>> groups;  ///< ordered by id
};

/// Splits the GPU contour between its buffers and the tiles read back from it (MeshFrame::tiles / groups with
/// levels of detail on the GPU contour). A published tile is drawn from its mesh and levels when its levels are
/// built (TileSurface::lods_built) and it is the buffers' current content (TileSurface::source_version equals
/// its IndirectTile::version); a group when every tile and group under it is. Those tiles are removed from
/// `indirect.tiles` (indirect.triangles is left as it was: the whole contour); `out` gets them and the groups
/// (reusing its storage). Both input lists must be ordered by id, as the sculpt thread publishes them.
/// O(tiles + groups' children).
void split_gpu_tiles(std::span<const std::shared_ptr<const compute::TileSurface>> tiles,
                     std::span<const std::shared_ptr<const compute::TileGroupSurface>> groups,
                     renderer::IndirectWorkpiece& indirect, GpuTileSplit& out);

}  // namespace tridex::app
