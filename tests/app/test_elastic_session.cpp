// `tridex demo --elastic` end to end: the bundled squeeze ball is pressed in steps and released; the report shows the
// dent growing with every step and gone after the release, the force from the undeformed surface, and a bad scene
// field or an option that does not apply is refused with a message naming it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

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

}  // namespace
