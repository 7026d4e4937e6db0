// `tridex demo --elastic` end to end: the bundled squeeze ball is pressed in steps and released; the report shows the
// dent growing with every step and gone after the release, the force from the undeformed surface, and a bad scene
// field or an option that does not apply is refused with a message naming it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../test_paths.hpp"
#include "test_files.hpp"

namespace {

using tridex::app::test::run_tridex;
namespace fs = std::filesystem;

TEST(ElasticSession, SqueezeBallDentsAndSpringsBack) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-elastic";
    fs::remove_all(dir);
    const auto r = run_tridex("demo --elastic --validate --width 96 --height 72 --out " + dir.string(), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream f(dir / "report.json");
    const nlohmann::json j = nlohmann::json::parse(f);
    const nlohmann::json& d = j["deformation"];
    const nlohmann::json& steps = j["steps"];
    ASSERT_EQ(steps.size(), 5u) << j.dump();  // four depths, then the release
    const double k = j["object"]["stiffness_n_per_m"].get<double>();
    double last = 0.0;
    for (std::size_t i = 0; i + 1 < steps.size(); ++i) {
        const double shown = steps[i]["max_displacement_m"].get<double>();
        const double pen = steps[i]["penetration_m"].get<double>();
        EXPECT_GT(shown, last) << i;
        EXPECT_NEAR(shown, pen, 0.05 * pen) << i;  // the drawn surface follows the tool's deepest point
        EXPECT_NEAR(steps[i]["force_n"].get<double>(), k * pen, 1e-6) << i;  // from the undeformed surface
        last = shown;
    }
    EXPECT_TRUE(d["grows_monotonically"].get<bool>());
    EXPECT_NEAR(d["max_displacement_m"].get<double>(), last, 1e-12);
    EXPECT_LT(d["residual_displacement_m"].get<double>(), 1e-9);
    EXPECT_EQ(steps.back()["force_n"].get<double>(), 0.0);
    EXPECT_EQ(j["render"]["validation_messages"], 0);
    for (const char* png : {"left.png", "right.png", "sbs.png", "released.png", "haptics.csv"})
        EXPECT_GT(fs::file_size(dir / png), 100u) << png;
}

TEST(ElasticSession, RefusesBadFieldsAndOptionsThatDoNotApply) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-elastic-bad";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path scene = dir / "ball.json";
    {
        std::ofstream s(scene);
        s << R"({ "objects": [ { "radius_m": 0.02, "influence_radius_m": 0.03 } ] })";
    }
    const auto bad = run_tridex("demo --elastic --scene " + scene.string() + " --out " + (dir / "a").string(), dir / "a");
    EXPECT_NE(bad.exit_code, 0);
    EXPECT_NE(bad.err.find(scene.string() + ": field 'objects[0].influence_radius_m'"), std::string::npos) << bad.err;
    {
        std::ofstream s(scene);
        s << R"({ "objects": [ { "elastic": false } ] })";
    }
    const auto rigid = run_tridex("demo --elastic --scene " + scene.string() + " --out " + (dir / "b").string(), dir / "b");
    EXPECT_NE(rigid.exit_code, 0);
    EXPECT_NE(rigid.err.find("field 'press.object'"), std::string::npos) << rigid.err;
    const auto op = run_tridex("demo --elastic --op push --out " + (dir / "c").string(), dir / "c");
    EXPECT_NE(op.exit_code, 0);
    EXPECT_NE(op.err.find("--elastic: --op does not apply"), std::string::npos) << op.err;
    const auto scene_only = run_tridex("demo --scene " + scene.string() + " --out " + (dir / "d").string(), dir / "d");
    EXPECT_NE(scene_only.exit_code, 0);
    EXPECT_NE(scene_only.err.find("--scene: only with --elastic"), std::string::npos) << scene_only.err;
}

// A `tridex run` scene with the bundled squeeze ball beside the bunny, on the scripted stroke's path, at 96 x 72 px per
// eye; `elastic` false makes the ball rigid, no "objects" leaves it out.
std::string write_ball_scene(const fs::path& dir, const char* objects) {
    const std::string path = (dir / "scene.json").string();
    std::ifstream in(std::string(TRIDEX_ASSETS_DIR) + "/squeeze_ball_run_scene.json");
    nlohmann::json j = nlohmann::json::parse(in);
    j["workpiece"]["mesh"] = std::string(TRIDEX_ASSETS_DIR) + "/bunny.off";
    j["display"] = {{"preset", "desktop"}, {"resolution", {96, 72}}, {"refresh_hz", 60}};
    if (objects) j["objects"] = nlohmann::json::parse(objects);
    else j.erase("objects");
    std::ofstream(path) << j.dump(1);
    return path;
}

nlohmann::json read_report(const fs::path& dir) {
    std::ifstream f(dir / "report.json");
    return nlohmann::json::parse(f);
}

TEST(ElasticSession, ARunFeelsAndDrawsTheSceneBallAndItSpringsBackAfterTheStroke) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-elastic-run";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // Without the ball: the stroke only touches the bunny.
    const std::string plain = write_ball_scene(dir, nullptr);
    const auto r0 = run_tridex("run " + plain + " --display offscreen --validate --out " + (dir / "plain").string(), dir / "plain");
    ASSERT_EQ(r0.exit_code, 0) << r0.err;
    const nlohmann::json j0 = read_report(dir / "plain");
    EXPECT_TRUE(j0["deformation"].is_null());
    // With the bundled elastic ball: felt (a larger force where the stroke passes through it), drawn dented while
    // pressed, back to its reference once the tool has left; the recording carries it, so a replay feels it too.
    std::ifstream in(std::string(TRIDEX_ASSETS_DIR) + "/squeeze_ball_run_scene.json");
    const std::string ball = nlohmann::json::parse(in)["objects"].dump();
    const std::string elastic = write_ball_scene(dir, ball.c_str());
    const auto r1 = run_tridex("run " + elastic + " --display offscreen --validate --record " + (dir / "ball.trdx").string() +
                                   " --out " + (dir / "ball").string(),
                               dir / "ball");
    ASSERT_EQ(r1.exit_code, 0) << r1.err;
    const nlohmann::json j1 = read_report(dir / "ball");
    ASSERT_TRUE(j1["deformation"].is_object()) << j1.dump();
    const nlohmann::json& d = j1["deformation"];
    EXPECT_GT(d["max_displacement_m"].get<double>(), 1e-3) << d.dump();
    EXPECT_EQ(d["residual_displacement_m"].get<double>(), 0.0) << d.dump();
    EXPECT_GE(d["objects"][0]["frames_pressed"].get<int>(), 1) << d.dump();
    EXPECT_EQ(d["objects"][0]["name"], "squeeze_ball");
    EXPECT_TRUE(j1["stroke_completed"].get<bool>());
    EXPECT_EQ(j1["validation_messages"], 0);
    // Felt: the ball's own part of the contact force (the total is capped at the Omni's 0.88 N, which the bunny's
    // contact alone can reach on a loaded machine).
    EXPECT_EQ(j0["haptics"]["object_contact_ticks"], 0);
    EXPECT_EQ(j0["haptics"]["max_object_force_n"].get<double>(), 0.0);
    EXPECT_GT(j1["haptics"]["object_contact_ticks"].get<int>(), 10) << j1["haptics"].dump();
    EXPECT_GT(j1["haptics"]["max_object_force_n"].get<double>(), 0.2) << j1["haptics"].dump();
    const double ball_force = j1["haptics"]["max_force_n"].get<double>();
    const auto rp = run_tridex("replay " + (dir / "ball.trdx").string() + " --out " + (dir / "replay").string(), dir / "replay");
    ASSERT_EQ(rp.exit_code, 0) << rp.err;
    // The replay runs unpaced, so its sculpt thread's snapshots meet the ticks at other moments than live: the peak
    // force (near the Omni's 0.88 N cap) agrees within 15 %.
    EXPECT_NEAR(read_report(dir / "replay")["haptics"]["max_force_n"].get<double>(), ball_force, 0.15 * ball_force);
    // A rigid ball: felt the same way, never drawn dented.
    const std::string rigid = write_ball_scene(
        dir, R"([{"name": "stone", "elastic": false, "centre_m": [-0.006, -0.011, 0.09], "radius_m": 0.012,
                 "stiffness_n_per_m": 300, "influence_radius_m": 0.008}])");
    const auto r2 = run_tridex("run " + rigid + " --display offscreen --out " + (dir / "rigid").string(), dir / "rigid");
    ASSERT_EQ(r2.exit_code, 0) << r2.err;
    const nlohmann::json j2 = read_report(dir / "rigid");
    EXPECT_EQ(j2["deformation"]["max_displacement_m"].get<double>(), 0.0);
    EXPECT_GE(j2["deformation"]["objects"][0]["frames_pressed"].get<int>(), 1);
    EXPECT_GT(j2["haptics"]["object_contact_ticks"].get<int>(), 10) << j2["haptics"].dump();
    EXPECT_GT(j2["haptics"]["max_object_force_n"].get<double>(), 0.2) << j2["haptics"].dump();
}

TEST(ElasticSession, ARunSceneRefusesABadObjectNamingItsField) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-elastic-run-bad";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene = write_ball_scene(dir, R"([{"radius_m": -0.01}])");
    const auto r = run_tridex("run " + scene + " --display offscreen --out " + (dir / "o").string(), dir / "o");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(scene + ": field 'objects[0].radius_m'"), std::string::npos) << r.err;
}

}  // namespace
