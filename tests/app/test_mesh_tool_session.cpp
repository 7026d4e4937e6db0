// tests/app/test_mesh_tool_session.cpp - sessions with a closed-mesh tool: the tool placed on its tip, the spec
// and its JSON, scene refusals naming 'tool.mesh', a `tridex run` that carves, records and replays to the same
// sculpted.ply byte for byte, and a replay that refuses a changed tool mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "test_files.hpp"
#include "app/commands/replay/replay.hpp"
#include "app/scene/run_scene.hpp"
#include "app/session/run/run_session.hpp"
#include "app/session/batch/session.hpp"
#include "app/scene/session_spec.hpp"
#include "app/scene/tool_mesh.hpp"
#include "core/error.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

std::string env_or(const char* name, const std::string& fallback) {
    const char* v = std::getenv(name);
    return v ? v : fallback;
}

std::string tool_asset() { return env_or("TRIDEX_ASSETS", "assets") + "/spatula_tool.off"; }
std::string shared_data() { return env_or("TRIDEX_SHARED_DATA", "../shared/data"); }

// The bunny at 48 cells, the bundled spatula tool (16 mm) pressed from above, the Omni.
std::string write_mesh_tool_scene(const fs::path& dir, const std::string& tool_mesh) {
    const std::string path = (dir / "mesh_tool.json").string();
    std::ofstream(path) << R"({
  "workpiece": { "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "shape": "mesh", "mesh": ")" << tool_mesh << R"(", "size_m": 0.016 },
  "haptics": { "points": 24 },
  "stroke": { "duration_s": 0.8, "length_m": 0.05, "depth_m": 0.004, "press_axis": "y" },
  "display": { "preset": "desktop", "resolution": [96, 72], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.1, 0.6] }
})";
    return path;
}

TEST(MeshToolSession, ToolMeshIsScaledToItsSizeWithItsTipOnTheOrigin) {
    const TriMesh m = load_tool_mesh(tool_asset(), 0.016);
    const Aabb b = m.bounds();
    const Vec3 size = b.size();
    EXPECT_NEAR(std::max({size.x, size.y, size.z}), 0.016, 1e-12);
    EXPECT_NEAR(b.lo.y, 0.0, 1e-15);                  // the tip is the lowest point along the axis
    EXPECT_NEAR(b.lo.x + b.hi.x, 0.0, 1e-12);         // centred across the axis
    EXPECT_NEAR(b.lo.z + b.hi.z, 0.0, 1e-12);
    EXPECT_NEAR(tool_mesh_reach_m(m, 1), 0.0, 1e-15);  // pressed from above it reaches no lower than its tip
    EXPECT_GT(tool_mesh_reach_m(m, 2), 0.0);
    EXPECT_THROW(load_tool_mesh(tool_asset(), 0.0), Error);
}

TEST(MeshToolSession, SpecCarriesTheToolMeshThroughJsonAndValidation) {
    SessionSpec s;
    set_tool_mesh(s, tool_asset(), 0.016, "--tool-mesh");
    EXPECT_EQ(s.tool.kind, ToolKind::kMesh);
    EXPECT_TRUE(fs::path(s.tool_mesh_path).is_absolute());
    EXPECT_GT(s.tool_mesh_bytes, 0u);
    EXPECT_GT(s.tool.radius_m, 0.016 * 0.9);
    s.points = 16;
    validate_spec(s, "spec");
    const SessionSpec back = spec_from_json(spec_to_json(s), "back");
    EXPECT_EQ(back.tool.kind, ToolKind::kMesh);
    EXPECT_EQ(back.tool_mesh_path, s.tool_mesh_path);
    EXPECT_EQ(back.tool_size_m, s.tool_size_m);
    EXPECT_EQ(back.tool_mesh_crc32, s.tool_mesh_crc32);
    EXPECT_EQ(back.tool_mesh_bytes, s.tool_mesh_bytes);
    EXPECT_EQ(back.tool.radius_m, s.tool.radius_m);
    const haptics::HapticLoopConfig cfg = loop_config(back, 0);
    EXPECT_EQ(cfg.tool.kind, ToolKind::kMesh);
    EXPECT_EQ(cfg.tool_points.count, 16);
    EXPECT_EQ(cfg.contact_mode, haptics::MultiPointMode::kInteractionMesh);
    // Every contact point lies within the tool's bounds.
    const Aabb b = load_tool_mesh(s.tool_mesh_path, s.tool_size_m).bounds().inflated(1e-12);
    for (int i = 0; i < cfg.tool_points.count; ++i) EXPECT_TRUE(b.contains(cfg.tool_points.local_m[i])) << i;

    SessionSpec bad = s;
    bad.tool.radius_m *= 2.0;  // not the mesh's
    EXPECT_THROW(validate_spec(bad, "spec"), Error);
    bad = s;
    bad.tool_size_m = 0.5;  // over a quarter of the stock
    EXPECT_THROW(validate_spec(bad, "spec"), Error);
    bad = s;
    bad.tool_mesh_path.clear();
    EXPECT_THROW(validate_spec(bad, "spec"), Error);
    bad = s;
    bad.points = 2;
    EXPECT_THROW(validate_spec(bad, "spec"), Error);
}

TEST(MeshToolSession, SceneRefusesOpenMalformedAndMissingToolMeshesNamingTheField) {
    const fs::path dir = test::temp_dir("mesh_tool_scene_bad");
    const std::string d = shared_data();
    for (const std::string& mesh : {d + "/meshes/elephant-with-holes.off", d + "/bad/malformed.obj",
                                    d + "/bad/empty.off", (dir / "missing.off").string()}) {
        const std::string path = write_mesh_tool_scene(dir, mesh);
        try {
            (void)load_run_scene(path);
            ADD_FAILURE() << "accepted " << mesh;
        } catch (const Error& e) {
            const std::string msg = e.what();
            EXPECT_EQ(msg.rfind(path + ": field 'tool.mesh': ", 0), 0u) << msg;
        }
    }
    const std::string path = (dir / "radius.json").string();
    std::ofstream(path) << R"({"tool": {"shape": "mesh", "mesh": ")" << tool_asset() << R"(", "radius_m": 0.004}})";
    EXPECT_THROW((void)load_run_scene(path), Error);
    // The scene resolves the mesh against its own folder.
    fs::copy_file(tool_asset(), dir / "tool.off");
    const RunScene ok = load_run_scene(write_mesh_tool_scene(dir, "tool.off"));
    EXPECT_EQ(ok.spec.tool.kind, ToolKind::kMesh);
    EXPECT_EQ(fs::path(ok.spec.tool_mesh_path), fs::absolute(dir / "tool.off").lexically_normal());
    EXPECT_NEAR(ok.stroke.tool_radius_m, 0.0, 1e-15);  // pressed from above: the tip is its lowest point
}

TEST(MeshToolSession, RunCarvesRecordsAndReplaysByteForByteAndAChangedToolIsRefused) {
    const fs::path dir = test::temp_dir("mesh_tool_session");
    fs::copy_file(tool_asset(), dir / "tool.off");
    RunOptions o;
    o.scene = write_mesh_tool_scene(dir, "tool.off");
    o.display = "offscreen";
    o.out = (dir / "run").string();
    o.record = (dir / "run.trdx").string();
    o.cpu = true;  // the CPU reference: bit-identical to the GPU path
    const RunResult r = run_stereo_session(o);
    EXPECT_TRUE(r.stroke_completed);
    EXPECT_LT(r.volume_after_m3, r.volume_before_m3) << "the mesh tool carved nothing";
    std::ifstream rf(dir / "run" / "report.json");
    const nlohmann::json rep = nlohmann::json::parse(rf);
    EXPECT_EQ(rep["tool"]["shape"], "mesh");
    EXPECT_GT(rep["haptics"]["contact_ticks"].get<int>(), 0) << "the 24 contact points never touched";

    OutputOptions out;
    out.out = (dir / "replay").string();
    out.width = 64;
    out.height = 48;
    run_replay(o.record, out, SculptOptions{true, false, false, false, ""});
    const std::string live = test::bytes_of(dir / "run" / "sculpted.ply");
    EXPECT_FALSE(live.empty());
    EXPECT_TRUE(live == test::bytes_of(dir / "replay" / "sculpted.ply")) << "the replay sculpted a different model";

    std::ofstream(dir / "tool.off", std::ios::app) << "\n";  // the same mesh, other bytes
    out.out = (dir / "replay2").string();
    try {
        run_replay(o.record, out, SculptOptions{true, false, false, false, ""});
        ADD_FAILURE() << "a changed tool mesh was replayed";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("tool mesh"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace tridex::app
