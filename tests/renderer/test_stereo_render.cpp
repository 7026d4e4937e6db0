// Tests of OffscreenStereoRenderer on lavapipe: golden image, disparity, strategies agree, errors.
#include <gtest/gtest.h>

#include <limits>

#include <cstdlib>
#include <filesystem>

#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/stereo/eye_strategy.hpp"
#include "renderer/image/image.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr int kW = 96, kH = 72;
constexpr double kEyeSeparation = 0.065;
// Golden tolerance: every channel within 3 (of 255) on at least 99.5 % of the pixels.
constexpr int kChannelTolerance = 3;
constexpr double kMinFractionWithin = 0.995;

std::filesystem::path output_dir() {
    const auto dir = std::filesystem::current_path() / "renderer_out";
    std::filesystem::create_directories(dir);
    return dir;
}

std::filesystem::path golden_path(const char* name) {
    const char* data = std::getenv("TRIDEX_TEST_DATA");
    return std::filesystem::path(data ? data : "tests/data") / "golden" / name;
}

std::size_t differing_pixels(const Image& a, const Image& b) {
    const ImageComparison c = compare_images(a, b, 0);
    return c.pixels - c.within;
}

TEST(StereoRender, GoldenCubeBallAndWorkspaceBox) {
    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
        const TriMesh cube = test::test_cube();
        const StereoImages eyes = r.render(test::test_scene(cube), test::small_screen(), test::test_head(),
                                           kEyeSeparation);
        const Image actual = side_by_side(eyes.left, eyes.right);
        const auto out = output_dir();
        write_png((out / "stereo_golden_actual.png").string(), actual);

        const auto golden_file = golden_path("stereo_cube_ball_box_96x72.png");
        ASSERT_TRUE(std::filesystem::exists(golden_file))
            << "missing golden " << golden_file << "; candidate written to " << out / "stereo_golden_actual.png";
        const Image golden = read_png(golden_file.string());
        const ImageComparison c = compare_images(actual, golden, kChannelTolerance);
        std::printf("[golden] %zu/%zu pixels within %d, max channel diff %d (strategy %s)\n", c.within, c.pixels,
                    kChannelTolerance, c.max_channel_diff, std::string(to_string(r.strategy())).c_str());
        if (c.fraction_within() < kMinFractionWithin) {
            write_png((out / "stereo_golden_diff.png").string(), difference_image(actual, golden, kChannelTolerance));
            ADD_FAILURE() << "golden mismatch: " << c.fraction_within() * 100.0 << " % within tolerance; see "
                          << out / "stereo_golden_diff.png";
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(StereoRender, AllWorkingStrategiesDrawTheSameImages) {
    gpu::Context ctx = gpu::Context::create({});
    {
        const TriMesh cube = test::test_cube();
        StereoImages reference;
        bool have_reference = false;
        for (EyeStrategy s : {EyeStrategy::kPassPerEye, EyeStrategy::kMultiview, EyeStrategy::kInstancedLayer}) {
            OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH, s);
            if (r.strategy() != s) continue;  // fell back; its self-test failed
            const StereoImages e = r.render(test::test_scene(cube), test::small_screen(), test::test_head(),
                                            kEyeSeparation);
            if (!have_reference) {
                reference = e;
                have_reference = true;
                continue;
            }
            EXPECT_EQ(differing_pixels(e.left, reference.left), 0u) << to_string(s);
            EXPECT_EQ(differing_pixels(e.right, reference.right), 0u) << to_string(s);
        }
        EXPECT_TRUE(have_reference);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(StereoRender, ResizedRendererDrawsWhatAFreshOneOfThatSizeDraws) {
    gpu::Context ctx = gpu::Context::create({});
    {
        const TriMesh cube = test::test_cube();
        SceneView view = test::test_scene(cube);
        view.show_overlay = true;  // its scale follows the image height
        view.frame_time_ms = 10.0;  // the same text in both renderers
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
        (void)r.render(view, test::small_screen(), test::test_head(), kEyeSeparation);
        EXPECT_EQ(r.target_generation(), 0u);
        r.resize(kW + 40, kH / 2);
        EXPECT_EQ(r.target_generation(), 1u);
        EXPECT_EQ(r.width(), kW + 40);
        EXPECT_EQ(r.height(), kH / 2);
        EXPECT_THROW((void)r.last_images(), Error);  // the new target holds no frame yet
        const StereoImages resized = r.render(view, test::small_screen(), test::test_head(), kEyeSeparation);
        OffscreenStereoRenderer fresh = OffscreenStereoRenderer::create(ctx, kW + 40, kH / 2);
        const StereoImages want = fresh.render(view, test::small_screen(), test::test_head(), kEyeSeparation);
        ASSERT_EQ(resized.left.width, kW + 40);
        ASSERT_EQ(resized.left.height, kH / 2);
        EXPECT_EQ(differing_pixels(resized.left, want.left), 0u);
        EXPECT_EQ(differing_pixels(resized.right, want.right), 0u);
        r.resize(kW + 40, kH / 2);  // the same size: nothing changes, the last frame stays readable
        EXPECT_EQ(r.target_generation(), 1u);
        EXPECT_EQ(differing_pixels(r.last_images().left, want.left), 0u);
        EXPECT_THROW(r.resize(0, 10), Error);
        EXPECT_EQ(r.width(), kW + 40);  // a refused size keeps the old target
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(StereoRender, OffPlaneObjectsDifferBetweenEyesScreenPlaneDoesNot) {
    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
        // The ball alone, 10 cm in front of the screen: the two eyes see it at different places.
        SceneView ball;
        ball.tool_centre_m = Vec3(0.0, 0.0, 0.1);
        ball.tool_radius_m = 0.03;
        ball.show_workspace = false;
        const StereoImages a = r.render(ball, test::small_screen(), test::test_head(), kEyeSeparation);
        EXPECT_GT(differing_pixels(a.left, a.right), 50u);

        // A flat (zero-thickness, unlit) workspace box lying in the screen plane: zero disparity, so the
        // two eyes' images are identical pixel for pixel.
        SceneView flat;
        flat.workspace_m.add(Vec3(-0.1, -0.05, 0.0));
        flat.workspace_m.add(Vec3(0.12, 0.08, 0.0));
        const StereoImages b = r.render(flat, test::small_screen(), test::test_head(), kEyeSeparation);
        EXPECT_EQ(differing_pixels(b.left, b.right), 0u);
        const Image clear = r.render(SceneView{}, test::small_screen(), test::test_head(), kEyeSeparation).left;
        EXPECT_GT(differing_pixels(b.left, clear), 1000u);  // the box was drawn at all
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(StereoRender, BubbleIsATranslucentSphereAroundItsCentre) {
    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 64, 48);
        const Screen screen = test::small_screen();
        const Pose head = test::test_head();
        SceneView v;
        v.bubble_centre_m = Vec3(0.0, 0.0, 0.05);
        v.bubble_radius_m = 0.06;
        const StereoImages with = r.render(v, screen, head, kEyeSeparation);
        const StereoImages without = r.render(SceneView{}, screen, head, kEyeSeparation);
        // The bubble tints the middle of the image, translucently (not the opaque tool colour), and
        // leaves the corners as the clear colour.
        const auto px = [](const Image& img, int x, int y) { return img.at(x, y); };
        const auto mid = px(with.left, 32, 24), mid_clear = px(without.left, 32, 24);
        EXPECT_GT(mid[2], mid_clear[2]);        // bluer
        EXPECT_LT(mid[2], 120);                 // but see-through (alpha 0.15 over a dark background)
        for (int k = 0; k < 4; ++k) EXPECT_EQ(px(with.left, 0, 0)[k], px(without.left, 0, 0)[k]) << k;
        v.bubble_radius_m = std::numeric_limits<double>::infinity();
        EXPECT_THROW(r.render(v, screen, head, kEyeSeparation), Error);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(StereoRender, EmptySceneIsTheClearColour) {
    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 20, 10);
        const StereoImages e = r.render(SceneView{}, Screen::powerwall(), Pose{Vec3(0.0, 0.0, 2.0)}, 0.065);
        // Clear colour (0.08, 0.09, 0.11, 1) in UNORM8: round(x * 255) = (20, 23, 28, 255).
        for (const Image* img : {&e.left, &e.right}) {
            ASSERT_EQ(img->width, 20);
            ASSERT_EQ(img->height, 10);
            EXPECT_EQ(compare_images(*img, Image::filled(20, 10, 20, 23, 28, 255), 0).within, 200u);
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(StereoRender, BadInputThrowsAndRendererStaysUsable) {
    gpu::Context ctx = gpu::Context::create({});
    {
        EXPECT_THROW(OffscreenStereoRenderer::create(ctx, 0, 10), Error);
        EXPECT_THROW(OffscreenStereoRenderer::create(ctx, 10, 100000), Error);
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 16, 12);
        const Screen s = Screen::powerwall();
        EXPECT_THROW(r.render(SceneView{}, s, Pose{Vec3(0.0, 0.0, -1.0)}, 0.065), Error);  // behind the screen
        EXPECT_THROW(r.render(SceneView{}, s, Pose{Vec3(0.0, 0.0, 2.0)}, -0.065), Error);
        TriMesh broken;
        broken.positions = {Vec3(0.0), Vec3(0.1, 0.0, 0.0), Vec3(0.0, 0.1, 0.0)};
        broken.triangles = {{0u, 1u, 3u}};
        SceneView v;
        v.workpiece = &broken;
        EXPECT_THROW(r.render(v, s, Pose{Vec3(0.0, 0.0, 2.0)}, 0.065), Error);
        const StereoImages ok = r.render(SceneView{}, s, Pose{Vec3(0.0, 0.0, 2.0)}, 0.065);
        EXPECT_EQ(ok.left.width, 16);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
