// The offscreen stereo sink's policy: eyes drawn per output, frame-sequential presents and eye order, swap,
// and the three PNGs of the last frame (output.png: compose(), anaglyph from the GPU pass).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/output/offscreen_sink.hpp"
#include "renderer/output/stereo_output.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 64, kH = 48;

StereoCamera test_camera() { return StereoCamera{test::small_screen(), test::test_head(), 0.065}; }

fs::path fresh_dir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("tridex_stereo_sink_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

TEST(OffscreenSink, FrameSequentialPresentsTwicePerFrameAndShowsTheLastEye) {
    gpu::Context ctx = gpu::Context::create();
    OffscreenStereoRenderer renderer = OffscreenStereoRenderer::create(ctx, kW, kH);
    const TriMesh cube = test::test_cube();
    for (const bool swap : {false, true}) {
        SinkOptions so;
        so.output = StereoOutput::kFrameSequential;
        so.swap_eyes = swap;
        so.refresh_hz = 120.0;
        OffscreenSink sink(ctx, so);
        EXPECT_EQ(sink.eye_count(), 2);
        EXPECT_EQ(sink.presents_per_frame(), 2);
        EXPECT_EQ(sink.present_mode(), "offscreen");
        EXPECT_TRUE(sink.present_timings().is_null());
        EXPECT_EQ(sink.last_eye(), -1);
        for (int f = 0; f < 3; ++f) {
            sink.draw(renderer, test::test_scene(cube), test_camera());
            EXPECT_EQ(sink.present(renderer), 2);
        }
        EXPECT_EQ(sink.presents(), 6u);
        EXPECT_EQ(sink.last_eye(), swap ? 0 : 1);  // the last present opens the right shutter
        const fs::path dir = fresh_dir(swap ? "fs_swapped" : "fs");
        const std::vector<std::string> files = sink.finish(renderer, dir.string());
        ASSERT_EQ(files.size(), 3u);
        const Image left = read_png(files[0]), right = read_png(files[1]), shown = read_png(files[2]);
        EXPECT_GT(compare_images(left, right, 0).max_channel_diff, 0);
        EXPECT_EQ(compare_images(shown, swap ? left : right, 0).max_channel_diff, 0);
        fs::remove_all(dir);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(OffscreenSink, MonoDrawsOneEyeAndAnaglyphComesFromTheGpuPass) {
    gpu::Context ctx = gpu::Context::create();
    OffscreenStereoRenderer renderer = OffscreenStereoRenderer::create(ctx, kW, kH);
    const TriMesh cube = test::test_cube();
    {
        SinkOptions so;
        so.output = StereoOutput::kMono;
        OffscreenSink sink(ctx, so);
        EXPECT_EQ(sink.eye_count(), 1);
        SceneView scene = test::test_scene(cube);
        scene.eye_count = 2;  // the sink decides
        sink.draw(renderer, scene, test_camera());
        EXPECT_TRUE(renderer.last_frame_stats().passes.empty() ||
                    std::all_of(renderer.last_frame_stats().passes.begin(), renderer.last_frame_stats().passes.end(),
                                [](const PassTime& p) { return p.eye != 1; }));
        EXPECT_EQ(sink.present(renderer), 1);
        EXPECT_EQ(sink.last_eye(), -1);
        const fs::path dir = fresh_dir("mono");
        const std::vector<std::string> files = sink.finish(renderer, dir.string());
        ASSERT_EQ(files.size(), 3u);
        EXPECT_EQ(compare_images(read_png(files[0]), read_png(files[1]), 0).max_channel_diff, 0);
        EXPECT_EQ(compare_images(read_png(files[0]), read_png(files[2]), 0).max_channel_diff, 0);
        fs::remove_all(dir);
    }
    {
        SinkOptions so;
        so.output = StereoOutput::kAnaglyph;
        so.anaglyph = AnaglyphMethod::kDubois;
        OffscreenSink sink(ctx, so);
        EXPECT_THROW(sink.present(OffscreenStereoRenderer::create(ctx, kW, kH)), Error);  // no frame yet
        sink.draw(renderer, test::test_scene(cube), test_camera());
        EXPECT_EQ(sink.present(renderer), 1);
        const fs::path dir = fresh_dir("anaglyph");
        const std::vector<std::string> files = sink.finish(renderer, dir.string());
        ASSERT_EQ(files.size(), 3u);
        const Image want = compose(StereoOutput::kAnaglyph, read_png(files[0]), read_png(files[1]));
        EXPECT_LE(compare_images(read_png(files[2]), want, 0).max_channel_diff, 1);
        fs::remove_all(dir);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(OffscreenSink, QuadSaysHowItsLayersAreWritten) {
    gpu::Context ctx = gpu::Context::create();
    SinkOptions so;
    so.output = StereoOutput::kQuad;
    const OffscreenSink quad(ctx, so);
    ASSERT_EQ(quad.notes().size(), 1u);
    EXPECT_NE(quad.notes()[0].find("output.png shows layer 0"), std::string::npos);
    so.refresh_hz = 0.0;
    EXPECT_THROW(OffscreenSink(ctx, so), Error);
}

}  // namespace
}  // namespace tridex::renderer
