// The mouse stylus's keys: [ and ] resize the tool, 1 / 2 / 3 choose the op; a recorded mouse session whose keys
// changed the op and the tool size replays (`tridex replay`) to the same sculpted.ply byte for byte, and a replay
// that ignores the recorded changes does not.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "app/input/key_script.hpp"
#include "app/input/mouse_stylus.hpp"
#include "app/commands/replay/replay.hpp"
#include "app/input/run_input.hpp"
#include "app/session/run/run_actions.hpp"
#include "app/session/run/run_session.hpp"
#include "core/error.hpp"
#include "devices/recording.hpp"
#include "run_test_scene.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 192, kH = 144;
const Vec3 kEye(0.0, 0.05, 0.6);
const renderer::Screen kScreen = renderer::Screen::desktop_monitor();

// The pixel (of a kW x kH eye image) where the ray from kEye through world point p crosses the screen.
std::pair<double, double> pixel_of(const Vec3& p) {
    const Vec3 s = kEye + (p - kEye) * (kEye.z / (kEye.z - p.z));
    const double u = (s.x - kScreen.lower_left.x) / kScreen.width();
    const double v = (s.y - kScreen.lower_left.y) / kScreen.height();
    return {u * kW, (1.0 - v) * kH};
}

renderer::InputEvent key_press(renderer::Key k) {
    renderer::InputEvent e;
    e.type = renderer::InputType::kKey;
    e.key = k;
    e.action = renderer::InputAction::kPress;
    return e;
}

// Three drags (the keys pressed between them by default): along y = +10 mm with the scene's 6 mm ball (subtract), "]" twice, along y = -10 mm with the
// larger ball, "3" (paint), then along y = +10 mm again.
std::string write_scene(const fs::path& dir,
                        const std::string& keys = R"({"t_s": 1.15, "press": "]"}, {"t_s": 1.2, "press": "rightbracket"}, {"t_s": 2.2, "press": "3"})") {
    const auto px = [](double x, double y) { return pixel_of(Vec3(x, y, 0.05)); };
    const auto [a0x, a0y] = px(-0.02, 0.01);
    const auto [a1x, a1y] = px(0.02, 0.01);
    const auto [b0x, b0y] = px(-0.02, -0.01);
    const auto [b1x, b1y] = px(0.02, -0.01);
    const auto point = [](double t, double x, double y, int b) {
        return "{\"t_s\": " + std::to_string(t) + ", \"x_px\": " + std::to_string(x) + ", \"y_px\": " +
               std::to_string(y) + ", \"buttons\": " + std::to_string(b) + "}";
    };
    const std::string path = (dir / "keys_scene.json").string();
    std::ofstream f(path);
    f << R"({
  "workpiece": { "resolution": 64, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "device": { "driver": "mouse" },
  "stroke": "none",
  "display": { "preset": "desktop", "resolution": [)" << kW << ", " << kH << R"(], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] },
  "cursor": [ )" << point(0.2, a0x, a0y, 0) << ", " << point(0.5, a0x, a0y, 1) << ", " << point(1.1, a1x, a1y, 0)
      << ", " << point(1.3, b0x, b0y, 0) << ", " << point(1.5, b0x, b0y, 1) << ", " << point(2.1, b1x, b1y, 0)
      << ", " << point(2.3, a0x, a0y, 0) << ", " << point(2.5, a0x, a0y, 1) << ", " << point(3.1, a1x, a1y, 0)
      << ", " << point(3.3, a1x, a1y, 0) << R"( ],
  "keys": [ )" << keys << R"( ]
}
)";
    return path;
}

// Options of a recorded offscreen mono run of `scene` into dir/run (CPU path, no journal), recorded to dir/run.trdx.
RunOptions recorded_run(const fs::path& dir, const std::string& scene) {
    RunOptions o;
    o.scene = scene;
    o.display = "offscreen";
    o.stereo = "mono";
    o.out = (dir / "run").string();
    o.record = (dir / "run.trdx").string();
    o.no_journal = true;
    o.cpu = true;  // the CPU reference: bit-identical to the GPU path, faster to set up in a test
    return o;
}

// Replays `recording` on the CPU into dir/name with small images; returns the replay's sculpted.ply bytes.
std::string replay_to(const std::string& recording, const fs::path& dir, const std::string& name) {
    OutputOptions out;
    out.out = (dir / name).string();
    out.width = 64;
    out.height = 48;
    run_replay(recording, out, SculptOptions{true, false, false, false, ""});
    return test::bytes_of(dir / name / "sculpted.ply");
}

TEST(MouseKeys, BracketsResizeTheToolWithinLimits) {
    renderer::SceneNavigation nav;
    RunInput in(nullptr, nav, renderer::MouseNavigation{});
    MouseStylus m(0.008, Vec3(0.0));
    in.use_stylus(&m);
    bool swap = false, ao = true;
    RunActions acts(nullptr, &m, nav, nullptr, swap, ao, ToolShape{});
    const auto press = [&](const renderer::InputEvent& e) {
        in.handle(e);
        for (const std::string& a : in.take_actions()) EXPECT_TRUE(builtin_actions().run(a, acts)) << a;
    };
    press(key_press(renderer::Key::kRightBracket));
    EXPECT_DOUBLE_EQ(m.tool().radius_m, 0.008 * 1.25);
    EXPECT_DOUBLE_EQ(m.radius_m(), 0.008 * 1.25);
    EXPECT_DOUBLE_EQ(m.depth_m(), 0.008 * 1.25);  // the depth keeps its share of the radius
    press(key_press(renderer::Key::kLeftBracket));
    press(key_press(renderer::Key::kLeftBracket));
    EXPECT_DOUBLE_EQ(m.tool().radius_m, 0.008 / 1.25);
    for (int i = 0; i < 20; ++i) press(key_press(renderer::Key::kLeftBracket));
    EXPECT_EQ(m.size_steps(), -MouseStylus::kMaxSizeSteps);
    EXPECT_FALSE(m.resize(-1));
    EXPECT_NE(m.status().find("ball r "), std::string::npos) << m.status();
    EXPECT_NE(m.status().find("([ ])"), std::string::npos) << m.status();

    // A flat end scales its length with its radius; a mesh tool keeps its size.
    ToolShape flat;
    flat.kind = ToolKind::kFlatEnd;
    flat.radius_m = 0.004;
    flat.length_m = 0.02;
    MouseStylus f(flat, Vec3(0.0));
    EXPECT_TRUE(f.resize(2));
    EXPECT_DOUBLE_EQ(f.tool().radius_m, 0.004 * 1.25 * 1.25);
    EXPECT_DOUBLE_EQ(f.tool().length_m, 0.02 * 1.25 * 1.25);
    ToolShape mesh;
    mesh.kind = ToolKind::kMesh;
    mesh.radius_m = 0.01;
    MouseStylus g(mesh, Vec3(0.0));
    EXPECT_FALSE(g.resize(1));
    EXPECT_EQ(g.tool().radius_m, 0.01);
    EXPECT_NE(g.status().find("fixed size"), std::string::npos) << g.status();

    // Scene key scripts name the brackets by character or by name.
    EXPECT_EQ(parse_key_chord("[", "keys[0]").key, renderer::Key::kLeftBracket);
    EXPECT_EQ(parse_key_chord("]", "keys[0]").key, renderer::Key::kRightBracket);
    EXPECT_EQ(parse_key_chord("LeftBracket", "keys[0]").key, renderer::Key::kLeftBracket);
}

// A flat end (axis up) rests on its rim on a surface facing the eye and on its end face on a surface facing up.
TEST(MouseKeys, FlatEndRestsOnItsRimOrItsEndFace) {
    ToolShape flat;
    flat.kind = ToolKind::kFlatEnd;
    flat.radius_m = 0.004;
    flat.length_m = 0.02;
    const auto one_triangle = [](const Vec3& a, const Vec3& b, const Vec3& c) {
        auto t = std::make_shared<TriMesh>();
        t->positions = {a, b, c};
        t->triangles = {{0, 1, 2}};
        PickSurface s;
        s.whole = t;
        return s;
    };
    const PickSurface facing_eye = one_triangle(Vec3(-1.0, -1.0, 0.05), Vec3(1.0, -1.0, 0.05), Vec3(0.0, 1.0, 0.05));
    const PickSurface facing_up = one_triangle(Vec3(-1.0, 0.0, 1.0), Vec3(0.0, 0.0, -1.0), Vec3(1.0, 0.0, 1.0));
    MouseStylus m(flat, Vec3(0.0, 0.0, 0.2));
    const auto [x, y] = pixel_of(Vec3(0.01, 0.0, 0.05));
    m.set_cursor(x, y);
    EXPECT_NEAR(m.update(kScreen, kEye, kW, kH, facing_eye).hip_m.z, 0.054, 1e-9);  // the rim: a radius off
    const auto [ux, uy] = pixel_of(Vec3(0.01, 0.0, 0.0));
    m.set_cursor(ux, uy);
    const StylusTarget t = m.update(kScreen, kEye, kW, kH, facing_up);
    ASSERT_TRUE(t.on_surface);
    EXPECT_NEAR(t.hip_m.y, 0.0, 1e-9);  // the end face on the surface
    m.set_left(true);
    EXPECT_NEAR(m.update(kScreen, kEye, kW, kH, facing_up).hip_m.y, -0.004, 1e-9);  // pressed in by the depth
}

TEST(MouseKeys, RecordedKeyChangesReplayByteForByte) {
    const fs::path dir = test::temp_dir("mouse_keys_replay");
    const RunOptions o = recorded_run(dir, write_scene(dir));
    const RunResult r = run_stereo_session(o);
    EXPECT_EQ(r.notes.front(), "ended: the scripted cursor ended");
    EXPECT_GT(r.volume_before_m3 - r.volume_after_m3, 1e-7) << "the drags carved nothing";
    ASSERT_FALSE(r.mouse.is_null());
    EXPECT_EQ(r.mouse["op"], "paint");
    EXPECT_DOUBLE_EQ(r.mouse["tool"]["radius_m"].get<double>(), 0.006 * 1.25 * 1.25);
    EXPECT_GE(r.mouse["tool_changes"].get<int>(), 1);

    // The recording holds the size and op changes at the ticks that used them.
    devices::Recording rec = devices::read_recording(o.record);
    std::size_t big = 0, painted = 0;
    for (const devices::RecordedTick& t : rec.ticks) {
        if (t.tool.radius_m == 0.006 * 1.25 * 1.25) ++big;
        if (t.op == static_cast<std::uint8_t>(ToolOp::kPaint)) ++painted;
    }
    EXPECT_GT(big, 500u);
    EXPECT_GT(painted, 500u);

    const std::string live = test::bytes_of(dir / "run" / "sculpted.ply");
    EXPECT_FALSE(live.empty());
    EXPECT_TRUE(live == replay_to(o.record, dir, "replay"))
        << "the replay of the mouse session's recording sculpted a different model";

    // The same device samples without the recorded changes (as a version 1 recording has none) carve
    // something else: the check above can fail.
    for (devices::RecordedTick& t : rec.ticks) {
        t.tool = ToolShape{};
        t.op = t.tool_mode;
        if (t.tool_mode == static_cast<std::uint8_t>(ToolOp::kPaint)) t.tool_mode = t.op = 1;
    }
    const std::string stripped = (dir / "stripped.trdx").string();
    devices::write_recording(stripped, rec);
    EXPECT_FALSE(live == replay_to(stripped, dir, "stripped"))
        << "a replay without the key changes sculpted the same model";
}

// Ctrl+Z and Ctrl+Shift+Z during a mouse session replay: the recording keeps where the sculpt thread took them
// (header marks), so `tridex replay` undoes and redoes the same strokes and sculpts the same sculpted.ply byte for
// byte; the same samples without the marks keep every drag.
TEST(MouseKeys, RecordedUndoAndRedoReplayByteForByte) {
    const fs::path dir = test::temp_dir("mouse_undo_replay");
    // The second drag (along y = -10 mm) undone; the last undone and redone.
    const RunOptions o = recorded_run(
        dir, write_scene(dir, R"({"t_s": 2.2, "press": "ctrl+z"}, {"t_s": 3.2, "press": "ctrl+z"}, {"t_s": 3.25, "press": "ctrl+shift+z"})"));
    const RunResult r = run_stereo_session(o);
    EXPECT_EQ(r.sculpt.undo_requests, 2u);
    EXPECT_EQ(r.sculpt.redo_requests, 1u);
    EXPECT_GT(r.volume_before_m3 - r.volume_after_m3, 1e-7) << "nothing is left carved";
    // Three drags, three strokes: the cursor and the keys share the device's clock, so no key falls inside a drag
    // (on the loop's clock, which runs ahead when the loop skips deadlines, the third drag could start before the
    // first Ctrl+Z and be cut in two by it).
    EXPECT_EQ(test::read_json(dir / "run" / "report.json")["history"]["strokes"], 3);

    devices::Recording rec = devices::read_recording(o.record);
    ASSERT_TRUE(rec.header.marks.has_value());
    std::size_t undos = 0, redos = 0;
    for (const devices::RecordedMark& m : *rec.header.marks) {
        undos += m.kind == "undo";
        redos += m.kind == "redo";
    }
    EXPECT_EQ(undos, 2u);
    EXPECT_EQ(redos, 1u);

    const std::string live = test::bytes_of(dir / "run" / "sculpted.ply");
    EXPECT_FALSE(live.empty());
    EXPECT_TRUE(live == replay_to(o.record, dir, "replay"))
        << "the replay of a session with Ctrl+Z and Ctrl+Shift+Z sculpted a different model";
    const nlohmann::json report = test::read_json(dir / "replay" / "report.json");
    ASSERT_TRUE(report.contains("history")) << report.dump();
    EXPECT_EQ(report["history"]["undos"], 2);
    EXPECT_EQ(report["history"]["redos"], 1);

    // Without the marks (as a file from before they were kept) the second drag stays carved.
    rec.header.marks.reset();
    const std::string stripped = (dir / "stripped.trdx").string();
    devices::write_recording(stripped, rec);
    EXPECT_FALSE(live == replay_to(stripped, dir, "stripped")) << "a replay without the marks sculpted the same model";
    const double kept = test::read_json(dir / "replay" / "report.json")["volume_removed_m3"].get<double>();
    const double all = test::read_json(dir / "stripped" / "report.json")["volume_removed_m3"].get<double>();
    EXPECT_GT(all - kept, 0.3 * kept) << "the undone drag's groove is missing from the replay without marks";
}

// Undo in one order with a placement: the bunny is moved with Place (key 8) and carved on where it was put (1);
// Ctrl+Z takes back the groove, a second Ctrl+Z the move (the newest step left), Ctrl+Shift+Z moves it again. The
// recording keeps both pose sets, so the replay puts the bunny where the session left it and sculpts the same model.
TEST(MouseKeys, APlacementIsUndoneInOrderWithTheStrokesAndReplays) {
    const fs::path dir = test::temp_dir("mouse_place_undo");
    const auto point = [](double t, const Vec3& p, int b) {
        const auto [x, y] = pixel_of(p);
        return "{\"t_s\": " + std::to_string(t) + ", \"x_px\": " + std::to_string(x) + ", \"y_px\": " +
               std::to_string(y) + ", \"buttons\": " + std::to_string(b) + "}";
    };
    const Vec3 c(0.0, 0.0, 0.05), moved = c + Vec3(0.03, 0.0, 0.0);
    const std::string scene = (dir / "place_scene.json").string();
    std::ofstream(scene) << R"({
  "workpiece": { "resolution": 64, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "device": { "driver": "mouse" },
  "stroke": "none",
  "display": { "preset": "desktop", "resolution": [)" << kW << ", " << kH << R"(], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] },
  "cursor": [ )" << point(0.2, c, 0) << ", " << point(0.5, c, 1) << ", " << point(1.1, moved, 1) << ", "
                         << point(1.2, moved, 0) << ", " << point(1.5, moved + Vec3(-0.01, 0.01, 0.0), 0) << ", "
                         << point(1.7, moved + Vec3(-0.01, 0.01, 0.0), 1) << ", "
                         << point(2.2, moved + Vec3(0.01, 0.01, 0.0), 1) << ", "
                         << point(2.3, moved + Vec3(0.01, 0.01, 0.0), 0) << ", " << point(3.3, moved, 0) << R"( ],
  "keys": [ {"t_s": 0.3, "press": "8"}, {"t_s": 1.3, "press": "1"}, {"t_s": 2.6, "press": "ctrl+z"},
            {"t_s": 2.8, "press": "ctrl+z"}, {"t_s": 3.0, "press": "ctrl+shift+z"} ]
}
)";
    const RunOptions o = recorded_run(dir, scene);
    const RunResult r = run_stereo_session(o);
    EXPECT_EQ(r.sculpt.history.strokes, 1u);  // the groove was carved ...
    EXPECT_EQ(r.sculpt.history.undos, 1u);    // ... and taken back
    EXPECT_EQ(r.sculpt.history.redos, 0u);    // the redo went to the placement, not to the groove
    EXPECT_EQ(r.volume_after_m3, r.volume_before_m3);
    const devices::Recording rec = devices::read_recording(o.record);
    ASSERT_EQ(rec.header.poses.size(), 2u);  // back to the start, then moved again
    EXPECT_EQ(rec.header.poses[0].pose.position, Vec3(0.0));
    EXPECT_GT(rec.header.poses[1].pose.position.x, 0.02);
    EXPECT_LT(rec.header.poses[0].tick, rec.header.poses[1].tick);
    const nlohmann::json live = test::read_json(dir / "run" / "report.json");
    ASSERT_TRUE(live["workpiece"].contains("pose_end")) << live["workpiece"].dump();
    EXPECT_EQ(live["workpiece"]["pose_end"]["position_m"][0].get<double>(), rec.header.poses[1].pose.position.x);

    const std::string live_ply = test::bytes_of(dir / "run" / "sculpted.ply");
    EXPECT_TRUE(live_ply == replay_to(o.record, dir, "replay")) << "the replay sculpted a different model";
    EXPECT_EQ(test::read_json(dir / "replay" / "report.json")["workpiece"]["pose_end"], live["workpiece"]["pose_end"]);

    // Without the last pose set (the redo's) the replay leaves the bunny where the undo put it back: the check above
    // can fail.
    devices::Recording stripped = rec;
    stripped.header.poses.pop_back();
    const std::string path = (dir / "stripped.trdx").string();
    devices::write_recording(path, stripped);
    replay_to(path, dir, "stripped");
    const nlohmann::json s = test::read_json(dir / "stripped" / "report.json");
    EXPECT_NE(s["workpiece"]["pose_end"], live["workpiece"]["pose_end"]) << s["workpiece"].dump();
}

}  // namespace
}  // namespace tridex::app
