// Reference objects in a `tridex run` session, end to end: a closed mesh placed on the scripted stroke's path is felt
// (the report's object force) and drawn, never sculpted; the recording carries it, so a replay feels it the same and
// carves the same model; a changed mesh file is refused by the replay; bad scene fields are refused naming them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../test_paths.hpp"
#include "cube_off.hpp"
#include "test_files.hpp"

namespace {

using tridex::app::test::bytes_of;
using tridex::app::test::read_json;
using tridex::app::test::run_tridex;
namespace test = tridex::app::test;
namespace fs = std::filesystem;

// The bundled squeeze-ball run scene with `references` (JSON) instead of its ball, at 160 x 120 px.
std::string write_scene(const fs::path& dir, const std::string& references) {
    const std::string path = (dir / "scene.json").string();
    std::ifstream in(std::string(TRIDEX_ASSETS_DIR) + "/squeeze_ball_run_scene.json");
    nlohmann::json j = nlohmann::json::parse(in);
    j["workpiece"]["mesh"] = std::string(TRIDEX_ASSETS_DIR) + "/bunny.off";
    j["display"] = {{"preset", "desktop"}, {"resolution", {160, 120}}, {"refresh_hz", 60}};
    j.erase("objects");
    if (!references.empty()) j["references"] = nlohmann::json::parse(references);
    std::ofstream(path) << j.dump(1);
    return path;
}

TEST(ReferenceSession, ACubeOnTheStrokesPathIsFeltDrawnAndReplayedTheSame) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-reference-run";
    fs::remove_all(dir);
    fs::create_directories(dir);
    test::write_cube_off(dir / "cube.off");
    // Where the bundled scene's squeeze ball sits: the stroke passes through it.
    const std::string scene = write_scene(
        dir, R"([{"name": "stone", "mesh": "cube.off", "size_m": 0.024, "position_m": [-0.006, -0.011, 0.09],
                 "axis": [0, 1, 0], "angle_deg": 20, "colour": [0.5, 0.5, 0.55]}])");
    const auto live = run_tridex("run " + scene + " --display offscreen --validate --record " +
                                     (dir / "rec.trdx").string() + " --out " + (dir / "live").string(),
                                 dir / "live");
    ASSERT_EQ(live.exit_code, 0) << live.err;
    const nlohmann::json j = read_json(dir / "live" / "report.json");
    EXPECT_GT(j["haptics"]["object_contact_ticks"].get<int>(), 10) << j["haptics"].dump();
    EXPECT_GT(j["haptics"]["max_object_force_n"].get<double>(), 0.2) << j["haptics"].dump();
    EXPECT_TRUE(j["stroke_completed"].get<bool>());
    EXPECT_EQ(j["validation_messages"], 0);
    const nlohmann::json& r = j["references"];
    ASSERT_EQ(r.size(), 1u) << j.dump();
    EXPECT_EQ(r[0]["name"], "stone");
    EXPECT_EQ(r[0]["triangles"], 12);
    EXPECT_EQ(r[0]["grid"]["cell_m"].get<double>(), 0.0005);  // 24 mm / 96 is finer than the 0.5 mm floor
    EXPECT_TRUE(j["settings"]["references"].is_array()) << j["settings"].dump();
    // Never sculpted: the bunny was carved, the cube is not part of the model. The replay feels it (the same
    // contact ticks) and carves the same model byte for byte.
    EXPECT_GT(j["volume_removed_m3"].get<double>(), 0.0);
    const auto rp = run_tridex("replay " + (dir / "rec.trdx").string() + " --out " + (dir / "replay").string(),
                               dir / "replay");
    ASSERT_EQ(rp.exit_code, 0) << rp.err;
    const nlohmann::json jr = read_json(dir / "replay" / "report.json");
    EXPECT_EQ(jr["haptics"]["object_contact_ticks"], j["haptics"]["object_contact_ticks"]);
    EXPECT_EQ(bytes_of(dir / "replay" / "sculpted.ply"), bytes_of(dir / "live" / "sculpted.ply"));
    // Without the cube the same stroke feels no object.
    const std::string plain = write_scene(dir, "");
    const auto none = run_tridex("run " + plain + " --display offscreen --out " + (dir / "plain").string(), dir / "plain");
    ASSERT_EQ(none.exit_code, 0) << none.err;
    EXPECT_EQ(read_json(dir / "plain" / "report.json")["haptics"]["object_contact_ticks"], 0);
    EXPECT_TRUE(read_json(dir / "plain" / "report.json")["references"].is_null());
    // A reference mesh that changed after the recording: the replay refuses it.
    std::ofstream(dir / "cube.off", std::ios::app) << "\n";
    const auto changed = run_tridex("replay " + (dir / "rec.trdx").string() + " --out " + (dir / "changed").string(),
                                    dir / "changed");
    EXPECT_NE(changed.exit_code, 0);
    EXPECT_NE(changed.err.find("the reference mesh " + fs::absolute(dir / "cube.off").lexically_normal().string() +
                               " changed since"),
              std::string::npos)
        << changed.err;
    EXPECT_NE(changed.err.find("it would feel different"), std::string::npos) << changed.err;
    // The journal needs no reference mesh: the samples hold what the hand did, so recover rebuilds the model.
    const auto recovered = run_tridex("recover " + (dir / "live" / "session.tdj").string() + " --out " +
                                          (dir / "recovered").string(),
                                      dir / "recovered");
    ASSERT_EQ(recovered.exit_code, 0) << recovered.err;
    EXPECT_EQ(bytes_of(dir / "recovered" / "sculpted.ply"), bytes_of(dir / "live" / "sculpted.ply"));
}

TEST(ReferenceSession, ASavedSessionWritesTheSceneThatOpensTheModelWithItsReferences) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-reference-save";
    fs::remove_all(dir);
    fs::create_directories(dir);
    test::write_cube_off(dir / "cube.off");
    const std::string scene = write_scene(
        dir, R"([{"name": "stone", "mesh": "cube.off", "size_m": 0.024, "position_m": [-0.006, -0.011, 0.09]},
                {"name": "stand", "mesh": "cube.off", "size_m": 0.05, "position_m": [0.1, 0.0, 0.05],
                 "axis": [0, 0, 1], "angle_deg": 45}])");
    const fs::path model = dir / "kept" / "carved.tdx";
    fs::create_directories(model.parent_path());
    const auto first = run_tridex("run " + scene + " --display offscreen --save " + model.string() + " --out " +
                                      (dir / "first").string(),
                                  dir / "first");
    ASSERT_EQ(first.exit_code, 0) << first.err;
    const fs::path saved = dir / "kept" / "carved.scene.json";
    ASSERT_TRUE(fs::exists(saved)) << first.err;
    const nlohmann::json j1 = read_json(dir / "first" / "report.json");
    bool listed = false;
    for (const auto& f : j1["files"]) listed = listed || f.get<std::string>() == saved.string();
    EXPECT_TRUE(listed) << j1["files"].dump();
    // Opened again: the carved model and both references, no stroke.
    const auto again = run_tridex("run " + saved.string() + " --display offscreen --seconds 1 --out " +
                                      (dir / "again").string(),
                                  dir / "again");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    const nlohmann::json j2 = read_json(dir / "again" / "report.json");
    EXPECT_NEAR(j2["volume_before_m3"].get<double>(), j1["volume_after_m3"].get<double>(), 1e-12);
    ASSERT_EQ(j2["references"].size(), 2u) << j2.dump();
    EXPECT_EQ(j2["references"][1]["name"], "stand");
    EXPECT_EQ(j2["references"][1]["position_m"], j1["references"][1]["position_m"]);
    EXPECT_EQ(j2["volume_removed_m3"].get<double>(), 0.0);
}

TEST(ReferenceSession, BadReferencesAreRefusedNamingTheFieldOrTheFile) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-reference-bad";
    fs::remove_all(dir);
    fs::create_directories(dir);
    test::write_cube_off(dir / "cube.off");
    auto refused = [&](const std::string& refs, const std::string& want) {
        const std::string scene = write_scene(dir, refs);
        const auto r = run_tridex("run " + scene + " --display offscreen --out " + (dir / "o").string(), dir / "o");
        EXPECT_NE(r.exit_code, 0) << refs;
        EXPECT_NE(r.err.find(want), std::string::npos) << refs << "\n" << r.err;
    };
    refused(R"([{"mesh": "cube.off", "axis": [0, 0, 0], "angle_deg": 10}])",
            "field 'references[0].axis': must not be zero");
    refused(R"([{"mesh": "missing.off"}])", "field 'references[0].mesh': no such file");
    refused(R"([{"mesh": "cube.off", "size_m": -1}])", "field 'references[0].size_m'");
    refused(R"([{"mesh": "cube.off", "colour": [1, 2, 0]}])", "field 'references[0].colour'");
    refused(R"([{"mesh": "cube.off", "spin": 1}])", "field 'references[0].spin': unknown field");
    refused(R"([])", "field 'references': must be an array of 1 to 8");
    // An open mesh cannot be felt (no inside): refused with the loader's reason, naming the reference.
    std::ofstream(dir / "open.off") << "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
    refused(R"([{"name": "sheet", "mesh": "open.off"}])", "reference 'sheet': ");
}

}  // namespace
