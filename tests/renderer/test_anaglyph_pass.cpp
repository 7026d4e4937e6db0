// The GPU anaglyph (AnaglyphPass) against the CPU reference compose() on a rendered scene, every method, eyes
// swapped or not, with Vulkan validation on; the renderer's image stays usable after the pass.
#include <gtest/gtest.h>
#include <utility>

#include <cstdio>

#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/output/anaglyph_pass.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/output/stereo_output.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

TEST(AnaglyphPass, MatchesTheCpuComposeWithinOneCodePerChannel) {
    gpu::Context ctx = gpu::Context::create();
    constexpr int kW = 160, kH = 120;
    OffscreenStereoRenderer renderer = OffscreenStereoRenderer::create(ctx, kW, kH);
    const TriMesh cube = test::test_cube();
    SceneView scene = test::test_scene(cube);
    scene.proxy_m = Vec3(0.06, 0.03, 0.06);
    scene.proxy_radius_m = 0.03;  // translucent over lit surfaces: many mixed colours
    const StereoImages eyes = renderer.render(scene, test::small_screen(), test::test_head(), 0.065);
    ASSERT_GT(compare_images(eyes.left, eyes.right, 0).max_channel_diff, 0);

    AnaglyphPass pass = AnaglyphPass::create(ctx, kW, kH);
    for (const AnaglyphMethod method : {AnaglyphMethod::kDubois, AnaglyphMethod::kColour, AnaglyphMethod::kGray}) {
        for (const bool swap : {false, true}) {
            const std::string what = std::string(to_string(method)) + (swap ? " swapped" : "");
            ComposeOptions co;
            co.swap_eyes = swap;
            co.anaglyph = method;
            const Image cpu = compose(StereoOutput::kAnaglyph, eyes.left, eyes.right, co);
            const Image gpu = pass.compose(renderer, method, swap);
            ASSERT_EQ(gpu.width, kW) << what;
            ASSERT_EQ(gpu.height, kH) << what;
            const ImageComparison c = compare_images(gpu, cpu, 0);
            // Dubois mixes in 32-bit floats on the GPU (doubles on the CPU): a value within float rounding of a
            // code boundary may land on the neighbouring code. Colour and gray are integer arithmetic: exact.
            EXPECT_LE(c.max_channel_diff, method == AnaglyphMethod::kDubois ? 1 : 0) << what;
            // Such values are rare: nearly every pixel is the CPU's to the code.
            EXPECT_GE(c.fraction_within(), 0.995) << what;
            std::printf("[anaglyph pass] %s: max channel diff %d, %.4f %% of pixels exact\n", what.c_str(),
                        c.max_channel_diff, 100.0 * c.fraction_within());
        }
    }
    // The pass runs its shader only where the frame drew, and clears the rest to the clear colour's anaglyph: a
    // frame whose items cover part of the image (the cube as a tile, the tool, the translucent proxy).
    TileMesh tile;
    tile.mesh = &cube;
    tile.bounds_m = cube.bounds();
    tile.version = 1;
    SceneView part = scene;
    part.workpiece = nullptr;
    part.tiles = std::span<const TileMesh>(&tile, 1);
    part.show_workspace = false;
    const StereoImages partial = renderer.render(part, test::small_screen(), test::test_head(), 0.065);
    ASSERT_EQ(renderer.last_drawn_rects().size(), 1u);  // no overlay: the items' bounds
    const PixelRect drawn = renderer.last_drawn_rects()[0];
    EXPECT_LT((drawn.x1 - drawn.x0) * (drawn.y1 - drawn.y0), kW * kH);
    for (const AnaglyphMethod method : {AnaglyphMethod::kDubois, AnaglyphMethod::kColour, AnaglyphMethod::kGray}) {
        ComposeOptions co;
        co.anaglyph = method;
        const ImageComparison c = compare_images(pass.compose(renderer, method, false),
                                                 compose(StereoOutput::kAnaglyph, partial.left, partial.right, co), 0);
        EXPECT_LE(c.max_channel_diff, method == AnaglyphMethod::kDubois ? 1 : 0) << to_string(method);
        EXPECT_GE(c.fraction_within(), 0.995) << to_string(method);
    }
    // With the overlay: its panel is a rectangle of its own, and its text comes through the pass too.
    part.show_overlay = true;
    const StereoImages with_overlay = renderer.render(part, test::small_screen(), test::test_head(), 0.065);
    EXPECT_EQ(renderer.last_drawn_rects().size(), 2u);
    {
        ComposeOptions co;
        const ImageComparison c =
            compare_images(pass.compose(renderer, AnaglyphMethod::kDubois, false),
                           compose(StereoOutput::kAnaglyph, with_overlay.left, with_overlay.right, co), 0);
        EXPECT_LE(c.max_channel_diff, 1);
        EXPECT_GE(c.fraction_within(), 0.995);
    }
    // A frame that draws nothing: every pixel is the clear colour's anaglyph, exactly the CPU's.
    SceneView nothing;
    nothing.show_workspace = false;
    const StereoImages bare = renderer.render(nothing, test::small_screen(), test::test_head(), 0.065);
    EXPECT_TRUE(renderer.last_drawn_rects().empty());
    for (const AnaglyphMethod method : {AnaglyphMethod::kDubois, AnaglyphMethod::kColour, AnaglyphMethod::kGray}) {
        ComposeOptions co;
        co.anaglyph = method;
        const Image cpu = compose(StereoOutput::kAnaglyph, bare.left, bare.right, co);
        EXPECT_EQ(compare_images(pass.compose(renderer, method, false), cpu, 0).max_channel_diff, 0)
            << to_string(method);
    }
    // The pass returned the renderer's image to its transfer layout: the next frame renders and reads back as before.
    renderer.render(scene, test::small_screen(), test::test_head(), 0.065);
    const StereoImages again = renderer.render(scene, test::small_screen(), test::test_head(), 0.065);
    EXPECT_EQ(compare_images(again.left, eyes.left, 0).max_channel_diff, 0);
    EXPECT_EQ(compare_images(again.right, eyes.right, 0).max_channel_diff, 0);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(AnaglyphPass, RefusesBadSizesAndARendererWithoutAFrame) {
    gpu::Context ctx = gpu::Context::create();
    EXPECT_THROW(AnaglyphPass::create(ctx, 0, 10), Error);
    EXPECT_THROW(AnaglyphPass::create(ctx, 10, -1), Error);
    OffscreenStereoRenderer renderer = OffscreenStereoRenderer::create(ctx, 32, 24);
    AnaglyphPass pass = AnaglyphPass::create(ctx, 32, 24);
    EXPECT_THROW(pass.compose(renderer, AnaglyphMethod::kDubois, false), Error);  // no frame yet
    AnaglyphPass other = AnaglyphPass::create(ctx, 16, 24);
    const TriMesh cube = test::test_cube();
    (void)renderer.render(test::test_scene(cube), test::small_screen(), test::test_head(), 0.065);
    EXPECT_THROW(other.compose(renderer, AnaglyphMethod::kDubois, false), Error);  // size differs
    EXPECT_EQ(pass.compose(renderer, AnaglyphMethod::kGray, false).width, 32);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// Resized with the renderer's eye images (a window's render scale), the pass composes what a pass made at that size
// composes, and refuses a size out of range.
TEST(AnaglyphPass, AResizedPassComposesWhatAFreshOneOfThatSizeComposes) {
    gpu::Context ctx = gpu::Context::create();
    {
        constexpr int kW = 160, kH = 120;
        OffscreenStereoRenderer renderer = OffscreenStereoRenderer::create(ctx, kW, kH);
        const TriMesh cube = test::test_cube();
        const SceneView scene = test::test_scene(cube);
        (void)renderer.render(scene, test::small_screen(), test::test_head(), 0.065);
        AnaglyphPass pass = AnaglyphPass::create(ctx, kW, kH);
        (void)pass.compose(renderer, AnaglyphMethod::kDubois, false);
        for (const auto& [w, h] : {std::pair{kW * 3 / 4, kH * 3 / 4}, std::pair{kW + 24, kH / 2}}) {
            renderer.resize(w, h);
            (void)renderer.render(scene, test::small_screen(), test::test_head(), 0.065);
            EXPECT_THROW((void)pass.compose(renderer, AnaglyphMethod::kDubois, false), Error)
                << "made for the old size";
            pass.resize(w, h);
            ASSERT_EQ(pass.width(), w);
            ASSERT_EQ(pass.height(), h);
            AnaglyphPass fresh = AnaglyphPass::create(ctx, w, h);
            const Image got = pass.compose(renderer, AnaglyphMethod::kDubois, false);
            const Image want = fresh.compose(renderer, AnaglyphMethod::kDubois, false);
            ASSERT_EQ(got.width, w);
            EXPECT_EQ(compare_images(got, want, 0).max_channel_diff, 0) << w << "x" << h;
        }
        // The renderer's eyes away and back between two composes: the pass keeps its size and binds the new target.
        renderer.resize(kW, kH);
        renderer.resize(kW + 24, kH / 2);
        (void)renderer.render(scene, test::small_screen(), test::test_head(), 0.065);
        pass.resize(kW + 24, kH / 2);
        AnaglyphPass fresh = AnaglyphPass::create(ctx, kW + 24, kH / 2);
        EXPECT_EQ(compare_images(pass.compose(renderer, AnaglyphMethod::kGray, false),
                                 fresh.compose(renderer, AnaglyphMethod::kGray, false), 0)
                      .max_channel_diff,
                  0);
        EXPECT_THROW(pass.resize(0, 10), Error);
        EXPECT_EQ(pass.width(), kW + 24);  // a refused size keeps the pass as it was
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
