// `tridex demo --op push`, `--op smooth`, `--op pull` and `--op grab` end to end: the scripted stroke pushes (smooths,
// grabs) the bunny, the report carries `deformation.max_displacement_m` and the volume within 2%, the recording replays
// and the journal recovers byte for byte, and the session journal names the op.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "test_files.hpp"

namespace {

using tridex::app::test::run_tridex;
namespace fs = std::filesystem;

std::string bytes_of(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

nlohmann::json report(const fs::path& dir) {
    std::ifstream f(dir / "report.json");
    return nlohmann::json::parse(f);
}

TEST(ClaySession, PushDemoDeformsKeepsVolumeAndReplaysByteForByte) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-clay-push";
    fs::remove_all(dir);
    const fs::path rec = dir / "push.trdx";
    const auto live = run_tridex("demo --op push --cpu --resolution 64 --seconds 1.5 --width 64 --height 48 --record " +
                                     rec.string() + " --out " + (dir / "live").string(),
                                 dir / "live");
    ASSERT_EQ(live.exit_code, 0) << live.err;
    const nlohmann::json j = report(dir / "live");
    EXPECT_EQ(j["settings"]["op"], "push");
    ASSERT_TRUE(j.contains("deformation")) << j.dump();
    const double moved = j["deformation"]["max_displacement_m"].get<double>();
    const double cell = j["workpiece"]["cell_m"].get<double>();
    EXPECT_GT(moved, 0.5 * cell) << "the push moved nothing";
    const double v0 = j["workpiece"]["volume_dexel_m3"].get<double>(), v1 = j["volume_after_m3"].get<double>();
    EXPECT_LT(std::fabs(v1 - v0) / v0, 0.02);
    EXPECT_EQ(j["mesh"]["boundary_edges"], 0);
    EXPECT_EQ(j["mesh"]["nonmanifold_edges"], 0);
    std::printf("push demo: max displacement %.2f mm (%.1f cells), volume change %.4f%%\n", 1e3 * moved, moved / cell,
                100.0 * (v1 - v0) / v0);

    const auto again = run_tridex(
        "replay " + rec.string() + " --cpu --width 64 --height 48 --out " + (dir / "replay").string(), dir / "replay");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    const std::string a = bytes_of(dir / "live" / "sculpted.ply"), b = bytes_of(dir / "replay" / "sculpted.ply");
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << "the replayed push sculpted a different model";
}

TEST(ClaySession, SmoothDemoRunsAndReports) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-clay-smooth";
    fs::remove_all(dir);
    const auto live = run_tridex(
        "demo --op smooth --cpu --resolution 64 --seconds 1 --width 64 --height 48 --out " + (dir / "live").string(),
        dir / "live");
    ASSERT_EQ(live.exit_code, 0) << live.err;
    const nlohmann::json j = report(dir / "live");
    EXPECT_EQ(j["settings"]["op"], "smooth");
    ASSERT_TRUE(j.contains("deformation"));
    const double v0 = j["workpiece"]["volume_dexel_m3"].get<double>(), v1 = j["volume_after_m3"].get<double>();
    EXPECT_LT(std::fabs(v1 - v0) / v0, 0.01);
    EXPECT_EQ(j["mesh"]["boundary_edges"], 0);
}

TEST(ClaySession, PullDemoRunsAndReports) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-clay-pull";
    fs::remove_all(dir);
    const auto live = run_tridex(
        "demo --op pull --cpu --resolution 64 --seconds 1 --width 64 --height 48 --out " + (dir / "live").string(),
        dir / "live");
    ASSERT_EQ(live.exit_code, 0) << live.err;
    const nlohmann::json j = report(dir / "live");
    EXPECT_EQ(j["settings"]["op"], "pull");
    ASSERT_TRUE(j.contains("deformation"));
    const double v0 = j["workpiece"]["volume_dexel_m3"].get<double>(), v1 = j["volume_after_m3"].get<double>();
    EXPECT_LT(std::fabs(v1 - v0) / v0, 0.02);
    EXPECT_EQ(j["mesh"]["boundary_edges"], 0);
    EXPECT_EQ(j["mesh"]["nonmanifold_edges"], 0);
}

TEST(ClaySession, GrabDemoMovesMaterialAndReplaysAndRecoversByteForByte) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-clay-grab";
    fs::remove_all(dir);
    const fs::path rec = dir / "grab.trdx";
    const auto live = run_tridex("demo --op grab --cpu --resolution 64 --seconds 1.5 --width 64 --height 48 --record " +
                                     rec.string() + " --out " + (dir / "live").string(),
                                 dir / "live");
    ASSERT_EQ(live.exit_code, 0) << live.err;
    const nlohmann::json j = report(dir / "live");
    EXPECT_EQ(j["settings"]["op"], "grab");
    ASSERT_TRUE(j.contains("deformation")) << j.dump();
    const double moved = j["deformation"]["max_displacement_m"].get<double>();
    const double cell = j["workpiece"]["cell_m"].get<double>();
    EXPECT_GT(moved, 2.0 * cell) << "the grab moved nothing";
    const double v0 = j["workpiece"]["volume_dexel_m3"].get<double>(), v1 = j["volume_after_m3"].get<double>();
    EXPECT_LT(std::fabs(v1 - v0) / v0, 0.02);
    EXPECT_EQ(j["mesh"]["boundary_edges"], 0);
    EXPECT_EQ(j["mesh"]["nonmanifold_edges"], 0);
    std::printf("grab demo: max displacement %.2f mm (%.1f cells), volume change %.4f%%\n", 1e3 * moved, moved / cell,
                100.0 * (v1 - v0) / v0);
    const std::string a = bytes_of(dir / "live" / "sculpted.ply");
    ASSERT_GT(a.size(), 1000u);
    const auto again = run_tridex(
        "replay " + rec.string() + " --cpu --width 64 --height 48 --out " + (dir / "replay").string(), dir / "replay");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    EXPECT_TRUE(a == bytes_of(dir / "replay" / "sculpted.ply")) << "the replayed grab sculpted a different model";
    // The same recording with the grab on the GPU clay kernel (lavapipe here): the same model.
    const auto on_gpu = run_tridex("replay " + rec.string() + " --gpu-clay --width 64 --height 48 --out " +
                                       (dir / "gpu").string(),
                                   dir / "gpu");
    ASSERT_EQ(on_gpu.exit_code, 0) << on_gpu.err;
    EXPECT_EQ(report(dir / "gpu")["clay_path"], "gpu");
    EXPECT_TRUE(a == bytes_of(dir / "gpu" / "sculpted.ply")) << "the GPU clay kernel's grab differs from the CPU's";
    const auto recovered = run_tridex(
        "recover " + (dir / "live" / "session.tdj").string() + " --out " + (dir / "rec").string(), dir / "recl");
    ASSERT_EQ(recovered.exit_code, 0) << recovered.err;
    EXPECT_TRUE(a == bytes_of(dir / "rec" / "sculpted.ply")) << "the recovered grab is a different model";
}

// `tridex run` with a push or grab scene reports how far the surface moved, as the demo does, and a subtract scene does
// not.
TEST(ClaySession, PushRunReportsHowFarTheSurfaceMoved) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-clay-run";
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const std::string op : {"push", "grab", "subtract"}) {
        const fs::path scene = dir / (op + ".json");
        std::ofstream(scene) << R"({"op": ")" << op
                             << R"(", "workpiece": {"resolution": 64}, "stroke": {"duration_s": 1.5},
                                   "display": {"preset": "desktop", "stereo": "mono", "resolution": [64, 48]}})";
        const auto run = run_tridex("run " + scene.string() + " --display offscreen --cpu --out " + (dir / op).string(),
                                    dir / (op + "_log"));
        ASSERT_EQ(run.exit_code, 0) << run.err;
        const nlohmann::json j = report(dir / op);
        if (op == "subtract") {
            EXPECT_TRUE(j["deformation"].is_null()) << j["deformation"];
            continue;
        }
        ASSERT_TRUE(j["deformation"].is_object()) << j["deformation"];
        const double moved = j["deformation"]["max_displacement_m"].get<double>();
        const double cell = j["workpiece"]["cell_m"].get<double>();
        EXPECT_GT(moved, 0.5 * cell) << "the " << op << " moved nothing";
        if (op == "push") {
            EXPECT_LT(moved, 0.05) << "a push of a 6 mm press cannot move the surface 5 cm";
        } else {  // a grab carries material along the stroke: as far as the measure looks (64 cells)
            EXPECT_LE(moved, 64.0 * cell * (1.0 + 1e-9));
        }
    }
}

}  // namespace
