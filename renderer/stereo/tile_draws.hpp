// renderer/stereo/tile_draws.hpp - the workpiece tiles and groups of tiles of a scene as per-eye draws: culled
// per eye, each at the level of detail its projected error allows.
#pragma once

#include <array>
#include <cstdint>
#include <functional>

#include "core/aabb.hpp"
#include "renderer/scene/gpu_mesh.hpp"
#include "renderer/scene/tile_culling.hpp"
#include "renderer/scene/tile_lod.hpp"
#include "renderer/scene/tile_mesh_cache.hpp"
#include "renderer/stereo/eye_strategy.hpp"
#include "renderer/stereo/frame_draws.hpp"
#include "renderer/stereo/stereo_frame.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "renderer/timing/frame_stats.hpp"

namespace tridex::renderer {

/// The eyes a frame's tile draws are chosen for.
struct TileDrawEyes {
    EyeStrategy strategy = EyeStrategy::kPassPerEye;
    int eye_count = 2;                 ///< 1 (mono: the left eye only) or 2
    std::array<Frustum, 2> frusta{};   ///< per eye, for culling
    std::array<LodEye, 2> lod_eyes{};  ///< per eye, for the projected error
};

/// The same eyes seen from a placed object's model frame (world_from_model: rigid, m): each frustum plane and LOD
/// view taken into that frame, so culling and levels of detail test model-frame bounds directly. Identity returns
/// the eyes as they are.
TileDrawEyes in_model_frame(const TileDrawEyes& eyes, const Pose& world_from_model);

/// Appends the opaque draws of scene.tiles and scene.tile_groups (whose GPU meshes `tiles` and `groups` hold,
/// synced to those lists in that order; `groups` entries carry the group's levels as their levels 1..n).
/// With scene.lod, each eye draws each group at the coarsest level within scene.lod_max_px (choose_group_levels)
/// unless an enclosing group is drawn, and the tiles no drawn group covers at their own level (choose_level);
/// multiview draws both eyes with one choice (the finer). Without it every tile at full resolution. Culling
/// (scene.cull_tiles) tests each drawn tile's or group's bounds per eye. `add` appends a draw of a mesh and
/// returns it (the caller sets the kind, colour and lighting); `cover` widens the eye mask's opaque region to a
/// box. Fills stats.tiles (visibility per tile), stats.tile_triangles and stats.groups_drawn. Only the meshes and
/// levels drawn are uploaded (TileMeshCache::need). Throws tridex::Error when a tile's group index or a group's
/// parent is out of range, or an upload does (naming the tile).
void add_tile_draws(const SceneView& scene, const TileDrawEyes& eyes, TileMeshCache& tiles,
                    TileMeshCache& groups, const std::function<StereoDraw&(const GpuMesh&)>& add,
                    const std::function<void(std::uint32_t, const Aabb&)>& cover, FrameStats& stats);

/// Appends the draws of scene.indirect_workpiece's tiles (the GPU contour: one vkCmdDrawIndexedIndirect per tile
/// and eye mask, flat-shaded contour pipeline), culled per eye unless scene.cull_tiles is off (multiview draws a tile
/// either eye sees in both), widening the opaque region by each drawn tile's bounds. Fills stats.tiles and adds the
/// drawn tiles' triangles to stats.tile_triangles. Nothing without an indirect workpiece or tiles. Throws
/// tridex::Error when one of its buffers is null.
void add_indirect_tile_draws(const SceneView& scene, const TileDrawEyes& eyes, FrameDraws& list, FrameStats& stats);

}  // namespace tridex::renderer
