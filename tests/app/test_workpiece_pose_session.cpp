// A posed workpiece in a `tridex run` session, end to end: the scene turns the bunny about its centre; the scripted
// stroke follows the turned surface and carves what it carves unturned (the samples are in the model's frame); the
// recording keeps the pose, so replay and recover give the live model byte for byte; a saved session writes the scene
// that opens the model where it was; bad pose fields are refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../test_paths.hpp"
#include "test_files.hpp"

namespace {

using tridex::app::test::bytes_of;
using tridex::app::test::read_json;
using tridex::app::test::run_tridex;
namespace fs = std::filesystem;

// The bundled squeeze-ball run scene without its ball, with `workpiece` fields merged in, at 160 x 120 px.
std::string write_scene(const fs::path& dir, const std::string& name, const std::string& workpiece) {
    const std::string path = (dir / name).string();
    std::ifstream in(std::string(TRIDEX_ASSETS_DIR) + "/squeeze_ball_run_scene.json");
    nlohmann::json j = nlohmann::json::parse(in);
    j["workpiece"]["mesh"] = std::string(TRIDEX_ASSETS_DIR) + "/bunny.off";
    j["workpiece"].update(nlohmann::json::parse(workpiece));
    j["display"] = {{"preset", "desktop"}, {"resolution", {160, 120}}, {"refresh_hz", 60}};
    j.erase("objects");
    std::ofstream(path) << j.dump(1);
    return path;
}

TEST(WorkpiecePoseSession, ATurnedBunnyIsCarvedInItsOwnFrameAndReplaysAndRecoversTheSame) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-workpiece-pose";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string turned = write_scene(dir, "turned.json", R"({"axis": [0, 1, 0], "angle_deg": 180})");
    const std::string plain = write_scene(dir, "plain.json", "{}");
    const auto live = run_tridex("run " + turned + " --display offscreen --validate --record " +
                                     (dir / "rec.trdx").string() + " --out " + (dir / "live").string(),
                                 dir / "live");
    ASSERT_EQ(live.exit_code, 0) << live.err;
    const nlohmann::json j = read_json(dir / "live" / "report.json");
    EXPECT_TRUE(j["stroke_completed"].get<bool>());
    EXPECT_EQ(j["validation_messages"], 0);
    // The pose: 180 degrees about +y through the centre (0, 0, 0.05): x and z flip, the centre stays.
    ASSERT_TRUE(j["workpiece"].contains("pose")) << j["workpiece"].dump();
    const nlohmann::json& pose = j["workpiece"]["pose"];
    ASSERT_TRUE(pose.is_object()) << j["workpiece"].dump();
    EXPECT_NEAR(pose["position_m"][2].get<double>(), 0.1, 1e-12);
    EXPECT_NEAR(std::abs(pose["orientation"][2].get<double>()), 1.0, 1e-12);
    EXPECT_TRUE(j["settings"]["workpiece_turn"].is_array()) << j["settings"].dump();
    // The same stroke on the unturned bunny removes the same volume: the hand followed the turned surface.
    const auto unturned = run_tridex("run " + plain + " --display offscreen --out " + (dir / "plain").string(),
                                     dir / "plain");
    ASSERT_EQ(unturned.exit_code, 0) << unturned.err;
    const nlohmann::json jp = read_json(dir / "plain" / "report.json");
    EXPECT_FALSE(jp["workpiece"].contains("pose"));
    EXPECT_FALSE(jp["settings"].contains("workpiece_turn"));  // unposed sessions keep their settings as before
    const double removed = j["volume_removed_m3"].get<double>();
    const double removed_plain = jp["volume_removed_m3"].get<double>();
    ASSERT_GT(removed_plain, 0.0);
    EXPECT_NEAR(removed / removed_plain, 1.0, 0.02) << removed << " vs " << removed_plain;
    // Replay (the recording's pose) and recover (the journal's model-frame samples) give the live model.
    const auto rp = run_tridex("replay " + (dir / "rec.trdx").string() + " --out " + (dir / "replay").string(),
                               dir / "replay");
    ASSERT_EQ(rp.exit_code, 0) << rp.err;
    EXPECT_EQ(bytes_of(dir / "replay" / "sculpted.ply"), bytes_of(dir / "live" / "sculpted.ply"));
    EXPECT_EQ(read_json(dir / "replay" / "report.json")["workpiece"]["pose"], pose);
    const auto rc = run_tridex("recover " + (dir / "live" / "session.tdj").string() + " --out " +
                                   (dir / "recovered").string(),
                               dir / "recovered");
    ASSERT_EQ(rc.exit_code, 0) << rc.err;
    EXPECT_EQ(bytes_of(dir / "recovered" / "sculpted.ply"), bytes_of(dir / "live" / "sculpted.ply"));
}

TEST(WorkpiecePoseSession, ASavedPosedSessionOpensWhereItWasAndAModelCanBePlacedElsewhere) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-workpiece-pose-save";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene = write_scene(dir, "scene.json", R"({"axis": [0, 0, 1], "angle_deg": 30})");
    const fs::path model = dir / "carved.tdx";
    const auto first = run_tridex("run " + scene + " --display offscreen --save " + model.string() + " --out " +
                                      (dir / "first").string(),
                                  dir / "first");
    ASSERT_EQ(first.exit_code, 0) << first.err;
    const fs::path saved = dir / "carved.scene.json";
    ASSERT_TRUE(fs::exists(saved)) << first.err;
    const nlohmann::json s = read_json(saved);
    EXPECT_NEAR(s["workpiece"]["angle_deg"].get<double>(), 30.0, 1e-9) << s.dump();
    const auto again = run_tridex("run " + saved.string() + " --display offscreen --seconds 1 --out " +
                                      (dir / "again").string(),
                                  dir / "again");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    const nlohmann::json j1 = read_json(dir / "first" / "report.json");
    const nlohmann::json j2 = read_json(dir / "again" / "report.json");
    EXPECT_NEAR(j2["volume_before_m3"].get<double>(), j1["volume_after_m3"].get<double>(), 1e-12);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(j2["workpiece"]["pose"]["position_m"][k].get<double>(),
                    j1["workpiece"]["pose"]["position_m"][k].get<double>(), 1e-9);
    for (int k = 0; k < 4; ++k)
        EXPECT_NEAR(j2["workpiece"]["pose"]["orientation"][k].get<double>(),
                    j1["workpiece"]["pose"]["orientation"][k].get<double>(), 1e-9);
    // The saved model placed elsewhere by a scene: its centre where the scene says, unturned.
    nlohmann::json moved = s;
    moved["workpiece"] = {{"model", model.string()}, {"position_m", {0.2, 0.0, 0.05}}};
    std::ofstream(dir / "moved.json") << moved.dump(1);
    const auto m = run_tridex("run " + (dir / "moved.json").string() + " --display offscreen --seconds 1 --out " +
                                  (dir / "moved").string(),
                              dir / "moved");
    ASSERT_EQ(m.exit_code, 0) << m.err;
    const nlohmann::json jm = read_json(dir / "moved" / "report.json");
    EXPECT_NEAR(jm["workpiece"]["pose"]["position_m"][0].get<double>(), 0.2, 1e-9) << jm["workpiece"].dump();
    EXPECT_NEAR(jm["workpiece"]["pose"]["orientation"][0].get<double>(), 1.0, 1e-12);
}

TEST(WorkpiecePoseSession, PlaceMovesTheWorkpieceWithTheHandAndTheReplayMovesItTheSame) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-workpiece-place";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::string scene = write_scene(dir, "scene.json", "{}");
    {  // the scripted hand holds the workpiece throughout its stroke (a simulated device has no engage button)
        std::ifstream in(scene);
        nlohmann::json j = nlohmann::json::parse(in);
        j["op"] = "place";
        std::ofstream(scene) << j.dump(1);
    }
    const auto live = run_tridex("run " + scene + " --display offscreen --validate --record " +
                                     (dir / "rec.trdx").string() + " --out " + (dir / "live").string(),
                                 dir / "live");
    ASSERT_EQ(live.exit_code, 0) << live.err;
    const nlohmann::json j = read_json(dir / "live" / "report.json");
    EXPECT_EQ(j["validation_messages"], 0);
    EXPECT_EQ(j["volume_removed_m3"].get<double>(), 0.0);  // placing carves nothing
    EXPECT_FALSE(j["workpiece"].contains("pose"));         // the scene did not pose it ...
    ASSERT_TRUE(j["workpiece"].contains("pose_end")) << j["workpiece"].dump();
    const nlohmann::json& end = j["workpiece"]["pose_end"];  // ... the hand moved it
    ASSERT_TRUE(end.is_object()) << j["workpiece"].dump();
    double moved = 0.0;
    for (int k = 0; k < 3; ++k) moved += std::pow(end["position_m"][k].get<double>(), 2.0);
    EXPECT_GT(std::sqrt(moved), 0.01) << end.dump();
    const auto rp = run_tridex("replay " + (dir / "rec.trdx").string() + " --out " + (dir / "replay").string(),
                               dir / "replay");
    ASSERT_EQ(rp.exit_code, 0) << rp.err;
    const nlohmann::json jr = read_json(dir / "replay" / "report.json");
    EXPECT_EQ(jr["workpiece"]["pose_end"], end) << jr["workpiece"].dump();
    EXPECT_EQ(bytes_of(dir / "replay" / "sculpted.ply"), bytes_of(dir / "live" / "sculpted.ply"));
}

TEST(WorkpiecePoseSession, BadPoseFieldsAreRefusedNamingThem) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-workpiece-pose-bad";
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto refused = [&](const std::string& fields, const std::string& want) {
        const std::string scene = write_scene(dir, "bad.json", fields);
        const auto r = run_tridex("run " + scene + " --display offscreen --out " + (dir / "o").string(), dir / "o");
        EXPECT_NE(r.exit_code, 0) << fields;
        EXPECT_NE(r.err.find(want), std::string::npos) << fields << "\n" << r.err;
    };
    refused(R"({"axis": [0, 0, 0], "angle_deg": 10})", "field 'workpiece.axis': must not be zero");
    refused(R"({"angle_deg": 400})", "field 'workpiece.angle_deg': must be in [-360, 360]");
    refused(R"({"axis": [0, 1]})", "field 'workpiece.axis'");
    refused(R"({"position_m": [0, 0, 0]})", "field 'workpiece.position_m': only with workpiece.model");
}

}  // namespace
