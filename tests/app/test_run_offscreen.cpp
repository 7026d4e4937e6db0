// `tridex run --display offscreen`: every stereo output writes left/right/output.png and report.json, output.png is
// compose() of the eyes, the frame-time histogram is reported, a whole stroke carves and reaches the renderer as
// new meshes, and Vulkan validation stays silent.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/run_session.hpp"
#include "core/error.hpp"
#include "renderer/image.hpp"
#include "renderer/image_compare.hpp"
#include "renderer/stereo_output.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using renderer::StereoOutput;

nlohmann::json read_json(const fs::path& p) {
    std::ifstream f(p);
    return nlohmann::json::parse(f);
}

// Expects the images to be identical; writes a difference image next to them when not.
void expect_same(const renderer::Image& got, const renderer::Image& want, const fs::path& dir, const std::string& what) {
    ASSERT_EQ(got.width, want.width) << what;
    ASSERT_EQ(got.height, want.height) << what;
    const renderer::ImageComparison c = renderer::compare_images(got, want, 0);
    EXPECT_EQ(c.max_channel_diff, 0) << what;
    if (c.max_channel_diff != 0) renderer::write_png((dir / (what + "_diff.png")).string(), renderer::difference_image(got, want, 0));
}

TEST(RunOffscreen, EveryStereoOutputWritesItsFiles) {
    const fs::path dir = test::temp_dir("run_offscreen");
    const std::string scene = test::write_small_scene(dir);
    for (const StereoOutput output : renderer::all_stereo_outputs()) {
        for (const bool swap : {false, true}) {
            if (swap && output != StereoOutput::kSideBySide && output != StereoOutput::kFrameSequential) continue;
            const std::string name = std::string(renderer::to_string(output)) + (swap ? "_swapped" : "");
            RunOptions o;
            o.scene = scene;
            o.display = "offscreen";
            o.stereo = std::string(renderer::to_string(output));
            o.frames = 3;
            o.swap_eyes = swap;
            o.out = (dir / name).string();
            const RunResult r = run_stereo_session(o);
            EXPECT_EQ(r.frames, 3u) << name;
            EXPECT_EQ(r.presents, output == StereoOutput::kFrameSequential ? 6u : 3u) << name;
            EXPECT_EQ(r.validation_messages, 0u) << name;

            const renderer::Image left = renderer::read_png((dir / name / "left.png").string());
            const renderer::Image right = renderer::read_png((dir / name / "right.png").string());
            const renderer::Image shown = renderer::read_png((dir / name / "output.png").string());
            EXPECT_EQ(left.width, 96) << name;
            EXPECT_EQ(left.height, 72) << name;
            const auto [w, h] = renderer::output_size(output, 96, 72);
            EXPECT_EQ(shown.width, w) << name;
            EXPECT_EQ(shown.height, h) << name;
            renderer::ComposeOptions co;
            co.swap_eyes = swap;
            co.eye_slot = output == StereoOutput::kFrameSequential ? 1 : 0;  // the last present opens the right shutter
            expect_same(shown, renderer::compose(output, left, right, co), dir, name + "_output");
            // The eyes differ (stereo) except in mono, where both files hold the one centre view.
            const int eye_diff = renderer::compare_images(left, right, 0).max_channel_diff;
            if (output == StereoOutput::kMono) {
                EXPECT_EQ(eye_diff, 0) << name;
            } else {
                EXPECT_GT(eye_diff, 0) << name;
            }
            if (output == StereoOutput::kFrameSequential) {  // the last present shows the right eye (left if swapped)
                EXPECT_EQ(r.last_eye, swap ? 0 : 1);
                expect_same(shown, swap ? left : right, dir, name + "_last_eye");
            }
            if (output == StereoOutput::kQuad) expect_same(shown, left, dir, name + "_layer0");

            const nlohmann::json rep = read_json(dir / name / "report.json");
            EXPECT_EQ(rep["stereo"], o.stereo) << name;
            EXPECT_EQ(rep["display"], "offscreen");
            EXPECT_EQ(rep["validation_messages"], 0);
            EXPECT_EQ(rep["frames"]["count"], 3);
            EXPECT_EQ(rep["frames"]["frame_ms"]["count"], 3);
            EXPECT_EQ(rep["frames"]["interval_ms"]["count"], 2);
            EXPECT_GT(rep["frames"]["frame_ms"]["max_ms"].get<double>(), 0.0);
            ASSERT_TRUE(rep["frames"]["frame_ms"]["bins"].is_array());
            std::uint64_t binned = 0;
            for (const auto& b : rep["frames"]["frame_ms"]["bins"]) binned += b[1].get<std::uint64_t>();
            EXPECT_EQ(binned + rep["frames"]["frame_ms"]["overflow"].get<std::uint64_t>(), 3u) << name;
            EXPECT_GT(rep["haptics"]["ticks"].get<double>(), 0.0) << name;
            EXPECT_TRUE(rep["sculpt"].contains("steps"));
            if (output == StereoOutput::kQuad) {
                EXPECT_NE(rep["notes"].dump().find("output.png shows layer 0"), std::string::npos);
            }
        }
    }
    fs::remove_all(dir);
}

TEST(RunOffscreen, WholeStrokeCarvesAndTheRendererTakesNewMeshes) {
    const fs::path dir = test::temp_dir("run_stroke");
    RunOptions o;
    o.scene = test::write_small_scene(dir, 0.8);
    o.display = "offscreen";
    o.stereo = "side-by-side";
    o.out = (dir / "out").string();  // no --frames / --seconds: until the stroke ends
    const RunResult r = run_stereo_session(o);
    EXPECT_TRUE(r.stroke_completed);
    EXPECT_GE(r.loop.ticks, 800u);
    EXPECT_LT(r.volume_after_m3, r.volume_before_m3);  // the stroke carved
    EXPECT_GT(r.sculpt.steps, 0u);
    EXPECT_GE(r.sculpt.mesh_publishes, 2u);            // the initial mesh and at least one carved one
    EXPECT_GE(r.mesh_versions_drawn, 2u);              // the renderer drew more than the first mesh
    EXPECT_GT(r.frames, 10u);                          // ~60 Hz over 0.8 s
    EXPECT_EQ(r.validation_messages, 0u);
    EXPECT_NE(r.notes.front().find("the stroke ended"), std::string::npos);
    const nlohmann::json rep = read_json(dir / "out" / "report.json");
    EXPECT_TRUE(rep["stroke_completed"].get<bool>());
    EXPECT_EQ(rep["frames"]["frame_ms"]["count"].get<std::uint64_t>(), r.frames);
    std::printf("[run] offscreen side-by-side 96x72, 0.8 s stroke: %llu frames, frame p50 %.2f ms p99 %.2f ms, GPU p50 "
                "%.2f ms, %llu meshes drawn of %llu published (publish p50 %.2f ms), %zu ticks, %llu sculpt steps\n",
                static_cast<unsigned long long>(r.frames), r.frame_ms.percentile_ms(0.5), r.frame_ms.percentile_ms(0.99),
                r.gpu_ms.percentile_ms(0.5), static_cast<unsigned long long>(r.mesh_versions_drawn),
                static_cast<unsigned long long>(r.sculpt.mesh_publishes),
                rep["meshes"]["publish_ms"]["median"].get<double>(), r.loop.ticks,
                static_cast<unsigned long long>(r.sculpt.steps));
    fs::remove_all(dir);
}

TEST(RunOffscreen, SceneWithoutStrokeNeedsALimit) {
    const fs::path dir = test::temp_dir("run_nostroke");
    const std::string scene = (dir / "still.json").string();
    std::ofstream(scene) << R"({"workpiece": {"resolution": 32}, "stroke": "none",
                              "display": {"preset": "desktop", "resolution": [64, 48], "stereo": "mono"}})";
    RunOptions o;
    o.scene = scene;
    o.display = "offscreen";
    o.out = (dir / "out").string();
    try {
        (void)run_stereo_session(o);
        ADD_FAILURE() << "an endless offscreen run was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--frames/--seconds"), std::string::npos) << e.what();
    }
    o.seconds = 0.2;
    const RunResult r = run_stereo_session(o);
    EXPECT_GE(r.frames, 2u);
    EXPECT_FALSE(r.stroke_completed);
    EXPECT_DOUBLE_EQ(r.volume_after_m3, r.volume_before_m3);  // the hand held still in front of the workpiece
    EXPECT_TRUE(fs::is_regular_file(dir / "out" / "output.png"));
    EXPECT_EQ(r.validation_messages, 0u);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
