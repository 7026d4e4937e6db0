// A scene of two workpieces in a `tridex run` session, end to end: the scripted stroke is planned on the second (turned
// and placed apart); only the second is carved, in its own frame, and the report, the terminal and the files say so;
// the recording replays both byte for byte, each journal recovers its own workpiece, and the saved scene opens both
// where they were, and a changed second mesh is refused; the desk's "P" (workpiece.next) chooses the first, which the stroke then never touches.
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

// The bundled squeeze-ball run scene with two bunnies side by side instead of its workpiece and ball (the second turned
// 90 degrees about +y), the stroke planned on the second, at 160 x 120 px; `extra` merged in.
std::string write_scene(const fs::path& dir, const std::string& extra = "{}") {
    const std::string path = (dir / "two.json").string();
    std::ifstream in(std::string(TRIDEX_ASSETS_DIR) + "/squeeze_ball_run_scene.json");
    nlohmann::json j = nlohmann::json::parse(in);
    j.erase("objects");
    j.erase("workpiece");
    const std::string bunny = std::string(TRIDEX_ASSETS_DIR) + "/bunny.off";
    const fs::path second = dir / "second.off";  // its own copy, which a test may change
    fs::copy_file(bunny, second, fs::copy_options::overwrite_existing);
    j["workpieces"] = nlohmann::json::array(
        {{{"mesh", bunny}, {"resolution", 64}, {"stock_m", 0.1}, {"centre_m", {-0.07, 0.0, 0.05}}},
         {{"mesh", second.string()}, {"resolution", 64}, {"stock_m", 0.1}, {"centre_m", {0.07, 0.0, 0.05}},
          {"axis", {0, 1, 0}}, {"angle_deg", 90}}});
    j["stroke"]["workpiece"] = 1;
    j["display"] = {{"preset", "desktop"}, {"resolution", {160, 120}}, {"refresh_hz", 60}};
    j.update(nlohmann::json::parse(extra));
    std::ofstream(path) << j.dump(1);
    return path;
}

TEST(SeveralWorkpiecesSession, TheTouchedOneIsCarvedAloneAndReplaysRecoversAndReopensTheSame) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-several-workpieces";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene = write_scene(dir);
    const fs::path saved = dir / "carved.tdx";
    const auto live = run_tridex("run " + scene + " --display offscreen --validate --record " +
                                     (dir / "rec.trdx").string() + " --save " + saved.string() + " --out " +
                                     (dir / "live").string(),
                                 dir / "live");
    ASSERT_EQ(live.exit_code, 0) << live.err;
    const std::string said = bytes_of(dir / "live" / "stdout.txt");
    EXPECT_NE(said.find("workpiece 2: sculpt"), std::string::npos) << said;
    const nlohmann::json j = read_json(dir / "live" / "report.json");
    EXPECT_EQ(j["validation_messages"], 0);
    EXPECT_TRUE(j["stroke_completed"].get<bool>());
    EXPECT_EQ(j["volume_removed_m3"].get<double>(), 0.0);  // the first is never touched
    ASSERT_TRUE(j["more_workpieces"].is_array()) << j.dump();
    ASSERT_EQ(j["more_workpieces"].size(), 1u);
    const nlohmann::json& second = j["more_workpieces"][0];
    EXPECT_GT(second["volume_removed_m3"].get<double>(), 1e-6) << second.dump();  // a groove of a few cm^3
    EXPECT_NEAR(std::abs(second["pose"]["orientation"][2].get<double>()), std::sqrt(0.5), 1e-12);
    EXPECT_EQ(second["journal"], (dir / "live" / "session-wp2.tdj").string());
    for (const char* f : {"sculpted.ply", "sculpted-wp2.ply", "session.tdj", "session-wp2.tdj"})
        EXPECT_TRUE(fs::exists(dir / "live" / f)) << f;
    // The replay carves both as the session did; each journal recovers its own workpiece.
    const auto rp = run_tridex("replay " + (dir / "rec.trdx").string() + " --out " + (dir / "replay").string(),
                               dir / "replay");
    ASSERT_EQ(rp.exit_code, 0) << rp.err;
    EXPECT_EQ(bytes_of(dir / "replay" / "sculpted.ply"), bytes_of(dir / "live" / "sculpted.ply"));
    EXPECT_EQ(bytes_of(dir / "replay" / "sculpted-wp2.ply"), bytes_of(dir / "live" / "sculpted-wp2.ply"));
    const auto rc = run_tridex("recover " + (dir / "live" / "session-wp2.tdj").string() + " --out " +
                                   (dir / "recovered").string(),
                               dir / "recovered");
    ASSERT_EQ(rc.exit_code, 0) << rc.err;
    EXPECT_EQ(bytes_of(dir / "recovered" / "sculpted.ply"), bytes_of(dir / "live" / "sculpted-wp2.ply"));
    // The saved scene opens both models where they were.
    ASSERT_TRUE(fs::exists(dir / "carved-wp2.tdx"));
    const auto again = run_tridex("run " + (dir / "carved.scene.json").string() + " --display offscreen --seconds 0.5 --out " +
                                      (dir / "again").string(),
                                  dir / "again");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    const nlohmann::json ja = read_json(dir / "again" / "report.json");
    ASSERT_EQ(ja["more_workpieces"].size(), 1u);
    EXPECT_NEAR(ja["more_workpieces"][0]["volume_before_m3"].get<double>(), second["volume_after_m3"].get<double>(), 1e-12);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(ja["more_workpieces"][0]["pose"]["position_m"][k].get<double>(),
                    second["pose"]["position_m"][k].get<double>(), 1e-9);
    // A second mesh changed since the recording would carve another model: the replay refuses it by name.
    std::ofstream(dir / "second.off", std::ios::app) << "\n";
    const auto changed = run_tridex("replay " + (dir / "rec.trdx").string() + " --out " + (dir / "changed").string(),
                                    dir / "changed");
    EXPECT_NE(changed.exit_code, 0);
    EXPECT_NE(changed.err.find("the workpiece mesh " + (dir / "second.off").string() + " changed since the recording"),
              std::string::npos) << changed.err;
}

TEST(SeveralWorkpiecesSession, ChoosingTheFirstLeavesTheTouchedSecondUncarved) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-several-workpieces-choose";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene = write_scene(dir, R"({"keys": [{"t_s": 0.05, "press": "p"}]})");
    const auto r = run_tridex("run " + scene + " --display offscreen --record " + (dir / "rec.trdx").string() +
                                  " --out " + (dir / "live").string(),
                              dir / "live");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = read_json(dir / "live" / "report.json");
    // The tool carves the first only, which it never reaches: neither loses material.
    EXPECT_EQ(j["more_workpieces"][0]["volume_removed_m3"].get<double>(), 0.0) << j["more_workpieces"].dump();
    EXPECT_EQ(j["volume_removed_m3"].get<double>(), 0.0);
    const auto rp = run_tridex("replay " + (dir / "rec.trdx").string() + " --out " + (dir / "replay").string(),
                               dir / "replay");
    ASSERT_EQ(rp.exit_code, 0) << rp.err;
    EXPECT_EQ(bytes_of(dir / "replay" / "sculpted-wp2.ply"), bytes_of(dir / "live" / "sculpted-wp2.ply"));
}

}  // namespace
