// A groove longer than the PHANTOM Omni can reach, carved in `tridex run` by four passes joined by Peng et al.'s
// workspace moves (section 4.1: two clicks, a drag, two clicks): the scripted hand presses the stylus button,
// the workspace follows, the groove is continuous, and the recording replays to the same model byte for byte.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "test_files.hpp"
#include "app/commands/replay/replay.hpp"
#include "app/session/run/run_session.hpp"
#include "app/session/batch/session.hpp"
#include "compute/mesh/mesh_io.hpp"
#include "core/error.hpp"
#include "devices/haptic_device.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

std::string asset(const char* name) {
    const char* env = std::getenv("TRIDEX_ASSETS");
    return (fs::path(env ? env : "assets") / name).string();
}

// The bundled long-groove scene at test size: the same stroke, a coarser lattice, small eyes.
std::string write_scene(const fs::path& dir, const std::string& moves) {
    std::ifstream in(asset("peng_long_groove_scene.json"));
    nlohmann::json j = nlohmann::json::parse(in);
    j["workpiece"]["mesh"] = asset("bar.off");
    j["workpiece"]["resolution"] = 96;
    j["stroke"]["moves"] = nlohmann::json::parse(moves);
    j["display"]["resolution"] = {96, 72};
    const std::string path = (dir / "peng.json").string();
    std::ofstream(path) << j.dump(2);
    return path;
}

TEST(RunPeng, FourPassesMoveTheWorkspaceAndCarveOneGrooveLongerThanTheDeviceReaches) {
    const fs::path dir = test::temp_dir("run_peng");
    RunOptions o;
    o.scene = write_scene(dir, R"(["jump", "drag", "jump"])");
    o.display = "offscreen";
    o.out = (dir / "run").string();
    o.record = (dir / "run.trdx").string();
    o.cpu = true;
    const RunResult r = run_stereo_session(o);
    EXPECT_TRUE(r.stroke_completed);

    std::ifstream rf(dir / "run" / "report.json");
    const nlohmann::json rep = nlohmann::json::parse(rf);
    const nlohmann::json& h = rep["haptics"];
    EXPECT_EQ(h["button_presses"].get<int>(), 5);  // two clicks, a drag, two clicks
    EXPECT_GT(h["modelling_paused_ticks"].get<int>(), 500);
    const double omni_x = devices::DeviceProfile::phantom_omni().workspace_m.size().x;  // 0.163 m
    const double tool_x = h["tool_world_extent_m"][0].get<double>(), hand_x = h["device_extent_m"][0].get<double>();
    EXPECT_GT(tool_x, 1.4 * omni_x) << "the tool did not travel beyond the device's reach";
    EXPECT_LT(hand_x, omni_x) << "the hand left the device's workspace";
    EXPECT_EQ(h["watchdog_trips"].get<int>(), 0);
    EXPECT_EQ(h["device_status"]["faults"], "none");

    // One continuous groove: the carved mesh has material removed under every pass (sample the top surface's
    // height along the groove's line from the mesh's vertices near it).
    const TriMesh carved = compute::load_closed_mesh((dir / "run" / "sculpted.ply").string());
    const Aabb b = carved.bounds();
    const double x0 = b.centre().x - 0.12, len = 0.24;  // 4 passes of 0.06 m, centred on the bar
    int dug = 0;
    for (int k = 0; k < 4; ++k) {
        const double xm = x0 + (k + 0.5) * len / 4;  // the middle of pass k
        double lowest = b.hi.y;
        for (const Vec3& v : carved.positions)
            if (std::abs(v.x - xm) < 0.005 && std::abs(v.z - b.centre().z) < 0.003) lowest = std::min(lowest, v.y);
        dug += b.hi.y - lowest > 0.001 ? 1 : 0;  // at least a millimetre deep
    }
    EXPECT_EQ(dug, 4) << "not every pass carved its stretch of the groove";

    OutputOptions out;
    out.out = (dir / "replay").string();
    out.width = 64;
    out.height = 48;
    run_replay(o.record, out, SculptOptions{true, false, false, false, ""});
    EXPECT_TRUE(test::bytes_of(dir / "run" / "sculpted.ply") == test::bytes_of(dir / "replay" / "sculpted.ply"))
        << "the replay (buttons included) sculpted a different model";
}

TEST(RunPeng, SceneRefusesPassesWithoutPengMovingAndTooManyMoves) {
    const fs::path dir = test::temp_dir("run_peng_bad");
    auto refused = [&](const std::string& edit, const std::string& field) {
        std::ifstream in(asset("peng_long_groove_scene.json"));
        nlohmann::json j = nlohmann::json::parse(in);
        j.merge_patch(nlohmann::json::parse(edit));
        j["workpiece"]["mesh"] = asset("bar.off");
        const std::string path = (dir / "bad.json").string();
        std::ofstream(path) << j.dump();
        try {
            (void)load_run_scene(path);
            ADD_FAILURE() << "accepted: " << edit;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    refused(R"({"workspace": {"mode": "scaling"}})", "stroke.passes");
    refused(R"({"stroke": {"moves": ["jump", "drag", "jump", "jump"]}})", "stroke.moves");
    refused(R"({"stroke": {"moves": ["hop"]}})", "stroke.moves[0]");
    refused(R"({"stroke": {"passes": 40}})", "stroke.passes");
}

}  // namespace
}  // namespace tridex::app
