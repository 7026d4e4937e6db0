// The Wand: grab-and-move and rotate deltas exact against hand-computed matrices, joystick scaling about the
// pivot, reset, lost and stale wands that never move the scene, and a loopback UDP sender speaking DTrack
// Flystick datagrams that moves the scene exactly as sent.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "../devices/dtrack_sender.hpp"
#include "app/input/dtrack_head.hpp"
#include "app/input/dtrack_wand.hpp"
#include "app/session/run/run_options.hpp"
#include "app/scene/run_scene.hpp"
#include "app/session/run/run_session.hpp"
#include "app/input/wand_navigation.hpp"
#include "core/error.hpp"
#include "dtrack_session.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

using renderer::SceneNavigation;
using tridex::test::dtrack_flystick_datagram;
using tridex::test::DTrackSender;
using tridex::test::rigid;
using tridex::test::rotation_y_deg;

void expect_mat_near(const glm::dmat4& a, const glm::dmat4& b, double tol) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(a[c][r], b[c][r], tol) << "column " << c << " row " << r;
}

WandSample at(const glm::dmat3& r, const Vec3& p, std::uint64_t buttons, double joy_y = 0.0) {
    return WandSample{true, Pose{p, glm::quat_cast(r)}, buttons, joy_y};
}

TEST(WandNavigator, TriggerMovesTheSceneByTheWandsTranslation) {
    SceneNavigation nav(Pose{Vec3(0.1, 0.2, 0.3), Quat(1, 0, 0, 0)}, 2.0);
    WandNavigator w;
    const glm::dmat3 id(1.0);
    w.update(at(id, Vec3(0.5, 1.0, 0.5), 0x1), 0.016, nav);  // press: no motion yet
    EXPECT_NEAR(nav.pose().position.x, 0.1, 1e-15);
    w.update(at(id, Vec3(0.6, 0.95, 0.5), 0x1), 0.016, nav);
    // Hand-computed: the scene origin moves by the wand's (0.1, -0.05, 0); scale and rotation stay.
    expect_mat_near(nav.world_from_scene(), rigid(glm::dmat3(2.0), Vec3(0.2, 0.15, 0.3)), 1e-12);
    w.update(at(id, Vec3(0.9, 0.95, 0.5), 0x0), 0.016, nav);  // released: the wand moves alone
    EXPECT_NEAR(nav.pose().position.x, 0.2, 1e-12);
    EXPECT_EQ(w.grabs(), 1u);
}

TEST(WandNavigator, TurningTheWandTurnsTheSceneAboutTheWand) {
    SceneNavigation nav;
    WandNavigator w;
    w.update(at(glm::dmat3(1.0), Vec3(1, 0, 0), 0x1), 0.016, nav);
    w.update(at(rotation_y_deg(90.0), Vec3(1, 0, 0), 0x1), 0.016, nav);
    // Hand-computed: D = T(1,0,0) Ry(90) T(-1,0,0); Ry(90) takes x to -z and z to x, so the scene origin goes to
    // (1,0,0) + Ry(90)(-1,0,0) = (1,0,1) and the scene's axes turn with the wand.
    glm::dmat3 r(0.0);
    r[0] = Vec3(0, 0, -1);
    r[1] = Vec3(0, 1, 0);
    r[2] = Vec3(1, 0, 0);
    expect_mat_near(nav.world_from_scene(), rigid(r, Vec3(1, 0, 1)), 1e-12);
}

TEST(WandNavigator, AGrabFollowsTheTotalDeltaSinceThePress) {
    const Pose start{Vec3(0.05, -0.1, 0.2), glm::quat_cast(rotation_y_deg(20.0))};
    SceneNavigation nav(start, 1.5);
    const glm::dmat4 w0 = nav.world_from_scene();
    WandNavigator w;
    const glm::dmat3 ra = rotation_y_deg(-10.0), rc = rotation_y_deg(35.0);
    const Vec3 pa(0.3, 1.2, 0.6), pc(-0.2, 1.4, 0.9);
    w.update(at(ra, pa, 0x1), 0.016, nav);
    w.update(at(rotation_y_deg(5.0), Vec3(0.1, 1.3, 0.7), 0x1), 0.016, nav);
    w.update(at(rc, pc, 0x1), 0.016, nav);
    // world_from_scene = wand_now * wand_at_press^-1 * world_from_scene_at_press (scale 1.5 kept).
    expect_mat_near(nav.world_from_scene(), rigid(rc, pc) * glm::inverse(rigid(ra, pa)) * w0, 1e-12);
}

TEST(WandNavigator, JoystickScalesAboutThePivotAtAnExponentialRateClamped) {
    WandNavigationSettings s;
    s.pivot_m = Vec3(0.2, 1.0, -0.3);
    SceneNavigation nav(Pose{}, 1.0, 0.5, 4.0);
    const Vec3 pivot_in_scene = nav.to_scene(s.pivot_m);
    WandNavigator w(s);
    w.update(at(glm::dmat3(1.0), Vec3(0), 0x0, 1.0), 0.05, nav);
    EXPECT_NEAR(nav.scale(), std::pow(2.0, 0.05), 1e-12);  // ln 2 per s at full deflection
    const Vec3 p = nav.to_world(pivot_in_scene);
    EXPECT_NEAR(glm::length(p - s.pivot_m), 0.0, 1e-12);  // the pivot stays put
    w.update(at(glm::dmat3(1.0), Vec3(0), 0x0, -1.0), 0.05, nav);
    EXPECT_NEAR(nav.scale(), 1.0, 1e-12);
    w.update(at(glm::dmat3(1.0), Vec3(0), 0x0, 0.05), 0.05, nav);  // inside the dead zone
    EXPECT_NEAR(nav.scale(), 1.0, 1e-12);
    w.update(at(glm::dmat3(1.0), Vec3(0), 0x0, 1.0), 30.0, nav);  // a long frame counts as max_dt_s
    EXPECT_NEAR(nav.scale(), std::pow(2.0, 0.1), 1e-12);
    for (int i = 0; i < 200; ++i) w.update(at(glm::dmat3(1.0), Vec3(0), 0x0, 1.0), 0.1, nav);
    EXPECT_NEAR(nav.scale(), 4.0, 1e-12);  // SceneNavigation's limit
    w.update(at(glm::dmat3(1.0), Vec3(0), 0x0, 1.0), std::nan(""), nav);
    EXPECT_NEAR(nav.scale(), 4.0, 1e-12);
}

TEST(WandNavigator, ResetButtonRestoresTheStartOnceAPress) {
    SceneNavigation nav;
    WandNavigator w;
    w.update(at(glm::dmat3(1.0), Vec3(0), 0x1), 0.016, nav);
    w.update(at(glm::dmat3(1.0), Vec3(0.3, 0, 0), 0x1), 0.016, nav);
    ASSERT_NEAR(nav.pose().position.x, 0.3, 1e-12);
    w.update(at(glm::dmat3(1.0), Vec3(0.3, 0, 0), 0x2), 0.016, nav);
    EXPECT_NEAR(nav.pose().position.x, 0.0, 1e-15);
    EXPECT_EQ(w.resets(), 1u);
    w.update(at(glm::dmat3(1.0), Vec3(0.3, 0, 0), 0x3), 0.016, nav);  // still held: no second reset; a new grab
    w.update(at(glm::dmat3(1.0), Vec3(0.4, 0, 0), 0x3), 0.016, nav);
    EXPECT_NEAR(nav.pose().position.x, 0.1, 1e-12);
    EXPECT_EQ(w.resets(), 1u);
}

TEST(WandNavigator, LostOrBadSamplesNeverMoveTheScene) {
    SceneNavigation nav;
    WandNavigator w;
    w.update(at(glm::dmat3(1.0), Vec3(0), 0x1), 0.016, nav);
    WandSample lost = at(rotation_y_deg(90.0), Vec3(5, 5, 5), 0x1, 1.0);
    lost.fresh = false;
    w.update(lost, 0.016, nav);
    EXPECT_FALSE(w.grabbing());
    EXPECT_EQ(w.grabs_dropped(), 1u);
    WandSample nan_pose = at(glm::dmat3(1.0), Vec3(std::nan(""), 0, 0), 0x1, 1.0);
    w.update(nan_pose, 0.016, nav);
    WandSample zero_q = at(glm::dmat3(1.0), Vec3(0), 0x1, 1.0);
    zero_q.pose.orientation = Quat(0, 0, 0, 0);
    w.update(zero_q, 0.016, nav);
    expect_mat_near(nav.world_from_scene(), glm::dmat4(1.0), 0.0);
    // Tracked again far away with the trigger held: the grab restarts there, no jump; then it follows.
    w.update(at(glm::dmat3(1.0), Vec3(2, 2, 2), 0x1), 0.016, nav);
    expect_mat_near(nav.world_from_scene(), glm::dmat4(1.0), 0.0);
    w.update(at(glm::dmat3(1.0), Vec3(2.1, 2, 2), 0x1), 0.016, nav);
    EXPECT_NEAR(nav.pose().position.x, 0.1, 1e-12);
    EXPECT_EQ(w.frames_lost(), 3u);
    EXPECT_EQ(w.grabs(), 2u);
}

TEST(WandNavigator, BadSettingsThrow) {
    WandNavigationSettings s;
    s.reset_button = 0;
    EXPECT_THROW(WandNavigator{s}, Error);
    s = {};
    s.grab_button = 64;
    EXPECT_THROW(WandNavigator{s}, Error);
    s = {};
    s.scale_rate_per_s = std::nan("");
    EXPECT_THROW(WandNavigator{s}, Error);
    s = {};
    s.dead_zone = 1.0;
    EXPECT_THROW(WandNavigator{s}, Error);
}

/// Sends `datagram`, waits until the receiver has parsed it and published it if it accepted it (at most 5 s), and
/// returns sample().
WandSample wait_sample(DTrackWand& w, DTrackSender& tx, const std::string& datagram) {
    const std::uint64_t before = w.receiver_stats().datagrams;
    EXPECT_TRUE(tx.send(datagram));
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (std::chrono::steady_clock::now() < until) {
        const devices::DTrackReceiverStats st = w.receiver_stats();
        // Parsed (the receiver counts a datagram before it parses it), and published if accepted.
        if (st.accepted + st.rejected > before && st.published == st.accepted) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return w.sample();
}

TEST(DTrackWand, AFlystickOverUdpMovesTheSceneAsSent) {
    DTrackWandSettings s;
    s.port = 0;
    s.bind_address = "127.0.0.1";
    s.flystick = 2;
    s.timeout_s = 0.5;
    const glm::dmat3 cal_r = rotation_y_deg(90.0);
    const Vec3 cal_t(0.25, -1.1, 0.4);
    s.tracker_to_wall = Pose{cal_t, glm::quat_cast(cal_r)};
    DTrackWand wand(s);
    DTrackSender tx(wand.port());
    SceneNavigation nav;
    WandNavigator wn;
    EXPECT_FALSE(wand.sample().fresh);  // nothing sent yet
    const glm::dmat3 ra = rotation_y_deg(10.0), rb = rotation_y_deg(-25.0);
    const Vec3 pa_mm(100, 1200, 300), pb_mm(-50, 1350, 420);
    WandSample a = wait_sample(wand, tx, dtrack_flystick_datagram(1, 2, pa_mm, ra, 0x1, 0.0, 0.0));
    ASSERT_TRUE(a.fresh) << wand.note();
    EXPECT_EQ(a.buttons, 0x1u);
    wn.update(a, 0.016, nav);
    WandSample b = wait_sample(wand, tx, dtrack_flystick_datagram(2, 2, pb_mm, rb, 0x1, 0.0, 0.0));
    ASSERT_TRUE(b.fresh) << wand.note();
    wn.update(b, 0.016, nav);
    // Expected, from the sent numbers: wall_from_wand = cal * (R, p mm / 1000); the scene follows B * A^-1.
    const glm::dmat4 cal = rigid(cal_r, cal_t);
    const glm::dmat4 A = cal * rigid(ra, pa_mm / 1000.0), B = cal * rigid(rb, pb_mm / 1000.0);
    expect_mat_near(nav.world_from_scene(), B * glm::inverse(A), 1e-8);
    // The joystick's y is controller 1.
    WandSample c = wait_sample(wand, tx, dtrack_flystick_datagram(3, 2, pb_mm, rb, 0x0, 0.3, -0.75));
    EXPECT_DOUBLE_EQ(c.joystick_y, -0.75);
    EXPECT_EQ(wand.report_json().at("frames_tracked").get<int>(), 3);
}

TEST(DTrackWand, StaleOrUntrackedFlysticksNeverMoveTheScene) {
    DTrackWandSettings s;
    s.port = 0;
    s.bind_address = "127.0.0.1";
    s.timeout_s = 0.1;
    DTrackWand wand(s);
    DTrackSender tx(wand.port());
    SceneNavigation nav;
    WandNavigator wn;
    wn.update(wait_sample(wand, tx, dtrack_flystick_datagram(1, 0, Vec3(0, 1000, 0), glm::dmat3(1.0), 0x1, 0, 0)),
              0.016, nav);
    ASSERT_TRUE(wn.grabbing()) << wand.note();
    // Untracked (quality -1) while the trigger is held: nothing moves.
    const WandSample u =
        wait_sample(wand, tx, dtrack_flystick_datagram(2, 0, Vec3(500, 1000, 0), glm::dmat3(1.0), 0x1, 0, 1.0, false));
    EXPECT_FALSE(u.fresh);
    wn.update(u, 0.016, nav);
    // A fresh pose, then silence: the stale sample (older than timeout_s) moves nothing even though its trigger is
    // held and its joystick pushed.
    wn.update(wait_sample(wand, tx, dtrack_flystick_datagram(3, 0, Vec3(0, 1000, 0), glm::dmat3(1.0), 0x1, 0, 1.0)),
              0.016, nav);
    const glm::dmat4 before = nav.world_from_scene();
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    const WandSample stale = wand.sample();
    EXPECT_FALSE(stale.fresh);
    EXPECT_NE(wand.note().find("stale"), std::string::npos) << wand.note();
    wn.update(stale, 0.016, nav);
    expect_mat_near(nav.world_from_scene(), before, 0.0);
    EXPECT_NEAR(nav.pose().position.x, 0.0, 1e-12);  // the untracked 0.5 m never arrived
    EXPECT_GE(wand.frames_stale(), 2u);
}

TEST(DTrackWand, SharesTheHeadsReceiverOnTheSamePort) {
    DTrackHeadSettings hs;
    hs.port = 0;
    hs.bind_address = "127.0.0.1";
    DTrackHead head(hs);
    DTrackWandSettings ws;
    ws.timeout_s = 1.0;
    DTrackWand wand(ws, head.receiver());
    EXPECT_EQ(wand.port(), head.port());
    DTrackSender tx(head.port());
    const WandSample w = wait_sample(wand, tx, dtrack_flystick_datagram(1, 0, Vec3(0, 1000, 0), glm::dmat3(1.0), 0, 0, 0));
    EXPECT_TRUE(w.fresh) << wand.note();
    EXPECT_EQ(wand.report_json().at("shared_receiver").get<bool>(), true);
}

TEST(DTrackWand, OptionParsing) {
    int port = 1, fly = 0;
    parse_dtrack_wand_option("dtrack:5001:3", port, fly);
    EXPECT_EQ(port, 5001);
    EXPECT_EQ(fly, 3);
    parse_dtrack_wand_option("dtrack:5002", port, fly);
    EXPECT_EQ(port, 5002);
    EXPECT_EQ(fly, 3);
    EXPECT_THROW(parse_dtrack_wand_option("dtrack:0:1", port, fly), Error);
    EXPECT_THROW(parse_dtrack_wand_option("dtrack:5000:16", port, fly), Error);
    EXPECT_THROW(parse_dtrack_wand_option("vrpn:5000", port, fly), Error);
    DTrackWandSettings s;
    s.flystick = -1;
    EXPECT_THROW(DTrackWand{s}, Error);
}

TEST(DTrackWand, SceneWandBlockIsReadAndChecked) {
    const RunScene s = run_scene_from_json(
        nlohmann::json::parse(R"({"wand": {"provider": "dtrack", "port": 5005, "flystick": 2, "timeout_s": 0.2}})"),
        "t.json", ".");
    EXPECT_TRUE(s.wand_dtrack);
    EXPECT_EQ(s.wand_port, 5005);
    EXPECT_EQ(s.wand_flystick, 2);
    EXPECT_DOUBLE_EQ(s.wand_timeout_s, 0.2);
    EXPECT_FALSE(run_scene_from_json(nlohmann::json::object(), "t.json", ".").wand_dtrack);
    for (const char* bad : {R"({"wand": {"provider": "vrpn"}})", R"({"wand": {"flystick": 16}})",
                            R"({"wand": {"port": 0}})", R"({"wand": {"button": 1}})"})
        EXPECT_THROW(run_scene_from_json(nlohmann::json::parse(bad), "t.json", "."), Error) << bad;
}

// Offscreen `tridex run --head dtrack:PORT:0 --wand dtrack:PORT:1` while a sender streams the head and a Flystick
// carried along +x with the trigger held: the wand shares the head's receiver and carries the scene along +x.
TEST(DTrackWand, OffscreenRunCarriesTheSceneWithTheFlystick) {
    namespace fs = std::filesystem;
    const fs::path dir = test::temp_dir("wand_run");
    const std::string scene = (dir / "scene.json").string();
    std::ofstream(scene) << R"({
  "workpiece": { "resolution": 32, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "stroke": "none",
  "display": { "preset": "desktop", "resolution": [64, 48], "refresh_hz": 60 }
})";
    const int port = test::free_dtrack_port();
    RunOptions o;
    o.scene = scene;
    o.display = "offscreen";
    o.stereo = "side-by-side";
    o.seconds = 1.0;
    o.out = (dir / "out").string();
    o.no_journal = true;
    o.items = false;
    o.head = "dtrack:" + std::to_string(port) + ":0";
    o.wand = "dtrack:" + std::to_string(port) + ":1";
    test::run_while_sending(o, port, [](DTrackSender& tx, unsigned fr, double) {
        tx.send(tridex::test::dtrack_datagram(fr, 0, Vec3(0.0, 0.0, 600.0), glm::dmat3(1.0)));
        tx.send(dtrack_flystick_datagram(fr, 1, Vec3(0.5 * fr, 0.0, 300.0), glm::dmat3(1.0), 0x1, 0.0, 0.0));
    });
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "out" / "report.json"));
    const nlohmann::json& w = report.at("wand");
    EXPECT_EQ(w.at("provider").get<std::string>(), "dtrack");
    EXPECT_TRUE(w.at("shared_receiver").get<bool>());
    EXPECT_GE(w.at("grabs").get<int>(), 1) << w.dump();
    EXPECT_GE(w.at("frames_tracked").get<int>(), 2) << w.dump();
    const nlohmann::json& p = w.at("final_position_m");
    EXPECT_GT(p[0].get<double>(), 0.005) << w.dump();  // carried along +x
    EXPECT_NEAR(p[1].get<double>(), 0.0, 1e-9);
    EXPECT_NEAR(p[2].get<double>(), 0.0, 1e-9);
    EXPECT_EQ(report.at("head").at("provider").get<std::string>(), "dtrack");
}

// Offscreen `tridex run --head dtrack:PORT:0 --device flystick:PORT:1`: the Flystick is the tool (no haptic
// device), reading the head's receiver. Carried through the workpiece with the trigger held it carves; carried
// the same way with the trigger released it carves nothing (the god-object still rests the proxy on the surface).
TEST(DTrackTool, TheFlystickCarvesOnlyWhileItsTriggerIsHeld) {
    namespace fs = std::filesystem;
    const fs::path dir = test::temp_dir("flystick_tool");
    const std::string scene = (dir / "scene.json").string();
    std::ofstream(scene) << R"({
  "workpiece": { "resolution": 32, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "display": { "preset": "desktop", "resolution": [64, 48], "refresh_hz": 60 }
})";
    const int port = test::free_dtrack_port();
    auto run = [&](unsigned buttons, const std::string& out) {
        RunOptions o;
        o.scene = scene;
        o.display = "offscreen";
        o.stereo = "side-by-side";
        o.seconds = 1.5;
        o.out = (dir / out).string();
        o.no_journal = true;
        o.head = "dtrack:" + std::to_string(port) + ":0";
        o.device = "flystick:" + std::to_string(port) + ":1";
        test::run_while_sending(o, port, [buttons](DTrackSender& tx, unsigned fr, double) {
            // Across the workpiece along x at its centre, 0.1 m/s, back and forth.
            const double x_mm = -50.0 + std::fmod(0.5 * fr, 100.0);
            tx.send(tridex::test::dtrack_datagram(fr, 0, Vec3(0.0, 0.0, 600.0), glm::dmat3(1.0)));
            tx.send(dtrack_flystick_datagram(fr, 1, Vec3(x_mm, 0.0, 50.0), glm::dmat3(1.0), buttons, 0.0, 0.0));
        });
        return nlohmann::json::parse(std::ifstream(dir / out / "report.json"));
    };
    const nlohmann::json held = run(0x1, "held");
    EXPECT_EQ(held.at("haptics").at("device_driver").get<std::string>(), "flystick");
    EXPECT_GT(held.at("haptics").at("contact_ticks").get<int>(), 0) << held.at("haptics").dump();
    EXPECT_LT(held.at("volume_after_m3").get<double>(), held.at("volume_before_m3").get<double>());
    const nlohmann::json released = run(0x0, "released");
    EXPECT_GT(released.at("haptics").at("contact_ticks").get<int>(), 0);
    EXPECT_EQ(released.at("volume_after_m3").get<double>(), released.at("volume_before_m3").get<double>());
    // The wand and the tool cannot be the same Flystick.
    RunOptions same;
    same.scene = scene;
    same.display = "offscreen";
    same.seconds = 0.1;
    same.out = (dir / "same").string();
    same.device = "flystick:" + std::to_string(port) + ":1";
    same.wand = "dtrack:" + std::to_string(port) + ":1";
    try {
        run_stereo_session(same);
        ADD_FAILURE() << "the wand's Flystick was accepted as the tool";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("navigates the scene already"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace tridex::app
