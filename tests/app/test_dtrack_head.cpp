// The DTrack head: a loopback UDP sender speaking DTrack moves the off-axis eyes exactly as the sent poses say
// (through the display's tracker-to-wall calibration and the head-to-eyes offset), untracked and stale bodies fall
// back and say so, bad datagrams are counted, and an offscreen `tridex run --head dtrack:PORT` draws the same
// eyes as a fixed head at the tracked pose.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "../devices/dtrack_sender.hpp"
#include "app/input/dtrack_head.hpp"
#include "app/session/run/run_session.hpp"
#include "core/error.hpp"
#include "renderer/camera/display_config.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/image/image.hpp"
#include "renderer/image/image_compare.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using tridex::test::DTrackSender;
using tridex::test::dtrack_datagram;
using tridex::test::rigid;
using tridex::test::rotation_y_deg;

/// Calls head_at until the head has taken datagram `n` of the receiver (or 5 s pass).
Pose wait_pose(DTrackHead& h, std::uint64_t accepted, double t_s) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (h.receiver_stats().published < accepted && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return h.head_at(t_s);
}

TEST(DTrackHead, EyesMoveExactlyAsTheSentPosesSay) {
    // Calibration: tracker y-up frame turned 90 degrees about +y and shifted; glasses 8 cm above, 2 cm in front of
    // the eyes and turned 180 degrees about +y (the target's z points forward).
    DTrackHeadSettings s;
    s.port = 0;
    s.bind_address = "127.0.0.1";
    s.body = 3;
    const glm::dmat3 cal_r = rotation_y_deg(90.0), off_r = rotation_y_deg(180.0);
    const Vec3 cal_t(0.25, -1.1, 0.4), off_t(0.0, -0.08, -0.02);
    s.tracker_to_wall = Pose{cal_t, glm::quat_cast(cal_r)};
    s.head_to_eyes = Pose{off_t, glm::quat_cast(off_r)};
    s.fallback = Pose{Vec3(0, 0, 2), Quat(1, 0, 0, 0)};
    s.timeout_s = 10.0;
    DTrackHead head(s);
    DTrackSender tx(head.port());
    const double sep = 0.065;
    const struct {
        Vec3 mm;
        double deg;
    } poses[] = {{{100.0, 1650.0, 900.0}, 0.0}, {{-320.5, 1702.25, 1250.75}, 35.0}, {{12.0, 1500.0, 2400.0}, -80.0}};
    std::uint64_t sent = 0;
    for (const auto& p : poses) {
        ASSERT_TRUE(tx.send(dtrack_datagram(static_cast<unsigned>(sent + 1), 3, p.mm, rotation_y_deg(p.deg))));
        ++sent;
        const Pose h = wait_pose(head, sent, 1.0);
        // Reference: wall <- tracker <- body <- eyes frame, as 4x4 matrices.
        const glm::dmat4 m = rigid(cal_r, cal_t) * rigid(rotation_y_deg(p.deg), p.mm * 1e-3) * rigid(off_r, off_t);
        const auto eyes = renderer::eye_positions(h, sep);
        for (int e = 0; e < 2; ++e) {
            const Vec3 want = Vec3(m * glm::dvec4((e == 0 ? -0.5 : 0.5) * sep, 0.0, 0.0, 1.0));
            EXPECT_NEAR(eyes[e].x, want.x, 1e-7) << "pose " << sent << " eye " << e;
            EXPECT_NEAR(eyes[e].y, want.y, 1e-7) << "pose " << sent << " eye " << e;
            EXPECT_NEAR(eyes[e].z, want.z, 1e-7) << "pose " << sent << " eye " << e;
        }
        ASSERT_TRUE(head.last_position_m().has_value());
        EXPECT_NEAR(head.last_position_m()->x, p.mm.x * 1e-3, 1e-12);  // tracker coordinates, before calibration
    }
    EXPECT_EQ(head.frames_tracked(), 3u);
    EXPECT_EQ(head.frames_stale(), 0u);
    EXPECT_EQ(head.latency_ms().count(), 3u);
    EXPECT_EQ(head.latency_ms().rejected(), 0u);
    EXPECT_GE(head.latency_ms().min_ms(), 0.0);
    const nlohmann::json j = head.report_json();
    EXPECT_EQ(j.at("provider"), "dtrack");
    EXPECT_EQ(j.at("frames_tracked"), 3);
    EXPECT_NEAR(j.at("last_position_m")[2].get<double>(), 2.4, 1e-12);
    EXPECT_EQ(j.at("latency_ms").at("count"), 3);
}

TEST(DTrackHead, UntrackedStaleAndOtherBodiesFallBackAndSaySo) {
    DTrackHeadSettings s;
    s.port = 0;
    s.bind_address = "127.0.0.1";
    s.body = 0;
    s.fallback = Pose{Vec3(0, 0, 2), Quat(1, 0, 0, 0)};
    s.timeout_s = 0.1;
    DTrackHead head(s);
    const auto origin = std::chrono::steady_clock::now();
    head.set_session_origin(origin);
    const auto now_s = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - origin).count(); };
    EXPECT_EQ(head.head_at(now_s()).position, s.fallback.position);
    EXPECT_NE(head.note().find("no sample"), std::string::npos) << head.note();
    DTrackSender tx(head.port());
    // Another body only: still the fallback.
    ASSERT_TRUE(tx.send(dtrack_datagram(1, 5, Vec3(1, 2, 3), glm::dmat3(1.0))));
    EXPECT_EQ(wait_pose(head, 1, now_s()).position, s.fallback.position);
    // Tracked: the pose.
    ASSERT_TRUE(tx.send(dtrack_datagram(2, 0, Vec3(100, 200, 300), glm::dmat3(1.0))));
    EXPECT_NEAR(wait_pose(head, 2, now_s()).position.z, 0.3, 1e-12);
    EXPECT_NE(head.note().find(": tracked"), std::string::npos) << head.note();
    // Quality -1: the last pose holds until it is timeout_s old, then the fallback, and the note says why.
    ASSERT_TRUE(tx.send(dtrack_datagram(3, 0, Vec3(0, 0, 0), glm::dmat3(0.0), false)));
    (void)wait_pose(head, 3, now_s());
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    EXPECT_EQ(head.head_at(now_s()).position, s.fallback.position);
    EXPECT_NE(head.note().find("not tracked (quality -1)"), std::string::npos) << head.note();
    // Tracked again, then silence: stale after the timeout.
    ASSERT_TRUE(tx.send(dtrack_datagram(4, 0, Vec3(100, 200, 300), glm::dmat3(1.0))));
    EXPECT_NEAR(wait_pose(head, 4, now_s()).position.x, 0.1, 1e-12);
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    EXPECT_EQ(head.head_at(now_s()).position, s.fallback.position);
    EXPECT_NE(head.note().find("old (timeout"), std::string::npos) << head.note();
    EXPECT_GE(head.frames_stale(), 4u);
    EXPECT_EQ(head.report_json().at("fallbacks"), 2);
    // Bad datagrams are counted by reason and change nothing.
    ASSERT_TRUE(tx.send("6d 1 [0 1.0][nan 0 0][1 0 0 0 1 0 0 0 1]"));
    ASSERT_TRUE(tx.send("junk"));
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (head.receiver_stats().datagrams < 6 && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const nlohmann::json j = head.report_json();
    EXPECT_EQ(j.at("rejected"), 2);
    EXPECT_EQ(j.at("rejected_by_reason").at("not_finite"), 1);
    EXPECT_EQ(j.at("rejected_by_reason").at("unknown_line"), 1);
    EXPECT_EQ(head.head_at(now_s()).position, s.fallback.position);
}

TEST(DTrackHead, OptionAndSceneAndDisplayConfigAreChecked) {
    int port = 5000, body = 0;
    parse_dtrack_head_option("dtrack:5001", port, body);
    EXPECT_EQ(port, 5001);
    EXPECT_EQ(body, 0);
    parse_dtrack_head_option("dtrack:6000:7", port, body);
    EXPECT_EQ(port, 6000);
    EXPECT_EQ(body, 7);
    for (const char* bad : {"dtrack:", "dtrack:0", "dtrack:70000", "dtrack:50x0", "dtrack:5000:", "dtrack:5000:-1",
                            "dtrack:5000:64", "dtrack:5000:1:2", "vicon:5000"})
        EXPECT_THROW(parse_dtrack_head_option(bad, port, body), Error) << bad;
    // Display config: the tracking transforms round-trip and bad ones are named.
    const nlohmann::json j = nlohmann::json::parse(R"({"preset": "powerwall", "tracking": {
        "tracker_to_wall": {"position_m": [0.1, -1.2, 0.3], "orientation_wxyz": [0.70710678118654752, 0, 0.70710678118654752, 0]},
        "head_to_eyes": {"position_m": [0, -0.08, 0.02]}}})");
    const renderer::DisplayConfig c = renderer::display_config_from_json(j, "wall.json");
    EXPECT_NEAR(c.tracker_to_wall.position.y, -1.2, 1e-15);
    EXPECT_NEAR(c.head_to_eyes.position.z, 0.02, 1e-15);
    const renderer::DisplayConfig back = renderer::display_config_from_json(renderer::display_config_to_json(c), "x");
    EXPECT_NEAR(back.tracker_to_wall.orientation.y, c.tracker_to_wall.orientation.y, 1e-15);
    for (const char* bad : {R"({"tracking": {"tracker_to_wall": {"orientation_wxyz": [2, 0, 0, 0]}}})",
                            R"({"tracking": {"head_to_eyes": {"position_m": [0, 0]}}})",
                            R"({"tracking": {"eyes": {}}})", R"({"tracking": 3})"}) {
        try {
            renderer::display_config_from_json(nlohmann::json::parse(bad), "wall.json");
            ADD_FAILURE() << "accepted " << bad;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("tracking"), std::string::npos) << e.what();
        }
    }
}

// The bundled example of a real wall (corners measured in tracker space) loads, and its corners were squared up.
TEST(DTrackHead, ExampleWallDisplayConfigLoads) {
    const char* assets = std::getenv("TRIDEX_ASSETS");
    ASSERT_NE(assets, nullptr);
    const renderer::DisplayConfig c = renderer::load_display_config(std::string(assets) + "/dtrack_powerwall_display.json");
    EXPECT_NEAR(c.screen.width(), 3.048, 0.002);
    EXPECT_NEAR(c.screen.height(), 2.286, 0.002);
    EXPECT_NEAR(c.head_to_eyes.position.z, 0.03, 1e-15);
    EXPECT_EQ(c.stereo, renderer::StereoOutput::kFrameSequential);
}

/// A UDP port that was free a moment ago.
int free_port() {
    devices::DTrackReceiver probe(0, "127.0.0.1");
    return probe.port();
}

/// Writes a scene without a stroke (the model does not change, so frames depend only on the head).
std::string write_still_scene(const fs::path& dir) {
    const std::string path = (dir / "scene.json").string();
    std::ofstream(path) << R"({
  "workpiece": { "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "stroke": "none",
  "display": { "preset": "desktop", "resolution": [96, 72], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.0, 0.6] }
})";
    return path;
}

RunResult run(const std::string& scene, const fs::path& out, const std::string& head, int frames = 4) {
    RunOptions o;
    o.scene = scene;
    o.display = "offscreen";
    o.stereo = "side-by-side";
    o.frames = frames;
    o.out = out.string();
    o.no_journal = true;
    o.items = false;  // no overlay: its frame times differ between runs
    o.lod = "off";    // levels of detail arrive when the worker has them: the frames they change differ between runs
    o.head = head;
    return run_stereo_session(o);
}

// Offscreen `tridex run --head dtrack:PORT:0` while a sender streams a head pose: the eyes are those of a fixed head
// at the tracked pose (the same images), and report.json's head block says what happened.
TEST(DTrackHead, OffscreenRunDrawsTheTrackedEyes) {
    const fs::path dir = test::temp_dir("dtrack_run");
    const std::string scene = write_still_scene(dir);
    const int port = free_port();
    std::atomic<bool> stop{false};
    // Head at (60, 40, 550) mm in tracker = wall coordinates (identity calibration), turned 10 degrees.
    std::thread sender([&] {
        DTrackSender tx(port);
        for (unsigned fr = 1; !stop.load(); ++fr) {
            tx.send(dtrack_datagram(fr, 0, Vec3(60.0, 40.0, 550.0), rotation_y_deg(10.0)));
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    });
    RunResult tracked;
    try {
        tracked = run(scene, dir / "dtrack", "dtrack:" + std::to_string(port) + ":0");
    } catch (...) {
        stop = true;
        sender.join();
        throw;
    }
    stop = true;
    sender.join();
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "dtrack" / "report.json"));
    const nlohmann::json& h = report.at("head");
    EXPECT_EQ(h.at("provider"), "dtrack");
    EXPECT_EQ(h.at("port"), port);
    EXPECT_GE(h.at("frames_tracked").get<int>(), 1);
    EXPECT_EQ(h.at("frames_tracked").get<int>() + h.at("frames_stale").get<int>(), 4);
    EXPECT_NEAR(h.at("last_position_m")[0].get<double>(), 0.060, 1e-12);
    EXPECT_NEAR(h.at("last_position_m")[2].get<double>(), 0.550, 1e-12);
    EXPECT_GE(h.at("latency_ms").at("count").get<int>(), 1);
    EXPECT_EQ(h.at("rejected"), 0);
    EXPECT_NE(h.at("note").get<std::string>().find(": tracked"), std::string::npos) << h.at("note");
    std::printf("[ dtrack ] run: %d frames tracked, latency median %.3f ms p99 %.3f ms (%d samples)\n",
                h.at("frames_tracked").get<int>(), h.at("latency_ms").at("median").get<double>(),
                h.at("latency_ms").at("p99").get<double>(), h.at("latency_ms").at("count").get<int>());

    // The same eyes from a fixed head at the tracked pose: the scene's head position and orientation.
    const std::string fixed_scene = (dir / "fixed.json").string();
    {
        nlohmann::json j = nlohmann::json::parse(std::ifstream(scene));
        const Quat q = glm::normalize(glm::quat_cast(rotation_y_deg(10.0)));
        j["head"] = {{"provider", "fixed"}, {"position_m", {0.060, 0.040, 0.550}}, {"orientation_wxyz", {q.w, q.x, q.y, q.z}}};
        std::ofstream(fixed_scene) << j.dump(2);
    }
    run(fixed_scene, dir / "fixed", "");
    const renderer::Image a = renderer::read_png((dir / "dtrack" / "left.png").string());
    const renderer::Image b = renderer::read_png((dir / "fixed" / "left.png").string());
    EXPECT_LE(renderer::compare_images(a, b, 0).max_channel_diff, 1);
    // And the test can fail: the default head (not tracked) draws other eyes.
    run(scene, dir / "untracked", "");
    const renderer::Image c = renderer::read_png((dir / "untracked" / "left.png").string());
    EXPECT_GT(renderer::compare_images(a, c, 0).max_channel_diff, 8);
}

// A tracker glitch never ends a session: a head tracked at or behind the screen plane (or anywhere the eyes cannot
// see the screen from) holds the last good head pose, here the scene's own, and is counted in report.json.
TEST(DTrackHead, AHeadBehindTheScreenIsHeldNotFatal) {
    const fs::path dir = test::temp_dir("dtrack_behind");
    const std::string scene = write_still_scene(dir);
    const int port = free_port();
    std::atomic<bool> stop{false};
    std::thread sender([&] {  // 100 mm behind the wall (identity calibration: tracker = wall coordinates)
        DTrackSender tx(port);
        for (unsigned fr = 1; !stop.load(); ++fr) {
            tx.send(dtrack_datagram(fr, 0, Vec3(0.0, 0.0, -100.0), glm::dmat3(1.0)));
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    });
    RunResult behind;
    try {
        behind = run(scene, dir / "behind", "dtrack:" + std::to_string(port) + ":0", 6);
    } catch (...) {
        stop = true;
        sender.join();
        throw;
    }
    stop = true;
    sender.join();
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "behind" / "report.json"));
    const nlohmann::json& h = report.at("head");
    EXPECT_GE(h.at("frames_tracked").get<int>(), 1) << h.dump();
    EXPECT_EQ(h.at("frames_held").get<int>(), h.at("frames_tracked").get<int>()) << h.dump();
    EXPECT_TRUE(std::any_of(behind.notes.begin(), behind.notes.end(),
                            [](const std::string& n) { return n.find("held the last good head pose") != std::string::npos; }));
    // The held frames were drawn from the scene's head: the same image as a run that never tracked the head.
    run(scene, dir / "fixed", "", 6);
    const renderer::Image a = renderer::read_png((dir / "behind" / "left.png").string());
    const renderer::Image b = renderer::read_png((dir / "fixed" / "left.png").string());
    EXPECT_LE(renderer::compare_images(a, b, 0).max_channel_diff, 1);
}

}  // namespace
}  // namespace tridex::app
