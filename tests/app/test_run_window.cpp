// `tridex run --display window` under a private Xvfb: the same session code path opens a window, presents a few
// vsync'd frames for side-by-side, frame-sequential and anaglyph, closes, writes report.json, and refuses quad on a
// surface without 2 image layers with the list of outputs that work.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "../renderer/test_window_xvfb.hpp"
#include "app/session/run/run_session.hpp"
#include "core/error.hpp"
#include "run_test_scene.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

TEST(RunWindow, OpensDrawsThreeFramesAndCloses) {
    renderer::test::VirtualDisplay display(1280, 1024);
    const fs::path dir = test::temp_dir("run_window");
    const std::string scene = test::write_small_scene(dir);
    struct Case {
        const char* stereo;
        std::uint64_t presents;
    };
    for (const Case c : {Case{"side-by-side", 3}, Case{"frame-sequential", 6}, Case{"anaglyph", 3}}) {
        RunOptions o;
        o.scene = scene;
        o.display = "window";
        o.stereo = c.stereo;
        o.frames = 3;
        o.out = (dir / c.stereo).string();
        const RunResult r = run_stereo_session(o);
        EXPECT_EQ(r.frames, 3u) << c.stereo;
        EXPECT_EQ(r.presents, c.presents) << c.stereo;
        EXPECT_EQ(r.present_mode, "fifo") << c.stereo;
        EXPECT_EQ(r.validation_messages, 0u) << c.stereo;
        std::ifstream f(dir / c.stereo / "report.json");
        const nlohmann::json rep = nlohmann::json::parse(f);
        EXPECT_EQ(rep["display"], "window");
        EXPECT_EQ(rep["frames"]["frame_ms"]["count"], 3);
        EXPECT_EQ(rep["frames"]["present"]["interval_ms"]["count"].get<std::uint64_t>(), c.presents - 1) << c.stereo;
        EXPECT_FALSE(fs::exists(dir / c.stereo / "output.png"));  // images are offscreen-only
        std::printf("[run window] %s: %llu presents, frame p50 %.2f ms, present interval p50 %.2f ms\n", c.stereo,
                    static_cast<unsigned long long>(r.presents), r.frame_ms.percentile_ms(0.5),
                    rep["frames"]["present"]["interval_ms"]["p50_ms"].get<double>());
    }
    fs::remove_all(dir);
}

// Frames over a frame-time target too small to meet: the budget steps the occlusion to 4x4 pixels, the levels to 2
// pixels, then the render scale down to --min-render-scale, 10 frames at a time; the eye images shrink with it
// while the window keeps its size, and the anaglyph's compose and the side-by-side blits scale them up without a
// validation message.
TEST(RunWindow, RenderScaleShrinksTheEyesOnTheFrameBudget) {
    renderer::test::VirtualDisplay display(1280, 1024);
    const fs::path dir = test::temp_dir("run_window_scale");
    const std::string scene = test::write_small_scene(dir);
    for (const char* stereo : {"anaglyph", "side-by-side"}) {
        RunOptions o;
        o.scene = scene;
        o.display = "window";
        o.stereo = stereo;
        o.frame_target_ms = 0.01;
        o.min_render_scale = 0.5;
        o.frames = 10 + 5;  // frames far over the target: all six steps down at once, and frames drawn at the last
        o.out = (dir / stereo).string();
        const RunResult r = run_stereo_session(o);
        EXPECT_EQ(r.validation_messages, 0u) << stereo;
        const nlohmann::json rep = test::read_json(dir / stereo / "report.json");
        const nlohmann::json& budget = rep["render"]["frame_budget"];
        EXPECT_DOUBLE_EQ(budget["now"]["scale"].get<double>(), 0.5) << budget.dump();
        EXPECT_EQ(budget["now"]["occlusion"], "quarter");
        // 2x2 and 4x4 at 1, 4x4 with the levels at 2 pixels, then 7/8, 3/4, 5/8, 1/2
        EXPECT_EQ(budget["ladder"].size(), 7u) << budget.dump();
        EXPECT_EQ(budget["now"]["lod_px"], 2.0);
        EXPECT_EQ(budget["frames_scaled"].get<std::uint64_t>(), 5u) << budget.dump();
        EXPECT_EQ(budget["frames_coarse_lod"].get<std::uint64_t>(), 5u) << budget.dump();
        EXPECT_EQ(budget["switches"].get<std::uint64_t>(), 1u) << budget.dump();
        EXPECT_EQ(rep["frames"]["render_scale_changes"], 1) << rep["frames"].dump();
        EXPECT_EQ(rep["frames"]["window_resizes"], 0);
        // The eyes at half the size the window gives them, rounded.
        const auto [w, h] = r.eye_resolution_window;
        EXPECT_GT(w, 1) << stereo;
        EXPECT_EQ(rep["frames"]["eye_resolution_window"], nlohmann::json::array({w, h}));
        EXPECT_EQ(rep["frames"]["eye_resolution_last"],
                  nlohmann::json::array({std::lround(w * 0.5), std::lround(h * 0.5)}))
            << "the window's eyes " << w << " x " << h;
    }
    fs::remove_all(dir);
}

// In a desk window, frames over the budget's target draw coarser levels of detail (--max-lod-px) after the
// occlusion's step: a still scene drawn with a target no frame meets, the render scale kept at 1, ends on the coarse
// step and draws fewer triangles per frame than with --max-lod-px 1, whose budget stops at the occlusion. Offscreen,
// the budget never coarsens the levels.
TEST(RunWindow, FrameBudgetDrawsCoarserLevelsWhenFramesRunLong) {
    renderer::test::VirtualDisplay display(1280, 1024);
    const fs::path dir = test::temp_dir("run_window_budget_lod");
    const std::string scene = (dir / "still.json").string();
    std::ofstream(scene) << R"({"workpiece": {"resolution": 96, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05]},
                              "stroke": "none", "head": {"provider": "fixed", "position_m": [0.0, 0.05, 0.6]},
                              "display": {"preset": "desktop", "resolution": [480, 270], "stereo": "mono"}})";
    const auto run = [&](double lod_px, const char* where) {
        RunOptions o;
        o.scene = scene;
        o.display = where;
        o.pace = false;
        o.frames = 120;
        o.frame_target_ms = 0.01;
        o.min_render_scale = 1.0;
        o.max_lod_px = lod_px;
        o.out = (dir / (std::string(where) + std::to_string(static_cast<int>(lod_px)))).string();
        return run_stereo_session(o);
    };
    const RunResult fine = run(1.0, "window"), coarse = run(8.0, "window"), offscreen = run(8.0, "offscreen");
    for (const RunResult* r : {&fine, &coarse, &offscreen}) EXPECT_EQ(r->validation_messages, 0u);
    EXPECT_EQ(fine.frame_budget.at("frames_coarse_lod"), 0u);
    EXPECT_EQ(fine.frame_budget.at("now").at("lod_px"), 1.0);
    EXPECT_EQ(coarse.frame_budget.at("now").at("lod_px"), 8.0);
    EXPECT_GE(coarse.frame_budget.at("frames_coarse_lod").get<std::uint64_t>(), 90u);  // from the 11th frame on
    EXPECT_EQ(offscreen.frame_budget.at("coarse_lod_px"), 1.0) << offscreen.frame_budget.dump();
    EXPECT_EQ(offscreen.frame_budget.at("frames_coarse_lod"), 0u);
    const auto per_frame = [](const RunResult& r) {
        return static_cast<double>(r.render.tile_triangles[0]) / static_cast<double>(r.render.frames);
    };
    EXPECT_LT(per_frame(coarse), 0.8 * per_frame(fine)) << per_frame(coarse) << " vs " << per_frame(fine);
    fs::remove_all(dir);
}

TEST(RunWindow, QuadIsRefusedWithTheOutputsThatWork) {
    renderer::test::VirtualDisplay display(1280, 1024);
    const fs::path dir = test::temp_dir("run_window_quad");
    RunOptions o;
    o.scene = test::write_small_scene(dir);
    o.display = "window";
    o.stereo = "quad";
    o.frames = 3;
    o.out = (dir / "out").string();
    try {
        (void)run_stereo_session(o);
        ADD_FAILURE() << "quad was accepted (does this surface report maxImageArrayLayers >= 2?)";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("quad"), std::string::npos) << m;
        for (const char* name : {"frame-sequential", "side-by-side", "top-bottom", "anaglyph", "mono"})
            EXPECT_NE(m.find(name), std::string::npos) << name << " missing from: " << m;
    }
    EXPECT_FALSE(fs::exists(dir / "out" / "report.json"));  // refused before any work
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
