// renderer/stereo/tile_draws.cpp - per-eye tile and group draws at their levels of detail.
#include "renderer/stereo/tile_draws.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "renderer/scene/material_palette.hpp"
#include "renderer/scene/tile_group_lod.hpp"

namespace tridex::renderer {

TileDrawEyes in_model_frame(const TileDrawEyes& eyes, const Pose& world_from_model) {
    if (world_from_model.is_identity()) return eyes;
    const Mat4 m = world_from_model.matrix();
    const Mat4 mt = glm::transpose(m);
    TileDrawEyes out = eyes;
    for (int e = 0; e < 2; ++e) {
        // A plane n.x + d >= 0 in the world is (M^T (n, d)).(x_model, 1) >= 0 in the model frame.
        for (glm::dvec4& p : out.frusta[e].planes) p = mt * p;
        out.lod_eyes[e].view = eyes.lod_eyes[e].view * m;
    }
    return out;
}

void add_tile_draws(const SceneView& scene, const TileDrawEyes& eyes, TileMeshCache& tiles,
                    TileMeshCache& groups, const std::function<StereoDraw&(const GpuMesh&)>& add,
                    const std::function<void(std::uint32_t, const Aabb&)>& cover, FrameStats& stats) {
    const int eye_count = eyes.eye_count;
    const bool multiview = eyes.strategy == EyeStrategy::kMultiview;
    const std::uint32_t eyes_drawn = eye_count == 1 ? 0b01u : 0b11u;
    const std::size_t ng = scene.tile_groups.size();
    const bool use_groups = scene.lod && ng > 0;

    // Per eye: the level of each group and whether an enclosing group covers it. Multiview draws both eyes
    // with one choice: that of the larger projection (the finer level).
    std::array<std::vector<std::size_t>, 2> group_level;
    std::array<std::vector<std::uint8_t>, 2> group_covered;
    std::array<std::vector<double>, 2> px;  // per eye and group: pixels_per_metre of its bounds
    std::vector<std::uint8_t> stands_in;
    if (use_groups) {
        stands_in = groups_standing_in(scene.tile_groups);
        for (int e = 0; e < eye_count; ++e) {
            px[e].resize(ng);
            for (std::size_t g = 0; g < ng; ++g) px[e][g] = pixels_per_metre(eyes.lod_eyes[e], scene.tile_groups[g].bounds_m);
        }
        if (multiview && eye_count == 2)
            for (std::size_t g = 0; g < ng; ++g) px[0][g] = px[1][g] = std::max(px[0][g], px[1][g]);
        for (int e = 0; e < eye_count; ++e)
            group_level[e] = choose_group_levels(scene.tile_groups, px[e], scene.lod_max_px, group_covered[e]);
    }
    const auto group_takes = [&](int e, std::size_t g) { return group_level[e][g] > 0 || group_covered[e][g] != 0; };

    // Groups drawn in place of their tiles; those whose joined neighbours all draw the same depth's coarse contour
    // draw only their own triangles (groups_drawn_own_only).
    if (use_groups) {
        std::vector<std::uint32_t> group_visible(ng, 0);  // eye bits
        std::array<std::vector<std::uint8_t>, 2> own_only;
        for (std::size_t g = 0; g < ng; ++g) {
            for (int e = 0; e < eye_count; ++e)
                if (!scene.cull_tiles || may_be_visible(eyes.frusta[e], scene.tile_groups[g].bounds_m))
                    group_visible[g] |= 1u << e;
            if (multiview && group_visible[g] != 0) group_visible[g] = eyes_drawn;
        }
        for (int e = 0; e < eye_count; ++e) {
            std::vector<std::uint8_t> seen(ng);
            for (std::size_t g = 0; g < ng; ++g) seen[g] = (group_visible[g] >> e) & 1u;
            own_only[e] = groups_drawn_own_only(scene.tile_groups, group_level[e], seen);
        }
        for (std::size_t g = 0; g < ng; ++g) {
            const TileGroup& group = scene.tile_groups[g];
            const std::uint32_t visible = group_visible[g];
            std::array<std::uint32_t, 2> mask{};  // per level drawn: the eyes drawing it
            bool wanting = false;
            bool within = false;  // an eye drew it within the pixel bound (not standing in over it)
            for (int e = 0; e < eye_count; ++e)
                within = within || level_within_bound(group, group_level[e][g], px[e][g], scene.lod_max_px);
            if (within) stats.groups_at_level.push_back(group.id);
            for (int e = 0; e < eye_count; ++e)
                if ((visible & (1u << e)) && group_level[e][g] > 0) {
                    ++stats.groups_drawn[e];
                    mask[e] = 1u << e;
                    wanting = wanting || wants_detail(group, group_level[e][g], px[e][g], scene.lod_max_px, stands_in[g] != 0);
                }
            if (wanting) stats.groups_wanting_detail.push_back(group.id);
            if (eye_count == 2 && mask[0] && mask[1] && group_level[0][g] == group_level[1][g] &&
                own_only[0][g] == own_only[1][g]) {
                mask[0] = 0b11u;
                mask[1] = 0;
            }
            for (int e = 0; e < 2; ++e) {
                if (mask[e] == 0) continue;
                const std::size_t level = group_level[e][g];
                const GpuMesh& m = groups.need(g, level);
                const std::size_t own = group.levels[level - 1].own_triangles;
                const std::uint32_t indices =
                    own_only[e][g] && 3 * own <= m.index_count() ? static_cast<std::uint32_t>(3 * own) : m.index_count();
                for (int f = 0; f < eye_count; ++f)
                    if (mask[e] & (1u << f)) {
                        stats.tile_triangles[f] += indices / 3;
                        if (indices != m.index_count()) ++stats.groups_own_only[f];
                    }
                if (indices == 0) continue;
                cover(mask[e], group.bounds_m);
                StereoDraw& d = add(m);
                d.index_count = indices;
                d.constants.palette = 1u;
                d.eye_mask = mask[e];
            }
        }
        std::sort(stats.groups_wanting_detail.begin(), stats.groups_wanting_detail.end());
        std::sort(stats.groups_at_level.begin(), stats.groups_at_level.end());
    }

    for (std::size_t i = 0; i < scene.tiles.size(); ++i) {
        const TileMesh& tile = scene.tiles[i];
        if (!tile.mesh || tile.mesh->triangles.empty()) continue;  // empty tiles are neither drawn nor skipped
        std::uint32_t mask = 0;
        for (int e = 0; e < eye_count; ++e)
            if (!scene.cull_tiles || may_be_visible(eyes.frusta[e], tile.bounds_m)) mask |= 1u << e;
        // Multiview cannot draw one view only: a tile either eye sees is drawn in both.
        if (multiview && mask != 0) mask = eyes_drawn;
        for (int e = 0; e < eye_count; ++e) ++((mask & (1u << e)) ? stats.tiles[e].drawn : stats.tiles[e].skipped);
        if (use_groups && tile.group != TileMesh::kNoGroup) {
            if (tile.group >= ng)
                throw Error("renderer: SceneView.tiles[" + std::to_string(i) + "].group " + std::to_string(tile.group) +
                            " is not a tile_groups index");
            for (int e = 0; e < eye_count; ++e)
                if (group_takes(e, tile.group)) mask &= ~(1u << e);  // a group draws this tile's surface
        }
        if (mask == 0) continue;
        cover(mask, tile.bounds_m);
        // Level of detail per eye; multiview draws both eyes with one level (the finer).
        std::array<std::size_t, 2> level{0, 0};
        if (scene.lod && !tile.levels.empty()) {
            for (int e = 0; e < eye_count; ++e)
                if (mask & (1u << e))
                    level[e] = choose_level(tile.levels, pixels_per_metre(eyes.lod_eyes[e], tile.bounds_m), scene.lod_max_px);
            if (multiview) level[0] = level[1] = std::min(level[0], level[1]);
        }
        const bool one_draw = mask != 0b11u || level[0] == level[1];
        for (int e = 0; e < 2; ++e) {
            const std::uint32_t eye_bit = 1u << e;
            if (!(mask & eye_bit)) continue;
            const GpuMesh& m = tiles.need(i, level[e]);
            for (int f = 0; f < eye_count; ++f)
                if ((one_draw ? mask : eye_bit) & (1u << f)) stats.tile_triangles[f] += m.index_count() / 3;
            if (m.index_count() != 0) {
                StereoDraw& d = add(m);
                d.constants.palette = tile.materials ? 1u : 0u;
                d.eye_mask = one_draw ? mask : eye_bit;
            }
            if (one_draw) break;
        }
    }
}

void add_indirect_tile_draws(const SceneView& scene, const TileDrawEyes& eyes, FrameDraws& list, FrameStats& stats) {
    const IndirectWorkpiece* iw = scene.indirect_workpiece;
    if (!iw || iw->tiles.empty()) return;
    if (iw->vertices == VK_NULL_HANDLE || iw->indices == VK_NULL_HANDLE || iw->commands == VK_NULL_HANDLE)
        throw Error("renderer: SceneView.indirect_workpiece has a null buffer");
    const int eye_count = eyes.eye_count;
    const std::uint32_t eyes_drawn = eye_count == 1 ? 0b01u : 0b11u;
    for (const IndirectTile& t : iw->tiles) {
        if (t.index_count == 0) continue;
        std::uint32_t mask = 0;
        for (int e = 0; e < eye_count; ++e)
            if (!scene.cull_tiles || may_be_visible(eyes.frusta[e], t.bounds_m)) mask |= 1u << e;
        if (eyes.strategy == EyeStrategy::kMultiview && mask != 0) mask = eyes_drawn;
        for (int e = 0; e < eye_count; ++e) {
            ++((mask & (1u << e)) ? stats.tiles[e].drawn : stats.tiles[e].skipped);
            if (mask & (1u << e)) stats.tile_triangles[e] += t.index_count / 3;
        }
        if (mask == 0) continue;
        list.cover(mask, placed(t.bounds_m, scene.workpiece_pose));
        StereoDraw d;
        d.kind = PipelineKind::kContour;
        d.vertices = iw->vertices;
        d.indices = iw->indices;
        d.index_count = t.index_count;
        d.indirect = iw->commands;
        d.indirect_offset = static_cast<VkDeviceSize>(t.id) * kIndirectCommandBytes;
        d.constants.world_from_model = glm::mat4(scene.workpiece_pose.matrix()) * iw->world_from_grid;
        d.constants.colour = palette_colours(scene.palette)[0];
        d.constants.lit = 1u;
        d.constants.palette = 1u;
        d.eye_mask = mask;
        list.add(d);
    }
}

}  // namespace tridex::renderer
