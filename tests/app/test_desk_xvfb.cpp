// The desk as a newcomer meets it, with real X input events (xdotool through XTEST) under a private Xvfb: a scene
// with no display section opens in mono, in a window sized to its monitor; the window resized by the window system
// changes the size the eyes are rendered at; choosing paint after the wheel turned a deep cut resets the depth.
// Skipped only when the Xvfb or xdotool binary is missing.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "../renderer/test_window_xvfb.hpp"
#include "../test_paths.hpp"
#include "run_test_scene.hpp"
#include "test_files.hpp"
#include "xvfb_session.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

ino_t inode_of(const fs::path& p) {
    struct stat st {};
    return ::stat(p.c_str(), &st) == 0 ? st.st_ino : 0;
}

TEST(DeskXvfb, MonoWindowSizedToTheMonitorFollowsResizesAndAnOpResetsTheDepth) {
    if (!test::have_binary("Xvfb") || !test::have_binary("xdotool"))
        GTEST_SKIP() << "needs the Xvfb and xdotool binaries (scripts/install-deps.sh installs xvfb and xdotool)";
    renderer::test::VirtualDisplay display(1000, 700);
    const fs::path dir = test::temp_dir("desk_xvfb");
    const std::string scene = (dir / "scene.json").string();
    // No display section: the desk preset, its window sized to the monitor.
    std::ofstream(scene) << R"({
  "workpiece": { "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "stroke": "none",
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] }
}
)";
    const fs::path out = dir / "out", save = dir / "live.tdx";
    test::TridexProcess app(TRIDEX_EXE,
                            "run " + scene + " --display window --cpu --no-journal --out " + out.string() + " --save " +
                                save.string(),
                            dir);
    const std::string w = test::find_window("tridex run");
    ASSERT_FALSE(w.empty());
    // 80% of the 1000 x 700 screen (no window manager: the work area is the screen).
    const std::string geometry = test::xdo("getwindowgeometry " + w);
    EXPECT_NE(geometry.find("Geometry: 800x560"), std::string::npos) << geometry;
    // A sync point: a save is written after the events before it were handled, and that frame is drawn.
    const auto sync = [&] {
        const ino_t before = inode_of(save);
        test::xdo("key ctrl+s");
        ASSERT_TRUE(test::wait_for([&] { return inode_of(save) != before && inode_of(save) != 0; }))
            << "Ctrl+S wrote no model; stderr: " << test::bytes_of(dir / "stderr.txt");
    };
    test::xdo("mousemove --window " + w + " 400 280");
    sync();
    // The newcomer's deep cut: ten wheel clicks away from the user (two radii in all), then paint.
    test::xdo("click --repeat 10 --delay 20 4");
    sync();
    test::xdo("key 3");
    // The window system resizes the window; the eyes follow it.
    test::xdo("windowsize " + w + " 640 300");
    sync();
    sync();  // the frame after the resize's events has drawn at the new size
    test::xdo("key Escape");
    ASSERT_TRUE(test::wait_for([&] { return !app.running(); })) << "Esc did not close the window";
    EXPECT_EQ(app.exit_code(), 0) << test::bytes_of(dir / "stderr.txt");
    const nlohmann::json rep = test::read_json(out / "report.json");
    EXPECT_EQ(rep["stereo"], "mono");
    EXPECT_EQ(rep["mouse"]["op"], "paint");
    EXPECT_NEAR(rep["mouse"]["depth_m"].get<double>(), 0.3 * 0.006, 1e-12) << "choosing paint kept the deep cut's depth";
    EXPECT_GE(rep["frames"]["window_resizes"].get<int>(), 1);
    // The eyes at the window's size times one of the frame-time budget's render scales (1 unless frames ran long).
    // The budget may step once more after the last frame is drawn, so the scale is matched against its ladder.
    EXPECT_EQ(rep["frames"]["eye_resolution_window"], nlohmann::json::array({640, 300})) << rep["frames"].dump();
    bool on_ladder = false;
    for (const auto& step : rep["render"]["frame_budget"]["ladder"]) {
        const double scale = step["scale"].get<double>();
        on_ladder = on_ladder || rep["frames"]["eye_resolution_last"] ==
                                     nlohmann::json::array({std::lround(640 * scale), std::lround(300 * scale)});
    }
    EXPECT_TRUE(on_ladder) << rep["frames"].dump() << "\n" << rep["render"]["frame_budget"].dump();
    EXPECT_EQ(rep["validation_messages"], 0);
    if (!HasFailure()) fs::remove_all(dir);  // kept for a look when something failed
}

}  // namespace
}  // namespace tridex::app
