// The newcomer's deep cut: the mouse stylus, its wheel turned to the deepest press, dragged across the default scene's
// bunny (128 cells, offscreen, a scripted cursor). The cut leaves specks of the groove's thin lips floating; they are
// removed when the stroke ends, so the carved mesh is one part (report.json sculpt.islands_removed counts them). The
// recording replays, and the journal recovers, to the same model bytes; a replay with --keep-islands keeps them.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands/recover/recover.hpp"
#include "app/commands/replay/replay.hpp"
#include "app/session/run/run_session.hpp"
#include "compute/mesh/mesh_io.hpp"
#include "compute/model/tdx_file.hpp"
#include "run_test_scene.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 480, kH = 270;  // the default scene's 960 x 540 eye, halved
const Vec3 kEye(0.0, 0.05, 0.6);
const renderer::Screen kScreen = renderer::Screen::desktop_monitor();

// The pixel (of a kW x kH eye image) where the ray from kEye through world point p crosses the screen.
std::pair<double, double> pixel_of(const Vec3& p) {
    const Vec3 s = kEye + (p - kEye) * (kEye.z / (kEye.z - p.z));
    const double u = (s.x - kScreen.lower_left.x) / kScreen.width();
    const double v = (s.y - kScreen.lower_left.y) / kScreen.height();
    return {u * kW, (1.0 - v) * kH};
}

// The default scene's workpiece, tool and head with the mouse: the cursor rests on the bunny at x = -45 mm, the wheel
// turns ten steps deeper (to two radii, the deepest), the left button goes down and the cursor drags across to
// x = +45 mm, and the button comes up.
std::string write_scene(const fs::path& dir) {
    const auto [x0, y0] = pixel_of(Vec3(-0.045, 0.0, 0.05));
    const auto [x1, y1] = pixel_of(Vec3(0.045, 0.0, 0.05));
    const auto point = [](double t, double x, double y, int buttons, int wheel = 0) {
        return "{\"t_s\": " + std::to_string(t) + ", \"x_px\": " + std::to_string(x) + ", \"y_px\": " + std::to_string(y) +
               ", \"buttons\": " + std::to_string(buttons) + ", \"wheel\": " + std::to_string(wheel) + "}";
    };
    const std::string path = (dir / "deep_cut_scene.json").string();
    std::ofstream(path) << R"({
  "workpiece": { "resolution": 128, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006, "stiffness_n_per_m": 700, "damping_n_s_per_m": 0.5 },
  "device": { "driver": "mouse" },
  "stroke": "none",
  "display": { "preset": "desktop", "stereo": "mono", "resolution": [)" << kW << ", " << kH << R"(], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] },
  "cursor": [ )" << point(0.2, x0, y0, 0) << ", " << point(0.3, x0, y0, 0, 10) << ", " << point(0.8, x0, y0, 1) << ", "
                  << point(3.8, x1, y1, 1) << ", " << point(4.3, x1, y1, 0) << ", " << point(4.5, x1, y1, 0) << R"( ]
}
)";
    return path;
}

std::size_t parts(const fs::path& ply) { return mesh_components(compute::load_closed_mesh(ply.string())); }

// Rays whose intervals differ between two models (depth bits and materials).
std::size_t differing_rays(const compute::TriDexel& a, const compute::TriDexel& b) {
    std::size_t n = 0;
    for (int s = 0; s < 3; ++s)
        for (std::size_t r = 0; r < a.sets[s].rays.size(); ++r) {
            const auto &x = a.sets[s].rays[r], &y = b.sets[s].rays[r];
            bool same = x.size() == y.size();
            for (std::size_t k = 0; same && k < x.size(); ++k)
                same = std::memcmp(&x[k].enter, &y[k].enter, sizeof(float)) == 0 &&
                       std::memcmp(&x[k].exit, &y[k].exit, sizeof(float)) == 0 &&
                       x[k].enter_material == y[k].enter_material && x[k].exit_material == y[k].exit_material;
            n += same ? 0 : 1;
        }
    return n;
}

TEST(DeepCut, TheNewcomersDeepMouseCutLeavesOnePartAndReplaysToTheSameModel) {
    const fs::path dir = test::temp_dir("deep_cut");
    RunOptions o;
    o.scene = write_scene(dir);
    o.display = "offscreen";
    o.out = (dir / "run").string();
    o.record = (dir / "run.trdx").string();
    o.save = (dir / "run.tdx").string();
    o.cpu = true;  // the CPU reference: bit-identical to the GPU path (tests/compute/test_sculpt_history_islands.cpp)
    const RunResult live = run_stereo_session(o);
    ASSERT_EQ(live.notes.front(), "ended: the scripted cursor ended");
    const nlohmann::json rep = test::read_json(dir / "run" / "report.json");
    ASSERT_FALSE(rep["mouse"].is_null());
    EXPECT_DOUBLE_EQ(rep["mouse"]["depth_m"].get<double>(), 0.012) << "the wheel took the depth to two radii";
    EXPECT_GT(live.volume_before_m3 - live.volume_after_m3, 1e-6) << "the drag carved a deep groove";
    const std::uint64_t removed = rep["sculpt"]["islands_removed"].get<std::uint64_t>();
    EXPECT_GE(removed, 1u) << "the deep cut leaves specks (the groove's thin lips)";
    EXPECT_EQ(live.sculpt.islands.specks, removed);
    EXPECT_EQ(rep["mesh"]["components"], 1);
    EXPECT_EQ(parts(dir / "run" / "sculpted.ply"), 1u);

    // The recording replays with the live session's setting (in its header) to the same model, byte for byte.
    OutputOptions out;
    out.width = 64;
    out.height = 48;
    out.out = (dir / "replay").string();
    run_replay(o.record, out, SculptOptions{true, false, false, false, ""}, (dir / "replay.tdx").string());
    EXPECT_EQ(test::bytes_of(dir / "replay" / "sculpted.ply"), test::bytes_of(dir / "run" / "sculpted.ply"));
    EXPECT_EQ(test::read_json(dir / "replay" / "report.json")["sculpt"]["islands_removed"], removed);
    const compute::TdxModel a = compute::load_tdx(o.save, std::size_t{1} << 32);
    const compute::TdxModel b = compute::load_tdx((dir / "replay.tdx").string(), std::size_t{1} << 32);
    EXPECT_EQ(differing_rays(a.model, b.model), 0u);

    // The journal recovers to the same model.
    run_recover((dir / "run" / "session.tdj").string(), (dir / "recover").string());
    EXPECT_EQ(test::bytes_of(dir / "recover" / "sculpted.ply"), test::bytes_of(dir / "run" / "sculpted.ply"));
    EXPECT_EQ(test::read_json(dir / "recover" / "report.json")["islands_removed"], removed);

    // --keep-islands keeps the specks: the mesh has a part for each (what the session showed before removal).
    out.out = (dir / "keep").string();
    run_replay(o.record, out, SculptOptions{true, false, false, false, ""}, "", {}, true);
    const nlohmann::json keep = test::read_json(dir / "keep" / "report.json");
    EXPECT_EQ(keep["sculpt"]["islands_removed"], 0);
    EXPECT_EQ(keep["settings"]["keep_islands"], true);
    const std::size_t kept_parts = parts(dir / "keep" / "sculpted.ply");
    EXPECT_EQ(kept_parts, removed + 1);
    EXPECT_EQ(keep["mesh"]["components"], kept_parts);
    std::printf("[deep cut] mesh parts: %zu with --keep-islands, %d after removal; %llu specks removed (%.3g mm^3), "
                "island search median %.2f ms\n",
                kept_parts, rep["mesh"]["components"].get<int>(), static_cast<unsigned long long>(removed),
                rep["sculpt"]["island_volume_m3"].get<double>() * 1e9, rep["sculpt"]["island_search_ms"]["median"].get<double>());
    if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
