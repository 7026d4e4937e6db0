// tests/app/test_coarse_group_render.cpp - the bunny at N = 256 and 512 drawn with group levels contoured from the
// model read at coarser strides (TileSurfaceCache::use_coarse_groups) against its full-resolution render: groups
// are drawn, far fewer triangles, the silhouette within half a percent of the pixels, colours within the desk test's
// tolerance, no background through the surface where a ring and a skirt meet a neighbour (no cracks), validation on.
#include <gtest/gtest.h>

#include <algorithm>

#include <chrono>
#include <cstdio>
#include <map>
#include <thread>
#include <utility>
#include <vector>

#include "app/scene/workpiece_source.hpp"
#include "app/session/view/tile_view.hpp"
#include "app/support/assets.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/tools/boolean.hpp"
#include "core/segment.hpp"
#include "gpu/context.hpp"
#include "lod_render_compare.hpp"
#include "renderer/camera/display_config.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {
namespace {

struct Coarse {
    Workpiece wp;
    compute::Contourer contourer;
    compute::TileSurfaceCache cache;
    TileView view;

    explicit Coarse(int n) : wp(prepare_workpiece(default_mesh_path(), n, 0.12, Vec3(0.0, 0.0, 0.05))), contourer(wp.model) {
        contourer.update(wp.model);
        compute::TileLodOptions o;
        o.cell_m = wp.model.lattice.cell_m;
        cache.enable_lod(o);
        cache.use_coarse_groups(wp.model);
        cache.build_lods_in_background();  // the tiles' own levels, as `tridex run` builds them
        cache.refresh(contourer);
        const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(180);
        while ((cache.lod_pending() > 0 || cache.coarse_waiting() > 0) && std::chrono::steady_clock::now() < limit) {
            cache.collect_lods();
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        EXPECT_EQ(cache.lod_pending(), 0u);
        EXPECT_EQ(cache.coarse_waiting(), 0u);
        tile_view_of(cache.tiles(), cache.groups(), true, view);
    }
};

// A 960x540 offscreen renderer with validation on, and the desk's screen.
gpu::ContextOptions validated() {
    gpu::ContextOptions opt;
    opt.validation = true;
    return opt;
}

struct Desk {
    gpu::Context ctx = gpu::Context::create(validated());
    renderer::OffscreenStereoRenderer r = renderer::OffscreenStereoRenderer::create(ctx, 960, 540);
    renderer::Screen screen = renderer::Screen::desktop_monitor();
};

// The desk (desktop monitor, 960x540, mono and stereo) and a close head 0.3 m from the screen, where groups of every
// depth meet tiles drawn at full resolution or at their own levels.
TEST(CoarseGroupRender, TheBunnyAt256And512MatchesItsFullResolutionRender) {
    Desk desk;
    gpu::Context& ctx = desk.ctx;
    renderer::OffscreenStereoRenderer& r = desk.r;
    const renderer::Screen& screen = desk.screen;
    std::map<std::pair<double, int>, std::size_t> drawn;  // per view: the triangles drawn at N = 256
    for (const int n : {256, 512}) {
        const Coarse c(n);
        renderer::SceneView scene;
        scene.show_workspace = false;
        Pose head;
        head.position = Vec3(0.0, 0.05, 0.6);
        const renderer::StereoImages empty = r.render(scene, screen, head, 0.065);
        const std::uint8_t bg[3] = {empty.left.rgba[0], empty.left.rgba[1], empty.left.rgba[2]};
        scene.tiles = c.view.tiles;
        scene.tile_groups = c.view.groups;
        for (const double z : {0.6, 0.3})
            for (const int eyes : {1, 2}) {
                head.position = Vec3(0.02, 0.06, z);
                scene.eye_count = eyes;
                scene.lod = true;
                const renderer::StereoImages lod = r.render(scene, screen, head, 0.065);
                scene.lod = false;
                const renderer::StereoImages full = r.render(scene, screen, head, 0.065);
                char what[64];
                std::snprintf(what, sizeof what, "[coarse render] N %d, head z %.1f m, %d eye(s)", n, z, eyes);
                expect_desk_match(lod, full, bg, what);
                EXPECT_GT(lod.stats.groups_drawn[0], 0u) << n << " " << z;
                if (z > 0.5) {
                    // At the desk's distance most groups meet neighbours of their own depth: they draw only their own
                    // triangles. Every group with its ring and skirt draws the same picture with more triangles.
                    EXPECT_GT(lod.stats.groups_own_only[0], 0u) << n;
                    std::vector<renderer::TileGroup> closed(c.view.groups.begin(), c.view.groups.end());
                    for (renderer::TileGroup& g : closed) g.neighbours = renderer::TileGroup::no_neighbours();
                    scene.tile_groups = closed;
                    scene.lod = true;
                    const renderer::StereoImages rings = r.render(scene, screen, head, 0.065);
                    scene.tile_groups = c.view.groups;
                    std::snprintf(what, sizeof what, "[coarse render] N %d, %d eye(s), own only vs rings", n, eyes);
                    expect_desk_match(lod, rings, bg, what);
                    EXPECT_EQ(rings.stats.groups_own_only[0], 0u);
                    EXPECT_LT(lod.stats.tile_triangles[0], rings.stats.tile_triangles[0]) << n;
                    std::printf("[coarse render] N %d, %d eye(s): %zu of %zu groups own only, %zu triangles (%zu with "
                                "every ring and skirt)\n",
                                n, eyes, lod.stats.groups_own_only[0], lod.stats.groups_drawn[0],
                                lod.stats.tile_triangles[0], rings.stats.tile_triangles[0]);
                }
                EXPECT_LT(2 * lod.stats.tile_triangles[0], full.stats.tile_triangles[0]) << n << " " << z;
                // The cost follows the pixels, not N: the same view draws about as many triangles at every N.
                auto& first = drawn[{z, eyes}];
                if (first == 0) first = lod.stats.tile_triangles[0];
                EXPECT_LT(double(lod.stats.tile_triangles[0]), 1.5 * double(first)) << n << " " << z;
            }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// A cut drops the finer groups' levels until they are rebuilt, while its tiles are all contoured. A close view then
// draws the enclosing groups over the bound (and names them as wanting detail) rather than the cut region's tiles at
// full resolution; once the levels are back, the bound decides again and no group wants detail.
TEST(CoarseGroupRender, GroupsStandInForLevelsACutDroppedUntilTheyAreRebuilt) {
    Desk desk;
    gpu::Context& ctx = desk.ctx;
    renderer::OffscreenStereoRenderer& r = desk.r;
    const renderer::Screen& screen = desk.screen;
    Coarse c(256);
    const compute::Lattice& L = c.wp.model.lattice;
    const Vec3 mid = L.to_world(0.5 * Vec3(L.cells[0], L.cells[1], L.cells[2]));
    compute::subtract_capsule(c.wp.model, Segment{mid - Vec3(0.1, 0.0, 0.0), mid + Vec3(0.1, 0.0, 0.0)}, 0.01);
    c.contourer.update(c.wp.model);
    c.cache.refresh(c.contourer);
    std::size_t waiting = 0;
    for (const compute::TileGroupSurface& g : c.cache.groups()) waiting += g.levels_waiting ? 1 : 0;
    ASSERT_GT(waiting, 0u);
    renderer::SceneView scene;
    scene.show_workspace = false;
    scene.lod = true;
    Pose head;
    head.position = Vec3(0.02, 0.06, 0.3);
    TileView view;
    const auto render = [&] {
        tile_view_of(c.cache.tiles(), c.cache.groups(), true, view);
        scene.tiles = view.tiles;
        scene.tile_groups = view.groups;
        return r.render(scene, screen, head, 0.065).stats;
    };
    const renderer::FrameStats standing = render();
    EXPECT_FALSE(standing.groups_wanting_detail.empty());
    // A group standing in over the bound is not among those drawn within it (what a stroke's rebuild reads).
    EXPECT_TRUE(std::is_sorted(standing.groups_at_level.begin(), standing.groups_at_level.end()));
    for (const std::uint64_t id : standing.groups_wanting_detail) {
        EXPECT_FALSE(std::binary_search(standing.groups_at_level.begin(), standing.groups_at_level.end(), id)) << id;
    }
    // The same view if the waiting levels were not stood in for: their tiles, at full resolution where they have no
    // level of their own yet.
    for (renderer::TileGroup& g : view.groups) g.levels_waiting = false;
    const renderer::FrameStats descended = r.render(scene, screen, head, 0.065).stats;
    EXPECT_LT(standing.tile_triangles[0], descended.tile_triangles[0]);
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(180);
    while ((c.cache.lod_pending() > 0 || c.cache.coarse_waiting() > 0) && std::chrono::steady_clock::now() < limit) {
        c.cache.collect_lods();
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ASSERT_EQ(c.cache.coarse_waiting(), 0u);
    const renderer::FrameStats settled = render();
    EXPECT_TRUE(settled.groups_wanting_detail.empty());
    // Nothing stands in now: every group drawn is drawn within the bound, and so named.
    EXPECT_GT(settled.groups_drawn[0], 0u);
    EXPECT_GE(settled.groups_at_level.size(), settled.groups_drawn[0]);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::app
