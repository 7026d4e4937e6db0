// `tridex run --display offscreen`: every stereo output writes left/right/output.png and report.json, output.png is
// compose() of the eyes (anaglyph: the GPU pass, within 1 code of compose()), the frame-time histogram is reported, a whole stroke carves and reaches the renderer as
// new meshes, and Vulkan validation stays silent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "test_files.hpp"
#include "app/session/run/run_session.hpp"
#include "core/error.hpp"
#include "renderer/image/image.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/output/stereo_output.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using renderer::StereoOutput;

// Expects the images to differ by at most `tolerance` per channel (default: identical); writes a difference image
// next to them when not.
void expect_same(const renderer::Image& got, const renderer::Image& want, const fs::path& dir, const std::string& what,
                 int tolerance = 0) {
    ASSERT_EQ(got.width, want.width) << what;
    ASSERT_EQ(got.height, want.height) << what;
    const renderer::ImageComparison c = renderer::compare_images(got, want, 0);
    EXPECT_LE(c.max_channel_diff, tolerance) << what;
    if (c.max_channel_diff > tolerance)
        renderer::write_png((dir / (what + "_diff.png")).string(), renderer::difference_image(got, want, 0));
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
            // Anaglyph: output.png is the GPU pass, compose() the CPU reference (within 1 code per channel).
            expect_same(shown, renderer::compose(output, left, right, co), dir, name + "_output",
                        output == StereoOutput::kAnaglyph ? 1 : 0);
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

            const nlohmann::json rep = test::read_json(dir / name / "report.json");
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
    const nlohmann::json rep = test::read_json(dir / "out" / "report.json");
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

// A scene whose fixed head is `head_z_m` in front of the screen (the small scene's workpiece reaches z = 0.11 m).
std::string write_scene_with_head(const fs::path& dir, const std::string& name, double head_z_m) {
    const std::string path = (dir / name).string();
    std::ofstream(path) << R"({
  "workpiece": { "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "stroke": { "duration_s": 0.5, "length_m": 0.06, "depth_m": 0.004 },
  "display": { "preset": "desktop", "resolution": [96, 72], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.0, )" << head_z_m << R"(] }
})";
    return path;
}

RunResult run_offscreen(const std::string& scene, const fs::path& out, const std::string& stereo, int frames,
                        bool items = true, bool tiles = true, bool cull = true) {
    RunOptions o;
    o.scene = scene;
    o.display = "offscreen";
    o.stereo = stereo;
    o.frames = frames;
    o.out = out.string();
    o.items = items;
    o.tiles = tiles;
    o.cull = cull;
    return run_stereo_session(o);
}

TEST(RunOffscreen, ItemsAndOverlayAreDrawnAndTheReportHasPassesAndTiles) {
    const fs::path dir = test::temp_dir("run_items");
    const std::string scene = test::write_small_scene(dir);
    const RunResult on = run_offscreen(scene, dir / "on", "side-by-side", 4);
    const RunResult off = run_offscreen(scene, dir / "off", "side-by-side", 4, false);
    EXPECT_EQ(on.validation_messages, 0u);
    EXPECT_EQ(off.validation_messages, 0u);
    EXPECT_TRUE(on.tiled);
    EXPECT_GT(on.tiles_last, 1u);
    EXPECT_DOUBLE_EQ(on.force_m_per_newton, 0.02);
    // The overlay panel sits in the top-left corner (6 px margin at 72 px height): there the images differ,
    // and without items that corner is the clear colour in both eyes.
    for (const char* eye : {"left.png", "right.png"}) {
        const renderer::Image a = renderer::read_png((dir / "on" / eye).string());
        const renderer::Image b = renderer::read_png((dir / "off" / eye).string());
        int differing = 0;
        for (int y = 3; y < 12; ++y)
            for (int x = 3; x < 30; ++x)
                for (int c = 0; c < 3; ++c) differing += a.rgba[(y * a.width + x) * 4 + c] != b.rgba[(y * b.width + x) * 4 + c];
        EXPECT_GT(differing, 20) << eye;
    }
    const nlohmann::json rep = test::read_json(dir / "on" / "report.json");
    const nlohmann::json& render = rep["render"];
    EXPECT_TRUE(render["tiled"].get<bool>());
    ASSERT_EQ(render["tiles"]["per_frame"].size(), 4u);
    std::uint64_t drawn = 0;
    for (const auto& f : render["tiles"]["per_frame"]) {
        ASSERT_EQ(f.size(), 4u);
        EXPECT_EQ(f[0].get<std::uint64_t>() + f[1].get<std::uint64_t>(), on.tiles_last);  // every tile: drawn or skipped
        drawn += f[0].get<std::uint64_t>();
    }
    EXPECT_EQ(render["tiles"]["drawn_total"][0].get<std::uint64_t>(), drawn);
    if (on.contour_path == "cpu")  // tile meshes: all uploaded once at least
        EXPECT_GE(render["tiles"]["uploads_total"].get<std::uint64_t>(), on.tiles_last);
    else  // GPU contour: drawn from the contourer's buffers, nothing uploaded
        EXPECT_EQ(render["tiles"]["uploads_total"].get<std::uint64_t>(), 0u);
    // Per-pass GPU times (pass-per-eye on lavapipe: every phase per eye), each with count, total, median, p99.
    const nlohmann::json& passes = render["passes"];
    ASSERT_FALSE(passes.empty());
    for (const auto& [name, p] : passes.items()) {
        EXPECT_EQ(p["count"].get<std::uint64_t>(), 4u) << name;
        EXPECT_GE(p["p99_ms"].get<double>(), p["median_ms"].get<double>()) << name;
        EXPECT_GE(p["total_ms"].get<double>(), p["median_ms"].get<double>()) << name;
        std::printf("[run items] pass %s: median %.3f ms p99 %.3f ms total %.3f ms\n", name.c_str(),
                    p["median_ms"].get<double>(), p["p99_ms"].get<double>(), p["total_ms"].get<double>());
    }
    if (on.eye_strategy.find("pass-per-eye") != std::string::npos) {
        EXPECT_TRUE(passes.contains("opaque.left"));
        EXPECT_TRUE(passes.contains("opaque.right"));
        EXPECT_TRUE(passes.contains("overlay.right"));
    }
    const nlohmann::json off_rep = test::read_json(dir / "off" / "report.json");
    EXPECT_FALSE(off_rep["render"]["items"].get<bool>());
    fs::remove_all(dir);
}

TEST(RunOffscreen, CloseUpHeadSkipsTilesAndWholeMeshFallbackDraws) {
    const fs::path dir = test::temp_dir("run_closeup");
    // The eyes 0.12 m from the screen: the near plane (0.05 m) cuts off the tiles nearest the viewer.
    const std::string scene = write_scene_with_head(dir, "close.json", 0.12);
    const RunResult culled = run_offscreen(scene, dir / "culled", "side-by-side", 3);
    EXPECT_EQ(culled.validation_messages, 0u);
    std::size_t skipped = 0;
    for (const auto& f : culled.render.tiles) skipped += std::max(f[0].skipped, f[1].skipped);
    std::printf("[run closeup] %zu tiles, last frame: left %zu drawn %zu skipped, right %zu drawn %zu skipped\n",
                culled.tiles_last, culled.render.tiles.back()[0].drawn, culled.render.tiles.back()[0].skipped,
                culled.render.tiles.back()[1].drawn, culled.render.tiles.back()[1].skipped);
    EXPECT_GT(skipped, 0u);
    // Without culling nothing is skipped; the pictures agree (skipped tiles were invisible) up to the tool,
    // whose position moves with the haptic loop's timing, so only the counts are compared here.
    const RunResult all = run_offscreen(scene, dir / "all", "side-by-side", 3, true, true, false);
    for (const auto& f : all.render.tiles) {
        EXPECT_EQ(f[0].skipped + f[1].skipped, 0u);
        EXPECT_EQ(f[0].drawn, all.tiles_last);
    }
    // The whole-mesh fallback: no tiles, the same triangles.
    const RunResult whole = run_offscreen(scene, dir / "whole", "side-by-side", 3, true, false);
    EXPECT_FALSE(whole.tiled);
    EXPECT_EQ(whole.contour_path, "cpu");  // the whole mesh comes from the CPU contourer
    EXPECT_EQ(whole.tiles_last, 0u);
    EXPECT_GT(whole.triangles, 0u);
    EXPECT_EQ(whole.render.tiles.back()[0].drawn + whole.render.tiles.back()[0].skipped, 0u);
    EXPECT_EQ(whole.validation_messages, 0u);
    fs::remove_all(dir);
}

TEST(RunOffscreen, MonoRendersOneEye) {
    const fs::path dir = test::temp_dir("run_mono");
    const std::string scene = test::write_small_scene(dir);
    const RunResult r = run_offscreen(scene, dir / "mono", "mono", 3);
    EXPECT_EQ(r.validation_messages, 0u);
    for (const auto& f : r.render.tiles) {
        EXPECT_EQ(f[1].drawn + f[1].skipped, 0u);  // the right eye did no work
        EXPECT_GT(f[0].drawn, 0u);
    }
    for (const auto& [name, ms] : r.render.pass_ms) EXPECT_EQ(name.find(".right"), std::string::npos) << name;
    if (r.eye_strategy.find("pass-per-eye") != std::string::npos) {
        EXPECT_EQ(r.render.pass_ms.count("opaque.left"), 1u);
    }
    const renderer::Image left = renderer::read_png((dir / "mono" / "left.png").string());
    const renderer::Image right = renderer::read_png((dir / "mono" / "right.png").string());
    expect_same(right, left, dir, "mono_right_is_left");
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

// On lavapipe, a CPU implementation of Vulkan, the sculpting frames are drawn without the ambient occlusion by
// default; the others and the session's last frame keep it, and --ao-while-sculpting on keeps it throughout.
TEST(RunOffscreen, SculptingFramesDropTheOcclusionOnACpuDevice) {
    const fs::path dir = test::temp_dir("run_ao_sculpting");
    RunOptions o;
    o.scene = test::write_small_scene(dir, 0.5);
    o.display = "offscreen";
    o.stereo = "mono";
    o.out = (dir / "auto").string();
    const RunResult automatic = run_stereo_session(o);
    EXPECT_FALSE(automatic.ao_sculpting);
    EXPECT_NE(automatic.ao_sculpting_reason.find("CPU implementation"), std::string::npos)
        << automatic.ao_sculpting_reason;
    EXPECT_GT(automatic.frames_occlusion_held, 0u);
    EXPECT_LT(automatic.frames_occlusion_held, automatic.frames);  // the first frame and the last keep it
    const nlohmann::json rep = test::read_json(dir / "auto" / "report.json");
    EXPECT_EQ(rep["render"]["ambient_occlusion_while_sculpting"]["frames_held"].get<std::uint64_t>(),
              automatic.frames_occlusion_held);
    EXPECT_FALSE(rep["render"]["ambient_occlusion_while_sculpting"]["on"].get<bool>());
    // The occlusion pass is timed only on the frames that ran it (mono on lavapipe: one render pass, "left").
    const auto pass_count = [](const nlohmann::json& report, const char* pass) -> std::uint64_t {
        const nlohmann::json& passes = report["render"]["passes"];
        return passes.contains(pass) ? passes[pass]["count"].get<std::uint64_t>() : 0u;
    };
    if (pass_count(rep, "opaque.left") > 0) {
        EXPECT_GT(pass_count(rep, "occlusion.left"), 0u);
        EXPECT_LT(pass_count(rep, "occlusion.left"), pass_count(rep, "opaque.left"));
    }

    o.ao_sculpting = "on";
    o.out = (dir / "on").string();
    const RunResult on = run_stereo_session(o);
    EXPECT_TRUE(on.ao_sculpting);
    EXPECT_EQ(on.frames_occlusion_held, 0u);
    EXPECT_EQ(on.ao_sculpting_reason, "--ao-while-sculpting on");
    const nlohmann::json on_rep = test::read_json(dir / "on" / "report.json");
    EXPECT_EQ(pass_count(on_rep, "occlusion.left"), pass_count(on_rep, "opaque.left"));

    o.ao = "off";  // nothing to hold back when the occlusion is off
    o.ao_sculpting = "off";
    o.out = (dir / "none").string();
    EXPECT_EQ(run_stereo_session(o).frames_occlusion_held, 0u);
    EXPECT_EQ(pass_count(test::read_json(dir / "none" / "report.json"), "occlusion.left"), 0u);

    o.ao_sculpting = "sometimes";
    try {
        (void)run_stereo_session(o);
        ADD_FAILURE() << "--ao-while-sculpting sometimes was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--ao-while-sculpting"), std::string::npos) << e.what();
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
