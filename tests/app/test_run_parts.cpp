// `tridex run` parts without a GPU: the scene file (defaults, bad fields named), options, the scene view from a
// LoopView, the navigated camera (analytic: same projection as moving the scene), and keyboard/mouse controls.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include <CLI/CLI.hpp>

#include "app/actions/action_registry.hpp"
#include "app/commands/run/run_cli.hpp"
#include "app/input/run_input.hpp"
#include "app/scene/run_scene.hpp"
#include "app/session/run/run_actions.hpp"
#include "app/session/run/run_options.hpp"
#include "app/session/run/run_sculpt.hpp"
#include "app/session/run/run_session.hpp"
#include "app/session/view/run_view.hpp"
#include "app/session/batch/session.hpp"
#include "core/error.hpp"
#include "renderer/camera/off_axis.hpp"
#include "error_of.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using test::error_of;

TEST(RunScene, DefaultSceneLoadsWithDocumentedValues) {
    const RunScene s = load_run_scene("");
    EXPECT_NE(s.source.find("default_scene.json"), std::string::npos);
    EXPECT_NE(s.spec.mesh_path.find("bunny.off"), std::string::npos);
    EXPECT_TRUE(fs::is_regular_file(s.spec.mesh_path));
    EXPECT_EQ(s.spec.resolution, 128);
    EXPECT_DOUBLE_EQ(s.spec.stock_m, 0.12);
    EXPECT_DOUBLE_EQ(s.spec.tool.radius_m, 0.006);
    EXPECT_TRUE(s.has_stroke);
    EXPECT_DOUBLE_EQ(s.stroke.duration_s, 3.0);
    EXPECT_DOUBLE_EQ(s.stroke.tool_radius_m, s.spec.tool.radius_m);
    EXPECT_EQ(s.display.stereo, renderer::StereoOutput::kMono);  // at the desk: mono; anaglyph by choice (--stereo)
    EXPECT_FALSE(s.display.resolution_given);  // a desk window is sized to its monitor
    EXPECT_EQ(s.display.width_px, 1920);       // offscreen: the desk preset's size
    EXPECT_EQ(s.head, HeadMode::kFixed);
    EXPECT_DOUBLE_EQ(s.head_pose.position.z, 0.6);
}

TEST(RunScene, ReadsEveryField) {
    const json j = json::parse(R"({
      "workpiece": {"resolution": 64, "stock_m": 0.2, "centre_m": [0.1, 0.2, 0.3]},
      "tool": {"radius_m": 0.01, "stiffness_n_per_m": 500, "damping_n_s_per_m": 0.2},
      "workspace": {"mode": "bubble", "scale": 2.0},
      "clay_group_sweeps": 24,
      "stroke": "none",
      "display": "powerwall",
      "head": {"provider": "scripted", "loop": true,
               "waypoints": [{"t_s": 0, "position_m": [0, 0, 2]},
                             {"t_s": 1, "position_m": [0.5, 0, 2], "orientation_wxyz": [0, 0, 1, 0]}]}})");
    const RunScene s = run_scene_from_json(j, "x.json", ".");
    EXPECT_EQ(s.spec.resolution, 64);
    EXPECT_DOUBLE_EQ(s.spec.workpiece_centre_m.z, 0.3);
    EXPECT_DOUBLE_EQ(s.spec.tool.radius_m, 0.01);
    EXPECT_EQ(s.spec.workspace_mode, "bubble");
    EXPECT_DOUBLE_EQ(s.spec.workspace_scale, 2.0);
    EXPECT_EQ(s.spec.clay_group_sweeps, 24u);
    EXPECT_FALSE(s.has_stroke);
    EXPECT_EQ(s.display.stereo, renderer::StereoOutput::kFrameSequential);
    EXPECT_DOUBLE_EQ(s.display.refresh_hz, 120.0);
    EXPECT_EQ(s.head, HeadMode::kScripted);
    ASSERT_EQ(s.head_waypoints.size(), 2u);
    EXPECT_DOUBLE_EQ(s.head_waypoints[1].pose.position.x, 0.5);
    EXPECT_DOUBLE_EQ(s.head_waypoints[1].pose.orientation.y, 1.0);
    EXPECT_TRUE(s.head_loop);
    // Without a head position the display's default head is used.
    EXPECT_DOUBLE_EQ(s.head_pose.position.z, renderer::DisplayConfig::powerwall().default_head_m.z);
}

TEST(RunScene, BadFieldsAreRefusedNamingFileAndField) {
    struct Case {
        const char* json;
        const char* field;
    };
    const Case cases[] = {
        {R"({"workpiece": {"resolution": 3}})", "'workpiece.resolution'"},
        {R"({"workpiece": {"resolution": 64.5}})", "'workpiece.resolution'"},
        {R"({"workpiece": {"stock_m": -1}})", "'workpiece.stock_m'"},
        {R"({"workpiece": {"mesh": "no_such_mesh.off"}})", "'workpiece.mesh'"},
        {R"({"workpiece": {"centre_m": [0, 0]}})", "'workpiece.centre_m'"},
        {R"({"tool": {"radius_m": 0.1}})", "'tool.radius_m'"},
        {R"({"tool": {"colour": 1}})", "'tool.colour'"},
        {R"({"workspace": {"mode": "teleport"}})", "'workspace.mode'"},
        {R"({"workspace": {"scale": "huge"}})", "'workspace.scale'"},
        {R"({"stroke": "sometimes"})", "'stroke'"},
        {R"({"stroke": {"press_axis": "x"}})", "'stroke.press_axis'"},
        {R"({"stroke": {"duration_s": 0}})", "'stroke.duration_s'"},
        {R"({"stroke": {"start_s": -1}})", "'stroke.start_s'"},
        {R"({"display": "cinema"})", "'display'"},
        {R"({"display": {"stereo": "holographic"}})", "'display'"},
        {R"({"head": {"provider": "psychic"}})", "'head.provider'"},
        {R"({"head": {"position_m": [0, 0.05, -0.2]}})", "'head.position_m': must be in front of the display's screen"},
        {R"({"head": {"provider": "scripted"}})", "'head.waypoints'"},
        {R"({"head": {"waypoints": [{"t_s": 1, "position_m": [0,0,1]}, {"t_s": 1, "position_m": [0,0,1]}]}})",
         "'head.waypoints[1].t_s'"},
        {R"({"head": {"waypoints": [{"t_s": 0, "position_m": [0,0,1], "orientation_wxyz": [2,0,0,0]}]}})",
         "'head.waypoints[0].orientation_wxyz'"},
        {R"({"lights": 3})", "'lights'"},
        {R"({"clay_group_sweeps": 0})", "'clay_group_sweeps'"},
        {R"({"clay_group_sweeps": 257})", "'clay_group_sweeps'"},
    };
    for (const Case& c : cases) {
        const std::string m = error_of([&] { (void)run_scene_from_json(json::parse(c.json), "scene.json", "."); });
        EXPECT_NE(m.find("scene.json"), std::string::npos) << c.json << " -> " << m;
        EXPECT_NE(m.find(c.field), std::string::npos) << c.json << " -> " << m;
    }
}

// A "fit" workspace: the device -> world gain is 1 while the reach fits 90 % of the workspace, else the ratio of
// the reach to 90 % of the workspace on the tightest axis.
// The workspace gain's range, [kWorkspaceScaleMin, kWorkspaceScaleMax], both ends in: a scene's and a recording's.
TEST(RunScene, AWorkspaceScaleOutOfRangeIsRefusedWithItsRange) {
    for (const char* bad : {"0", "1e-320", "0.00999", "100.5", "-1"}) {
        const std::string m = error_of([&] {
            (void)run_scene_from_json(json::parse(std::string(R"({"workspace": {"scale": )") + bad + "}}"), "scene.json", ".");
        });
        EXPECT_EQ(m.rfind("scene.json: field 'workspace.scale': must be in [0.01, 100], got ", 0), 0u) << bad << " -> " << m;
    }
    for (const double good : {kWorkspaceScaleMin, 1.0, kWorkspaceScaleMax}) {
        const json j = {{"workspace", {{"scale", good}}}};
        EXPECT_EQ(run_scene_from_json(j, "scene.json", ".").spec.workspace_scale, good);
    }
    SessionSpec s;
    s.workspace_scale = 1e-320;
    EXPECT_NE(error_of([&] { validate_spec(s, "rec.trdx"); }).find("'workspace_scale': must be in [0.01, 100], got"),
              std::string::npos);
}

TEST(RunScene, FitWorkspaceScale) {
    const RunScene s = run_scene_from_json(json::parse(R"({"workspace": {"scale": "fit"}})"), "scene.json", ".");
    EXPECT_TRUE(s.workspace_fit);
    devices::DeviceProfile p;
    p.name = "test";
    p.workspace_m = Aabb{Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05)};  // 100 mm: 90 mm usable
    EXPECT_EQ(fit_workspace_scale(Aabb{Vec3(0.0), Vec3(0.09, 0.01, 0.01)}, p), 1.0);
    EXPECT_NEAR(fit_workspace_scale(Aabb{Vec3(0.0), Vec3(0.09, 0.36, 0.18)}, p), 4.0, 1e-12);
    EXPECT_EQ(fit_workspace_scale(Aabb{}, p), 1.0);
    p.workspace_m = Aabb{};
    EXPECT_THROW(fit_workspace_scale(Aabb{Vec3(0.0), Vec3(0.1)}, p), Error);
}

TEST(RunScene, UnreadableAndInvalidFilesAreNamed) {
    const fs::path dir = fs::temp_directory_path() / ("tridex_run_parts_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string bad = (dir / "bad.json").string();
    std::ofstream(bad) << "{ \"workpiece\": ";
    EXPECT_NE(error_of([&] { (void)load_run_scene(bad); }).find(bad + ": not valid JSON"), std::string::npos);
    // A missing comma is placed by line and column, with what was expected there.
    const std::string comma = (dir / "comma.json").string();
    std::ofstream(comma) << "{\n  \"workpiece\": { \"resolution\": 32 }\n  \"tool\": { \"radius_m\": 0.006 }\n}\n";
    const std::string said = error_of([&] { (void)load_run_scene(comma); });
    EXPECT_NE(said.find(comma + ": not valid JSON: parse error at line 3, column"), std::string::npos) << said;
    EXPECT_NE(said.find("expected '}'"), std::string::npos) << said;
    // A number beyond a double's range is a bad file, named with its line, column, field and number.
    const std::string huge = (dir / "huge.json").string();
    std::ofstream(huge) << "{ \"workpiece\": { \"resolution\": 64,\n                \"stock_m\": 1e400 } }";
    EXPECT_EQ(error_of([&] { (void)load_run_scene(huge); }),
              huge + ": not valid JSON: number overflow at line 2, column 28, field 'workpiece.stock_m': '1e400' is "
                     "beyond a double's range (magnitudes up to about 1.8e308)");
    const std::string hz = (dir / "hz.json").string();
    std::ofstream(hz) << "{ \"display\": { \"refresh_hz\": 1e400 } }";
    EXPECT_NE(error_of([&] { (void)load_run_scene(hz); }).find(hz + ": not valid JSON: number overflow at line 1, column "
                                                                  "30, field 'display.refresh_hz': '1e400'"),
              std::string::npos)
        << error_of([&] { (void)load_run_scene(hz); });
    // A workspace gain too small to move the tool is refused naming the field and its range, not the hand's path.
    const std::string gain = (dir / "gain.json").string();
    std::ofstream(gain) << "{ \"workspace\": { \"scale\": 1e-320 } }";
    EXPECT_EQ(error_of([&] { (void)load_run_scene(gain); }).rfind(gain + ": field 'workspace.scale': must be in [0.01, 100], got ", 0),
              0u)
        << error_of([&] { (void)load_run_scene(gain); });
    // A stock too small for any tool is refused naming its own field, not a tool's.
    const std::string tiny = (dir / "tiny.json").string();
    std::ofstream(tiny) << "{ \"workpiece\": { \"stock_m\": 1e-320 } }";
    EXPECT_NE(error_of([&] { (void)load_run_scene(tiny); }).find("workpiece.stock_m"), std::string::npos)
        << error_of([&] { (void)load_run_scene(tiny); });
    const std::string missing = (dir / "missing.json").string();
    EXPECT_NE(error_of([&] { (void)load_run_scene(missing); }).find(missing), std::string::npos);
    fs::remove_all(dir);
}

TEST(RunOptions, BadOptionsAreRefusedNamingTheOption) {
    RunOptions o;
    o.display = "hologram";
    EXPECT_NE(error_of([&] { (void)resolve_run(o); }).find("--display"), std::string::npos);
    o = RunOptions{};
    o.stereo = "wiggle";
    EXPECT_NE(error_of([&] { (void)resolve_run(o); }).find("--stereo: unknown stereo output 'wiggle'"), std::string::npos);
    o = RunOptions{};
    o.frames = -1;
    EXPECT_NE(error_of([&] { (void)resolve_run(o); }).find("--frames"), std::string::npos);
    o = RunOptions{};
    o.seconds = std::nan("");
    EXPECT_NE(error_of([&] { (void)resolve_run(o); }).find("--seconds"), std::string::npos);
    o = RunOptions{};
    o.head = "scripted";  // the default scene has no waypoints
    EXPECT_NE(error_of([&] { (void)resolve_run(o); }).find("--head scripted"), std::string::npos);
    o = RunOptions{};
    o.head = "psychic";
    EXPECT_NE(error_of([&] { (void)resolve_run(o); }).find("--head"), std::string::npos);
    // --history-mib: the demo's range, 0 included in what is refused.
    for (const double mib : {0.0, 0.5, -1.0, 2e6}) {
        o = RunOptions{};
        o.history_mib = mib;
        EXPECT_NE(error_of([&] { (void)resolve_run(o); }).find("--history-mib: must be between 1 and 1048576"),
                  std::string::npos)
            << mib;
    }

    o = RunOptions{};
    o.display = "offscreen";
    o.stereo = "top-bottom-half";
    o.swap_eyes = true;
    o.monitor = "2";
    const RunSetup s = resolve_run(o);
    EXPECT_EQ(s.display, DisplayKind::kOffscreen);
    EXPECT_EQ(s.scene.display.stereo, renderer::StereoOutput::kTopBottomHalf);
    EXPECT_TRUE(s.swap_eyes);
    EXPECT_EQ(s.monitor_index, 2);
    o.monitor = "HDMI";
    EXPECT_EQ(resolve_run(o).monitor_name, "HDMI");
    EXPECT_TRUE(s.lod);   // on unless --lod off (built on a worker: start-up does not wait)
    EXPECT_TRUE(s.ao);    // the display config's ambient_occlusion (on)
    o.ao = "off";
    EXPECT_FALSE(resolve_run(o).ao);
    o.ao = "maybe";
    EXPECT_NE(error_of([&] { (void)resolve_run(o); }).find("--ao"), std::string::npos);
    o.ao = "on";
    EXPECT_DOUBLE_EQ(s.frame_target_ms, 25.0);  // the occlusion's budget at the desk's target
    o.frame_target_ms = 0.0;
    EXPECT_DOUBLE_EQ(resolve_run(o).frame_target_ms, 0.0);
    o.frame_target_ms = -5.0;
    EXPECT_NE(error_of([&] { (void)resolve_run(o); }).find("--frame-target-ms"), std::string::npos);
}

TEST(ImageSize, ParsesWidthByHeightAndRefusesTheRest) {
    EXPECT_EQ(parse_image_size("1280x720", "--render-size"), (std::pair<int, int>{1280, 720}));
    for (const char* bad : {"1280", "1280x", "x720", "1280*720", "1280x720p", "8x8", "99999x720", ""})
        EXPECT_NE(error_of([&] { (void)parse_image_size(bad, "--render-size"); }).find("--render-size"),
                  std::string::npos)
            << bad;
}

TEST(RunView, EnclosingBoxOfATurnedBox) {
    // A 2 x 1 x 1 m box (half extents 1, 0.5, 0.5) turned 90 degrees about z at (1, 2, 3): x and y swap.
    const Pose p{Vec3(1.0, 2.0, 3.0), glm::angleAxis(std::acos(-1.0) / 2.0, Vec3(0.0, 0.0, 1.0))};
    const Aabb b = enclosing_box(p, Vec3(1.0, 0.5, 0.5));
    EXPECT_NEAR(b.lo.x, 0.5, 1e-12);
    EXPECT_NEAR(b.hi.x, 1.5, 1e-12);
    EXPECT_NEAR(b.lo.y, 1.0, 1e-12);
    EXPECT_NEAR(b.hi.y, 3.0, 1e-12);
    EXPECT_NEAR(b.lo.z, 2.5, 1e-12);
    EXPECT_NEAR(b.hi.z, 3.5, 1e-12);
}

TEST(RunView, SceneViewFollowsTheLoopView) {
    const TriMesh mesh;
    const Aabb fallback{Vec3(-1.0), Vec3(1.0)};
    haptics::LoopView v;  // tick 0: nothing published yet
    renderer::SceneView s = scene_view_from(v, &mesh, 0.01, Vec3(0.1, 0.2, 0.3), fallback);
    EXPECT_EQ(s.workpiece, &mesh);
    EXPECT_EQ(s.tool_centre_m, Vec3(0.1, 0.2, 0.3));
    EXPECT_EQ(s.workspace_m.lo, fallback.lo);
    EXPECT_DOUBLE_EQ(s.tool_radius_m, 0.01);
    v.tick = 5;
    v.tool_world.position = Vec3(0.0, 0.0, 0.5);
    v.box.position = Vec3(0.0, 0.0, 0.4);
    v.box_half_extents_m = Vec3(0.1, 0.05, 0.02);
    v.bubble_centre_m = Vec3(0.0, 0.0, 0.4);
    v.bubble_radius_m = 0.03;
    s = scene_view_from(v, &mesh, 0.01, Vec3(0.1, 0.2, 0.3), fallback);
    EXPECT_EQ(s.tool_centre_m, Vec3(0.0, 0.0, 0.5));
    EXPECT_NEAR(s.workspace_m.lo.x, -0.1, 1e-15);
    EXPECT_NEAR(s.workspace_m.hi.z, 0.42, 1e-15);
    EXPECT_DOUBLE_EQ(s.bubble_radius_m, 0.03);
}

TEST(RunView, RunItemsShowProxyForceAndOverlay) {
    haptics::LoopView v;  // tick 0: no proxy, no force yet; the overlay shows what it is given
    renderer::SceneView s;
    add_run_items(s, v, 0.006, 0.02, RunOverlay{-1.0, 12.0, 16.5});
    EXPECT_DOUBLE_EQ(s.proxy_radius_m, 0.0);
    EXPECT_EQ(s.force_N, Vec3(0.0));
    EXPECT_TRUE(s.show_overlay);
    EXPECT_DOUBLE_EQ(s.haptic_rate_hz, -1.0);
    EXPECT_DOUBLE_EQ(s.sculpt_rate_hz, 12.0);
    EXPECT_DOUBLE_EQ(s.frame_time_ms, 16.5);
    EXPECT_FALSE(s.overlay_tile_counts) << "a person's overlay: no tile counts unless --overlay-stats";
    add_run_items(s, v, 0.006, 0.02, RunOverlay{-1.0, 12.0, 16.5, "", true});
    EXPECT_TRUE(s.overlay_tile_counts);
    v.tick = 3;
    v.proxy_m = Vec3(0.01, 0.02, 0.03);
    v.force_n = Vec3(0.0, 1.5, 0.0);
    add_run_items(s, v, 0.006, 0.02, RunOverlay{1000.0, 12.0, 16.5});
    EXPECT_EQ(s.proxy_m, Vec3(0.01, 0.02, 0.03));
    EXPECT_DOUBLE_EQ(s.proxy_radius_m, 0.006);
    EXPECT_EQ(s.force_N, Vec3(0.0, 1.5, 0.0));
    EXPECT_DOUBLE_EQ(s.force_m_per_newton, 0.02);
    EXPECT_DOUBLE_EQ(s.haptic_rate_hz, 1000.0);
}

TEST(RunView, RateMeterCountsOverTheLastSecond) {
    RateMeter m(1.0);
    EXPECT_DOUBLE_EQ(m.rate_hz(), -1.0);
    m.add(0.0, 0);
    EXPECT_DOUBLE_EQ(m.rate_hz(), -1.0);
    for (int i = 1; i <= 20; ++i) m.add(0.1 * i, 100u * static_cast<std::uint64_t>(i));  // 1000 per s for 2 s
    EXPECT_NEAR(m.rate_hz(), 1000.0, 1e-9);
    for (int i = 21; i <= 40; ++i) m.add(0.1 * i, 2000u + 10u * static_cast<std::uint64_t>(i - 20));  // 100 per s
    EXPECT_NEAR(m.rate_hz(), 100.0, 1e-9);  // only the last second counts
    m.add(4.0, 5000);  // same time: replaces the newest count
    EXPECT_GT(m.rate_hz(), 100.0);
    m.add(1.0, 10);    // time went back: a restart clears the history
    EXPECT_DOUBLE_EQ(m.rate_hz(), -1.0);
}

// Clip-space position of p through an eye's off-axis camera, divided by w: (x, y, depth).
Vec3 ndc(const renderer::EyeView& e, const Vec3& p) {
    const glm::dvec4 c = e.projection * e.view * glm::dvec4(p, 1.0);
    return Vec3(c) / c.w;
}

TEST(RunView, NavigatedCameraEqualsMovingTheScene) {
    const renderer::Screen screen = renderer::Screen::desktop_monitor();
    const Pose head{Vec3(0.05, 0.1, 0.6), glm::angleAxis(0.1, glm::normalize(Vec3(0.2, 1.0, 0.1)))};
    renderer::SceneNavigation nav;
    nav.translate(Vec3(0.02, -0.01, 0.05));
    nav.rotate(Vec3(0.3, 1.0, 0.2), 0.4, Vec3(0.0, 0.0, 0.1));
    nav.scale(1.7, Vec3(0.01, 0.02, 0.0));
    const double sep = 0.065, near_m = 0.05, far_m = 20.0;
    const RunCamera cam = navigated_camera(screen, head, sep, nav, near_m, far_m);
    EXPECT_NEAR(cam.eye_separation_m, sep / 1.7, 1e-15);
    const auto eyes_world = renderer::eye_positions(head, sep);
    const auto eyes_scene = renderer::eye_positions(cam.head, cam.eye_separation_m);
    for (int e = 0; e < 2; ++e) {
        const renderer::EyeView world_eye = renderer::off_axis_view(screen, eyes_world[e], near_m, far_m);
        const renderer::EyeView scene_eye = renderer::off_axis_view(cam.screen, eyes_scene[e], cam.near_m, cam.far_m);
        for (const Vec3& p : {Vec3(0.0), Vec3(0.03, -0.02, 0.04), Vec3(-0.1, 0.05, -0.2)}) {
            const Vec3 a = ndc(world_eye, nav.to_world(p));  // the scene moved, real camera
            const Vec3 b = ndc(scene_eye, p);                // the scene in place, navigated camera
            EXPECT_NEAR(a.x, b.x, 1e-9) << "eye " << e;
            EXPECT_NEAR(a.y, b.y, 1e-9) << "eye " << e;
            EXPECT_NEAR(a.z, b.z, 1e-9) << "eye " << e;
        }
    }
    // Without navigation the camera is the real one.
    const RunCamera id = navigated_camera(screen, head, sep, renderer::SceneNavigation{});
    EXPECT_NEAR(glm::length(id.screen.lower_right - screen.lower_right), 0.0, 1e-15);
    EXPECT_NEAR(glm::length(id.head.position - head.position), 0.0, 1e-15);
    EXPECT_DOUBLE_EQ(id.eye_separation_m, sep);
}

renderer::InputEvent key(renderer::Key k, renderer::InputAction a) {
    renderer::InputEvent e;
    e.type = renderer::InputType::kKey;
    e.key = k;
    e.action = a;
    return e;
}

TEST(RunInput, KeysMoveTheHeadMouseMovesTheScene) {
    renderer::KeyboardMouseHead head(Pose{Vec3(0.0, 0.0, 0.6), Quat(1.0, 0.0, 0.0, 0.0)}, 0.3);
    renderer::SceneNavigation nav;
    renderer::MouseNavigation mouse;
    mouse.metres_per_pixel = 0.001;
    RunInput in(&head, nav, mouse);
    (void)head.head_at(0.0);
    in.handle(key(renderer::Key::kW, renderer::InputAction::kPress));
    EXPECT_NEAR(head.head_at(1.0).position.z, 0.3, 1e-12);  // 0.3 m/s forward (-z) for 1 s
    in.handle(key(renderer::Key::kW, renderer::InputAction::kRelease));
    in.handle(key(renderer::Key::kR, renderer::InputAction::kPress));
    EXPECT_NEAR(head.head_at(1.5).position.y, 0.15, 1e-12);  // up for 0.5 s
    in.handle(key(renderer::Key::kR, renderer::InputAction::kRelease));

    // Shift + left drag pans by 0.001 m per pixel: 100 px right, 50 px down -> (+0.1, -0.05, 0).
    renderer::InputEvent b;
    b.type = renderer::InputType::kMouseButton;
    b.button = renderer::MouseButton::kLeft;
    b.action = renderer::InputAction::kPress;
    b.modifiers = renderer::modifier::kShift;
    in.handle(b);
    renderer::InputEvent m;
    m.type = renderer::InputType::kMouseMove;
    m.dx_px = 100.0;
    m.dy_px = 50.0;
    in.handle(m);
    EXPECT_NEAR(nav.to_world(Vec3(0.0)).x, 0.1, 1e-12);
    EXPECT_NEAR(nav.to_world(Vec3(0.0)).y, -0.05, 1e-12);
    b.action = renderer::InputAction::kRelease;
    in.handle(b);
    in.handle(m);  // no button: nothing moves
    EXPECT_NEAR(nav.to_world(Vec3(0.0)).x, 0.1, 1e-12);

    renderer::InputEvent s;
    s.type = renderer::InputType::kScroll;
    s.dy_px = 2.0;
    in.handle(s);
    EXPECT_NEAR(nav.scale(), 1.1 * 1.1, 1e-12);

    // Tab, O, Home and Esc name actions, in the order pressed; auto-repeat and releases of these do not.
    in.handle(key(renderer::Key::kTab, renderer::InputAction::kPress));
    in.handle(key(renderer::Key::kTab, renderer::InputAction::kPress));
    in.handle(key(renderer::Key::kO, renderer::InputAction::kPress));
    in.handle(key(renderer::Key::kO, renderer::InputAction::kRepeat));
    in.handle(key(renderer::Key::kO, renderer::InputAction::kRelease));
    in.handle(key(renderer::Key::kHome, renderer::InputAction::kPress));
    in.handle(key(renderer::Key::kEscape, renderer::InputAction::kPress));
    EXPECT_EQ(in.take_actions(), (std::vector<std::string>{"view.swap_eyes", "view.swap_eyes", "view.occlusion",
                                                           "view.reset", "session.end"}));
    EXPECT_TRUE(in.take_actions().empty());
    // The session runs them on its ActionTarget: view.reset puts the scene and the keyboard head back.
    bool swap = false, ao = true;
    RunActions acts(nullptr, nullptr, nav, &head, swap, ao, ToolShape{});
    for (const char* a : {"view.swap_eyes", "view.occlusion", "view.reset", "session.end"})
        EXPECT_TRUE(builtin_actions().run(a, acts)) << a;
    EXPECT_TRUE(swap);
    EXPECT_FALSE(ao);
    EXPECT_TRUE(acts.end_requested());
    EXPECT_DOUBLE_EQ(nav.scale(), 1.0);
    EXPECT_NEAR(head.head_at(2.0).position.z, 0.6, 1e-12);
    // The middle button is the menu button: held, not a pan.
    renderer::InputEvent mid;
    mid.type = renderer::InputType::kMouseButton;
    mid.button = renderer::MouseButton::kMiddle;
    in.handle(mid);
    EXPECT_TRUE(in.menu_held());
    const Vec3 before = nav.to_world(Vec3(0.0));
    in.handle(m);
    EXPECT_EQ(nav.to_world(Vec3(0.0)), before);
    mid.action = renderer::InputAction::kRelease;
    in.handle(mid);
    EXPECT_FALSE(in.menu_held());
}

TEST(RunCli, EveryFlagReachesTheOptions) {
    CLI::App cli{"tridex"};
    RunOptions o;
    CLI::App* cmd = cli.add_subcommand("run");
    add_run_options(*cmd, o);
    const char* argv[] = {"tridex", "run", "wall.json", "--display", "fullscreen", "--stereo", "frame-sequential",
                          "--monitor", "DP-1", "--frames", "7", "--out", "o", "--display-config", "d.json",
                          "--head", "tracker", "--swap-eyes", "--seconds", "2.5", "--validate", "--no-pace",
                          "--no-items", "--no-tiles", "--no-cull", "--bindings", "b.json"};
    cli.parse(static_cast<int>(std::size(argv)), argv);
    EXPECT_TRUE(*cmd);
    EXPECT_EQ(o.scene, "wall.json");
    EXPECT_EQ(o.display, "fullscreen");
    EXPECT_EQ(o.stereo, "frame-sequential");
    EXPECT_EQ(o.monitor, "DP-1");
    EXPECT_EQ(o.frames, 7);
    EXPECT_EQ(o.out, "o");
    EXPECT_EQ(o.display_config, "d.json");
    EXPECT_EQ(o.head, "tracker");
    EXPECT_TRUE(o.swap_eyes);
    EXPECT_DOUBLE_EQ(o.seconds, 2.5);
    EXPECT_TRUE(o.validate);
    EXPECT_FALSE(o.pace);
    EXPECT_FALSE(o.items);
    EXPECT_FALSE(o.tiles);
    EXPECT_FALSE(o.cull);
    EXPECT_EQ(o.bindings, "b.json");
    // A user error comes back as exit code 2 (message on stderr), not as an exception.
    RunOptions bad;
    bad.display = "hologram";
    EXPECT_EQ(run_command(bad), 2);
}

}  // namespace
}  // namespace tridex::app

namespace tridex::app {
namespace {

// With no --device and a scene without a device block, a window session's hand is the mouse and an offscreen one's
// the scripted hand; --device and the scene's block choose otherwise.
TEST(RunOptions, AWindowWithNoDeviceNamedUsesTheMouse) {
    const fs::path dir = fs::temp_directory_path() / ("tridex_run_default_device_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string bare = (dir / "bare.json").string();
    std::ofstream(bare) << "{ \"workpiece\": { \"resolution\": 32 } }";
    const std::string named = (dir / "named.json").string();
    std::ofstream(named) << "{ \"workpiece\": { \"resolution\": 32 }, \"device\": { \"driver\": \"simulated\" } }";
    auto driver = [&](const std::string& scene, const std::string& display, const std::string& device) {
        RunOptions o;
        o.scene = scene;
        o.display = display;
        o.device = device;
        o.frames = 1;
        o.out = (dir / "out").string();
        return resolve_run(o).scene.spec.device_driver;
    };
    EXPECT_EQ(driver(bare, "window", ""), "mouse");
    EXPECT_EQ(driver(bare, "fullscreen", ""), "mouse");
    EXPECT_EQ(driver(bare, "offscreen", ""), "simulated");
    EXPECT_EQ(driver(bare, "window", "simulated"), "simulated");
    EXPECT_EQ(driver(named, "window", ""), "simulated");
    // --mesh carves the user's own mesh in the scene's place, as the demo's --mesh does.
    RunOptions m;
    m.scene = bare;
    m.display = "offscreen";
    m.frames = 1;
    m.out = (dir / "out").string();
    m.mesh = (fs::path(std::getenv("TRIDEX_ASSETS")) / "bunny.off").string();
    EXPECT_EQ(resolve_run(m).scene.spec.mesh_path, fs::absolute(m.mesh).lexically_normal().string());
    EXPECT_TRUE(resolve_run(m).scene.spec.model_path.empty());
    m.mesh = (dir / "none.off").string();
    EXPECT_NE(error_of([&] { (void)resolve_run(m); }).find("--mesh: no such file"), std::string::npos);
    fs::remove_all(dir);
}

// A long run's render log stays bounded: sums and histograms over every frame, per-frame tile counts for the first
// kTileFramesKept frames only.
TEST(RenderLog, KeepsBoundedMemoryOverALongRun) {
    RenderLog log;
    const std::size_t frames = RenderLog::kTileFramesKept + 500;
    for (std::size_t f = 0; f < frames; ++f) {
        renderer::FrameStats s;
        s.tiles[0] = {3, 1};
        s.tiles[1] = {2, 2};
        s.tile_triangles = {100, 80};
        s.passes = {{"opaque", 0, 1.0 + 0.001 * static_cast<double>(f % 10)}, {"overlay", -1, 0.045}};
        log.add(s);
    }
    EXPECT_EQ(log.frames, frames);
    EXPECT_EQ(log.tiles.size(), RenderLog::kTileFramesKept);
    EXPECT_EQ(log.tiles_drawn[0], 3 * frames);
    EXPECT_EQ(log.tiles_skipped[1], 2 * frames);
    EXPECT_EQ(log.tile_triangles[1], 80 * frames);
    ASSERT_EQ(log.pass_ms.size(), 2u);
    const DurationHistogram& opaque = log.pass_ms.at("opaque.left");
    EXPECT_EQ(opaque.count(), frames);
    // The median's bin is [1.00, 1.01) ms, whose upper edge lies above every sample: the largest, 1.009 ms.
    EXPECT_NEAR(opaque.percentile_ms(0.5), 1.009, 1e-9);
    EXPECT_NEAR(log.pass_ms.at("overlay").percentile_ms(0.99), 0.045, 1e-9);
    EXPECT_NEAR(opaque.sum_ms(), static_cast<double>(frames) * 1.0045, 1e-6);
}

}  // namespace
}  // namespace tridex::app
