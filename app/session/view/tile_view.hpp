// app/session/view/tile_view.hpp - the contoured tiles (compute::TileSurface) and their groups (compute::TileGroupSurface)
// as the renderer's tile and group lists, with their levels of detail.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "compute/contour/contour_tiles.hpp"
#include "renderer/scene/tile_group_lod.hpp"
#include "renderer/scene/tile_mesh_cache.hpp"

namespace tridex::app {

/// Levels of detail as `run --lod` and a cluster config's "lod" name them.
struct LodChoice {
    bool on = false;  ///< build levels in the background and draw each tile and group at the level its pixels need
    /// Groups take their levels from the model read at coarser strides from this many cells along the model's
    /// longest side (compute::LodWorkerOptions::coarse_groups_from_cells; 1 = always, 0 = never).
    int coarse_groups_from_cells = 0;
};

/// The choice a name gives: "on" (simplified levels below compute::kCoarseGroupsFromCells cells, groups contoured
/// from the dexels from there), "coarse" (groups from the dexels at any size), "simplified" (never) or "off". Throws
/// tridex::Error "must be on, off, coarse or simplified, got \"NAME\"" on another name (the caller prefixes its
/// option or field).
LodChoice lod_choice(const std::string& name);

/// The renderer's view of a list of tiles and groups: `tiles` for SceneView::tiles and `groups` for
/// SceneView::tile_groups, whose levels point into `levels`. They keep pointers into the TileSurfaces and
/// TileGroupSurfaces, which must outlive the use of the view (the shared overload of tile_view_of holds them).
struct TileView {
    std::vector<renderer::TileMesh> tiles;
    std::vector<renderer::TileGroup> groups;
    std::vector<renderer::TileMeshLevel> levels;
    /// Each group's place (its depth and coordinates as one key) and index in `groups`, sorted by place: how a
    /// group's neighbours are found.
    std::vector<std::pair<std::uint64_t, std::size_t>> group_places;
    /// (tile id, id of the depth-1 group listing it) for every child of a depth-1 group, sorted: the group of a tile
    /// that comes in a later publish.
    std::vector<std::pair<std::uint64_t, std::uint64_t>> tile_groups;
    /// The list a later publish's tiles are merged into (then swapped with `tiles`), kept for its storage.
    std::vector<renderer::TileMesh> spare_tiles;
    /// The list a later publish's groups are merged into (then swapped with `groups`), kept for its storage.
    std::vector<renderer::TileGroup> spare_groups;
    /// The published tiles and groups the lists were filled from (tile_view_of's shared overload; empty after the
    /// other): a frame that gets the same ones again reuses the lists.
    std::vector<std::shared_ptr<const compute::TileSurface>> from_tiles;
    std::vector<std::shared_ptr<const compute::TileGroupSurface>> from_groups;
    bool from_lods = false;
    bool from_shared = false;
    bool from_sorted = false;  ///< the published lists were sorted by id with no null entry
};

/// Fills `out` (reusing its storage) with one renderer::TileMesh per surface (mesh, bounds, version, id,
/// materials) and, when with_lods, its TileSurface::lods as TileMesh::levels (the full mesh's normals at
/// the kept vertices), and one renderer::TileGroup per group (levels, bounds, version, parent index, and the
/// neighbours of the groups whose levels join them, TileMeshLevel::joins; each tile's TileMesh::group names its
/// depth-1 group). Without with_lods `groups` stays empty. Null pointers
/// are skipped (their children then have no group / parent). When `surfaces`, `groups` and with_lods are those `out`
/// was last filled from (the same objects: a published one never changes), `out` is left as it is. When both lists
/// are sorted by id (as a sculpt thread publishes them) and so were the last ones, the new lists are merged into the
/// last ones by id: unchanged objects keep their entries, replaced, new and gone ones are rewritten, added or
/// dropped, in O(tiles + groups) plus a search per changed entry. O(tiles log tiles) otherwise.
void tile_view_of(std::span<const std::shared_ptr<const compute::TileSurface>> surfaces,
                  std::span<const std::shared_ptr<const compute::TileGroupSurface>> groups, bool with_lods,
                  TileView& out);
/// As above for a TileSurfaceCache's own lists.
void tile_view_of(std::span<const compute::TileSurface> surfaces, std::span<const compute::TileGroupSurface> groups,
                  bool with_lods, TileView& out);

}  // namespace tridex::app
