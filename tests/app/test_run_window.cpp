// `tridex run --display window` under a private Xvfb: the same session code path opens a window, presents a few
// vsync'd frames for side-by-side, frame-sequential and anaglyph, closes, writes report.json, and refuses quad on a
// surface without 2 image layers with the list of outputs that work.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/session/run_session.hpp"
#include "core/error.hpp"
#include "../renderer/test_window_xvfb.hpp"
#include "run_test_scene.hpp"

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
