// tests/app/test_tile_group_lod_render.cpp - the contoured bunny drawn with levels of detail over tiles and groups
// of tiles against its full-resolution render: groups are drawn, the silhouette stays within half a percent of
// the pixels, no background shows through the surface (no cracks), and the validation layer stays silent; at the
// desk (the default scene, levels built on the background worker) the colours stay within a stated tolerance too.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <map>
#include <string>
#include <thread>
#include <utility>

#include "app/commands/demo/demo.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "app/session/view/tile_view.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "gpu/context.hpp"
#include "lod_render_compare.hpp"
#include "renderer/camera/display_config.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {
namespace {

// Directed edges of `m` without their reverse (a closed, consistently oriented mesh has none), and whether some
// directed edge occurs twice.
std::size_t open_edges(const TriMesh& m, bool& repeated) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> count;
    for (const auto& t : m.triangles)
        for (int i = 0; i < 3; ++i) ++count[{t[i], t[(i + 1) % 3]}];
    std::size_t open = 0;
    repeated = false;
    for (const auto& [e, c] : count) {
        if (c > 1) repeated = true;
        if (!count.contains({e.second, e.first})) ++open;
    }
    return open;
}

TEST(TileGroupLodRender, GroupsDrawnWithinTheSilhouetteBoundAndWithoutCracks) {
    gpu::ContextOptions opt;
    opt.validation = true;
    gpu::Context ctx = gpu::Context::create(opt);
    Workpiece wp = prepare_workpiece(default_mesh_path(), 128, 0.3, Vec3(0.0, 0.0, 0.3));
    compute::Contourer contourer(wp.model);
    contourer.update(wp.model);
    compute::TileSurfaceCache cache;
    compute::TileLodOptions o;
    o.cell_m = wp.model.lattice.cell_m;
    cache.enable_lod(o);
    cache.refresh(contourer);
    ASSERT_FALSE(cache.groups().empty());
    // No level opens its group: its open edges are the full group's border (kept exactly), so the levels of a
    // closed group are closed and neighbours meet without cracks.
    for (const compute::TileGroupSurface& g : cache.groups()) {
        if (g.lods.empty()) continue;
        bool repeated = false;
        const std::size_t border = open_edges(g.lods[0].mesh, repeated);
        for (const compute::TileLodLevel& l : g.lods) {
            EXPECT_EQ(open_edges(l.mesh, repeated), border) << "group " << g.id;
            EXPECT_FALSE(repeated) << "group " << g.id;
        }
    }
    TileView view;
    tile_view_of(cache.tiles(), cache.groups(), true, view);

    renderer::OffscreenStereoRenderer r = renderer::OffscreenStereoRenderer::create(ctx, 640, 360);
    renderer::SceneView scene;
    scene.show_workspace = false;
    Pose head;
    head.position = Vec3(0.0, 0.15, 0.65);
    const renderer::StereoImages empty = r.render(scene, renderer::Screen::powerwall(), head, 0.065);
    const std::uint8_t bg[3] = {empty.left.rgba[0], empty.left.rgba[1], empty.left.rgba[2]};
    scene.tiles = view.tiles;
    scene.tile_groups = view.groups;
    // Near and far heads: a far head lets whole groups stand in for their tiles.
    for (const double z : {0.65, 1.6}) {
        head.position = Vec3(0.0, 0.15, z);
        scene.lod = true;
        const renderer::StereoImages lod = r.render(scene, renderer::Screen::powerwall(), head, 0.065);
        scene.lod = false;
        const renderer::StereoImages full = r.render(scene, renderer::Screen::powerwall(), head, 0.065);
        const LodImageDiff d = compare_lod_images(lod, full, bg);
        const double mismatch = static_cast<double>(d.mismatched) / static_cast<double>(d.pixels);
        std::printf("head z %.2f m: groups drawn L %zu R %zu, triangles L %zu of %zu, silhouette mismatch %.4f%%, "
                    "holes %zu\n",
                    z, lod.stats.groups_drawn[0], lod.stats.groups_drawn[1], lod.stats.tile_triangles[0],
                    full.stats.tile_triangles[0], 100.0 * mismatch, d.holes);
        EXPECT_GT(lod.stats.groups_drawn[0], 0u) << "z " << z;
        EXPECT_GT(lod.stats.groups_drawn[1], 0u) << "z " << z;
        EXPECT_EQ(full.stats.groups_drawn[0], 0u);
        EXPECT_LT(2 * lod.stats.tile_triangles[0], full.stats.tile_triangles[0]) << "z " << z;
        EXPECT_LE(mismatch, 0.005) << "z " << z;
        // Near, tiles and groups meet on screen, where a crack between them would show; far, one closed level
        // (checked above) stands for the whole model, and a lone background pixel is its own geometry (a narrow
        // concavity the level widens within its error bound), not a crack.
        EXPECT_LE(d.holes, z < 1.0 ? 0u : 2u) << "z " << z;
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// The default scene at the desk (its bunny, 128 cells over 0.12 m, on the desktop monitor, 960x540 per eye, mono and
// stereo), its levels built on the background worker as `tridex run` builds them: with levels the image matches the
// full-resolution one within half a percent of silhouette pixels, a mean difference of 1.5 codes per channel and
// 1 % of pixels visibly different (a channel more than 48 codes off: shading on a coarser facet), and no cracks.
TEST(TileGroupLodRender, DeskViewWithBackgroundLevelsMatchesFullResolution) {
    gpu::ContextOptions opt;
    opt.validation = true;
    gpu::Context ctx = gpu::Context::create(opt);
    Workpiece wp = prepare_workpiece(default_mesh_path(), 128, 0.12, Vec3(0.0, 0.0, 0.05));
    compute::Contourer contourer(wp.model);
    contourer.update(wp.model);
    compute::TileSurfaceCache cache;
    compute::TileLodOptions o;
    o.cell_m = wp.model.lattice.cell_m;
    cache.enable_lod(o);
    cache.build_lods_in_background();
    cache.refresh(contourer);
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (cache.lod_pending() > 0 && std::chrono::steady_clock::now() < limit) {
        cache.collect_lods();
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ASSERT_EQ(cache.lod_pending(), 0u);
    TileView view;
    tile_view_of(cache.tiles(), cache.groups(), true, view);

    renderer::OffscreenStereoRenderer r = renderer::OffscreenStereoRenderer::create(ctx, 960, 540);
    renderer::SceneView scene;
    scene.show_workspace = false;
    const renderer::Screen screen = renderer::Screen::desktop_monitor();
    Pose head;
    head.position = Vec3(0.0, 0.05, 0.6);
    const renderer::StereoImages empty = r.render(scene, screen, head, 0.065);
    const std::uint8_t bg[3] = {empty.left.rgba[0], empty.left.rgba[1], empty.left.rgba[2]};
    scene.tiles = view.tiles;
    scene.tile_groups = view.groups;
    for (const int eyes : {1, 2}) {
        scene.eye_count = eyes;
        scene.lod = true;
        const renderer::StereoImages lod = r.render(scene, screen, head, 0.065);
        scene.lod = false;
        const renderer::StereoImages full = r.render(scene, screen, head, 0.065);
        expect_desk_match(lod, full, bg, "desk, " + std::to_string(eyes) + " eye(s)");
        EXPECT_LT(lod.stats.tile_triangles[0], full.stats.tile_triangles[0]) << "eyes " << eyes;
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::app
