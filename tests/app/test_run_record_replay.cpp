// `tridex run` with a flat-end mill, the wand profile and a materials table: it carves offscreen, reports the
// tool and the demo's haptics block, writes sculpted.ply, records, and the recording replays (`tridex replay`)
// to the same sculpted.ply byte for byte.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "test_files.hpp"
#include "app/commands/replay/replay.hpp"
#include "app/session/run/run_session.hpp"
#include "app/session/batch/session.hpp"
#include "core/error.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

// The bunny at 48 cells, a flat-end mill pressed from above, the 5-DOF wand, one material with friction.
std::string write_mill_scene(const fs::path& dir, int points) {
    const std::string path = (dir / "mill.json").string();
    std::ofstream(path) << R"({
  "workpiece": { "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "shape": "flat_end", "radius_m": 0.004, "length_m": 0.02 },
  "device": { "driver": "simulated", "profile": "wand" },
  "op": "subtract",
  "materials": [{ "id": 0, "stiffness_n_per_m": 500, "damping_n_s_per_m": 0.4,
                  "static_friction": 0.3, "dynamic_friction": 0.2 }],
  "haptics": { "points": )" << points << R"( },
  "stroke": { "duration_s": 0.8, "length_m": 0.05, "depth_m": 0.004, "press_axis": "y" },
  "display": { "preset": "desktop", "resolution": [96, 72], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.1, 0.6] }
})";
    return path;
}

TEST(RunRecordReplay, FlatEndWandSceneCarvesReportsAndReplaysByteForByte) {
    const fs::path dir = test::temp_dir("run_record_replay");
    RunOptions o;
    o.scene = write_mill_scene(dir, 24);
    o.display = "offscreen";
    o.out = (dir / "run").string();
    o.record = (dir / "run.trdx").string();
    o.cpu = true;  // the CPU reference: bit-identical to the GPU path, faster to set up in a test
    const RunResult r = run_stereo_session(o);
    EXPECT_TRUE(r.stroke_completed);
    EXPECT_LT(r.volume_after_m3, r.volume_before_m3) << "the mill carved nothing";

    const nlohmann::json rep = test::read_json(dir / "run" / "report.json");
    EXPECT_EQ(rep["tool"]["shape"], "flat_end");
    EXPECT_DOUBLE_EQ(rep["tool"]["radius_m"].get<double>(), 0.004);
    EXPECT_DOUBLE_EQ(rep["tool"]["length_m"].get<double>(), 0.02);
    EXPECT_EQ(rep["tool"]["points"], 24);
    for (const char* key : {"watchdog_trips", "passivity_energy_j", "realtime_scheduling", "contact_ticks", "max_force_n"})
        EXPECT_TRUE(rep["haptics"].contains(key)) << key;
    EXPECT_EQ(rep["haptics"]["device"], "Quanser 5-DOF Haptic Wand");
    EXPECT_EQ(rep["haptics"]["materials"], 1);
    EXPECT_GT(rep["haptics"]["contact_ticks"].get<int>(), 0) << "the 24 contact points never touched";
    EXPECT_EQ(rep["settings"]["tool"]["shape"], "flat_end");
    ASSERT_TRUE(fs::is_regular_file(dir / "run" / "sculpted.ply"));
    ASSERT_TRUE(fs::is_regular_file(dir / "run.trdx"));

    OutputOptions out;
    out.out = (dir / "replay").string();
    out.width = 64;
    out.height = 48;
    run_replay(o.record, out, SculptOptions{true, false, false, false, ""});
    const std::string live = test::bytes_of(dir / "run" / "sculpted.ply");
    const std::string again = test::bytes_of(dir / "replay" / "sculpted.ply");
    EXPECT_FALSE(live.empty());
    EXPECT_TRUE(live == again) << "the replay of the run's recording sculpted a different model";
    const nlohmann::json rrep = test::read_json(dir / "replay" / "report.json");
    EXPECT_EQ(rrep["tool"]["shape"], "flat_end");
    EXPECT_DOUBLE_EQ(rrep["volume_removed_m3"].get<double>(), rep["volume_before_m3"].get<double>() -
                                                                 rep["volume_after_m3"].get<double>());
}

TEST(RunRecordReplay, SceneRefusesToolsAndPointsThatDoNotExist) {
    const fs::path dir = test::temp_dir("run_scene_tools");
    auto expect_refused = [&](const std::string& body, const std::string& field) {
        const std::string path = (dir / "bad.json").string();
        std::ofstream(path) << body;
        try {
            (void)load_run_scene(path);
            ADD_FAILURE() << "accepted: " << body;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    expect_refused(R"({"tool": {"shape": "cone"}})", "tool.shape");
    expect_refused(R"({"workpiece": {"centre_m": [1e300, 0, 0]}})", "workpiece.centre_m");
    expect_refused(R"({"workpiece": {"mesh": "/tmp"}})", "is a folder");
    expect_refused(R"({"tool": {"shape": "mesh"}})", "tool.mesh");
    expect_refused(R"({"tool": {"shape": "ball", "length_m": 0.01}})", "tool.length_m");
    expect_refused(R"({"haptics": {"points": 2}})", "haptics.points");  // the wand's two points need a flat end
    expect_refused(R"({"device": {"driver": "falcon"}})", "device.driver");
    expect_refused(R"({"device": {"profile": "omni2"}})", "device.profile");
    expect_refused(R"({"op": "carve"})", "'op'");
    expect_refused(R"({"materials": [{"id": 300}]})", "materials[0].id");
    expect_refused(R"({"materials": [{"id": 1}, {"id": 1}]})", "materials[1].id");
    expect_refused(R"({"materials": [{"id": 1, "static_friction": 0.1, "dynamic_friction": 0.2}]})",
                   "materials[0].dynamic_friction");
}

}  // namespace
}  // namespace tridex::app
