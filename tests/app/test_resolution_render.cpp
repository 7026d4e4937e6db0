// tests/app/test_resolution_render.cpp - the bunny scan-converted at N = 128, 256, 512 and 1024 and drawn from the
// desk (desktop monitor, 960x540, the head 0.6 m from the screen, mono) looks the same at every N: against N = 1024,
// the silhouette differs in at most 1 % of the bunny's own pixels, at most 1 % of them are visibly different (a
// channel more than 48 codes off), and no background shows through. A finer lattice adds detail a pixel at this
// distance hardly shows. The images are written to the test's folder (TMPDIR/tridex_resolution_render) to be looked
// at.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

#include "app/scene/workpiece_source.hpp"
#include "app/session/view/tile_view.hpp"
#include "app/support/assets.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "gpu/context.hpp"
#include "lod_render_compare.hpp"
#include "renderer/camera/display_config.hpp"
#include "renderer/image/image.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {
namespace {

// The bunny at N cells, drawn from the desk at full resolution (every tile's own mesh).
renderer::StereoImages desk_render(renderer::OffscreenStereoRenderer& r, int n, std::size_t& triangles) {
    Workpiece wp = prepare_workpiece(default_mesh_path(), n, 0.12, Vec3(0.0, 0.0, 0.05));
    compute::Contourer contourer(wp.model);
    contourer.update(wp.model);
    compute::TileSurfaceCache cache;
    cache.refresh(contourer);
    TileView view;
    tile_view_of(cache.tiles(), cache.groups(), false, view);
    renderer::SceneView scene;
    scene.show_workspace = false;
    scene.tiles = view.tiles;
    scene.eye_count = 1;
    Pose head;
    head.position = Vec3(0.0, 0.05, 0.6);
    renderer::StereoImages im = r.render(scene, renderer::Screen::desktop_monitor(), head, 0.065);
    triangles = im.stats.tile_triangles[0];
    return im;
}

TEST(ResolutionRender, TheBunnyLooksTheSameFromTheDeskAtEveryN) {
    gpu::ContextOptions opt;
    opt.validation = true;
    gpu::Context ctx = gpu::Context::create(opt);
    renderer::OffscreenStereoRenderer r = renderer::OffscreenStereoRenderer::create(ctx, 960, 540);
    renderer::SceneView nothing;
    nothing.show_workspace = false;
    Pose head;
    head.position = Vec3(0.0, 0.05, 0.6);
    const renderer::StereoImages empty = r.render(nothing, renderer::Screen::desktop_monitor(), head, 0.065);
    const std::uint8_t bg[3] = {empty.left.rgba[0], empty.left.rgba[1], empty.left.rgba[2]};
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "tridex_resolution_render";
    std::filesystem::create_directories(dir);
    std::size_t reference_triangles = 0;
    const renderer::StereoImages reference = desk_render(r, 1024, reference_triangles);
    renderer::write_png((dir / "bunny_1024.png").string(), reference.left);
    std::size_t bunny_pixels = 0;  // the reference's pixels that are not background
    for (std::size_t i = 0; i + 3 < reference.left.rgba.size(); i += 4)
        bunny_pixels += !std::equal(bg, bg + 3, reference.left.rgba.data() + i);
    ASSERT_GT(bunny_pixels, 10000u);
    for (const int n : {128, 256, 512}) {
        std::size_t triangles = 0;
        const renderer::StereoImages im = desk_render(r, n, triangles);
        renderer::write_png((dir / ("bunny_" + std::to_string(n) + ".png")).string(), im.left);
        const LodImageDiff d = compare_lod_images(im, reference, bg);
        const double mismatch = static_cast<double>(d.mismatched) / static_cast<double>(bunny_pixels);
        const double far_off = static_cast<double>(d.far_off) / static_cast<double>(bunny_pixels);
        std::printf("[resolution render] N %d (%zu triangles) against N 1024 (%zu), of the bunny's %zu pixels: "
                    "silhouette mismatch %.3f%%, visibly different %.3f%%, holes %zu\n",
                    n, triangles, reference_triangles, bunny_pixels, 100.0 * mismatch, 100.0 * far_off, d.holes);
        EXPECT_LE(mismatch, 0.01) << n;
        EXPECT_LE(far_off, 0.01) << n;
        EXPECT_EQ(d.holes, 0u) << n;
        EXPECT_LT(triangles, reference_triangles) << n;
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::app
