// `tridex run --device spacemouse` end to end against a stand-in spacenavd socket: pushing the cap in moves the tool
// away from the viewer, as in every spacenavd application, through the session's haptic loop at no more than the
// scene's max_speed_m_s; the scene's gains are checked.
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "../devices/spnav_standin.hpp"
#include "app/scene/run_scene.hpp"
#include "app/session/run/run_session.hpp"
#include "core/error.hpp"
#include "devices/recording.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

std::string write_scene(const fs::path& dir, const std::string& device_extra) {
    const std::string path = (dir / "spacemouse_scene.json").string();
    std::ofstream(path) << R"({
  "workpiece": { "resolution": 48, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "device": { "driver": "spacemouse")" << device_extra << R"( },
  "stroke": "none",
  "display": { "preset": "desktop", "resolution": [96, 72], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] }
}
)";
    return path;
}

// Connects to `path` and closes again: wakes a stand-in still waiting for its client.
void poke(const std::string& path) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
    (void)::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
    ::close(fd);
}

TEST(SpaceMouseSession, ThePuckMovesTheToolAtTheScenesSpeed) {
    const fs::path dir = test::temp_dir("spacemouse_session");
    devices::test::SpnavStandIn daemon;
    ::setenv("SPNAV_SOCKET", daemon.path().c_str(), 1);
    constexpr double kSpeed = 0.02;  // m/s at full deflection (the default is 0.1)
    // The cap pushed all the way in, away from the user, once the session's device has connected: spacenavd's +z
    // (its frame is left-handed, z into the screen; libspnav's spnav_posrot_moveobj moves an object to -z for it).
    std::thread puck([&daemon] {
        daemon.wait_client();
        daemon.motion(0, 0, 350, 0, 0, 0);
    });
    RunOptions o;
    o.scene = write_scene(dir, R"(, "max_speed_m_s": 0.02, "dead_zone": 0.1, "full_scale": 350)");
    o.display = "offscreen";
    o.stereo = "mono";
    o.seconds = 2.0;
    o.out = (dir / "out").string();
    o.no_journal = true;
    o.cpu = true;
    o.record = (dir / "puck.trec").string();
    RunResult r;
    try {
        r = run_stereo_session(o);
    } catch (const std::exception& e) {
        ADD_FAILURE() << "the session failed: " << e.what();
    }
    poke(daemon.path());
    puck.join();
    ::unsetenv("SPNAV_SOCKET");
    if (HasFailure()) return;
    EXPECT_NE(r.haptics["device"].get<std::string>().find("spacemouse"), std::string::npos) << r.haptics.dump();
    EXPECT_EQ(r.haptics["device_driver"], "spacemouse");
    EXPECT_EQ(r.haptics["device_status"]["faults"], "none") << r.haptics["device_status"].dump();
    const double moved_z = r.haptics["tool_world_extent_m"][2].get<double>();
    const double moved_x = r.haptics["tool_world_extent_m"][0].get<double>();
    const double ticks = r.haptics["ticks"].get<double>();
    EXPECT_GT(moved_z, 1e-3) << "the push did not move the tool";
    EXPECT_LT(moved_x, 0.1 * moved_z) << "the tool moved across the push";
    // Rate control at the scene's speed: never faster than kSpeed over the ticks the session ran.
    const double moved = std::hypot(moved_x, r.haptics["tool_world_extent_m"][1].get<double>(), moved_z);
    EXPECT_LE(moved, kSpeed * ticks * 1e-3 + 1e-9);
    // The direction: the stylus went to -z in the device frame (away from the viewer), never toward the viewer.
    const devices::Recording rec = devices::read_recording(o.record);
    ASSERT_GT(rec.ticks.size(), 100u);
    const double dz = rec.ticks.back().device.pose.position.z - rec.ticks.front().device.pose.position.z;
    EXPECT_LT(dz, -0.5 * moved_z) << "pushing the cap in moved the tool toward the viewer";
    std::printf("[spacemouse session] %.0f ticks, tool moved %.1f mm along z\n", ticks, 1e3 * moved_z);
}

TEST(SpaceMouseSession, SceneGainsAreReadAndCheckedByName) {
    const fs::path dir = test::temp_dir("spacemouse_scene");
    const RunScene s = load_run_scene(
        write_scene(dir, R"(, "max_speed_m_s": 0.05, "max_rate_rad_s": 0.75, "dead_zone": 0.2, "full_scale": 500)"));
    EXPECT_EQ(s.device_options.at("max_speed_m_s"), 0.05);
    EXPECT_EQ(s.device_options.at("max_rate_rad_s"), 0.75);
    EXPECT_EQ(s.device_options.at("dead_zone"), 0.2);
    EXPECT_EQ(s.device_options.at("full_scale"), 500.0);
    const auto refused = [&](const std::string& extra, const std::string& field) {
        try {
            (void)load_run_scene(write_scene(dir, extra));
            ADD_FAILURE() << "accepted: " << extra;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    refused(R"(, "max_speed_m_s": 0)", "device.max_speed_m_s");
    refused(R"(, "dead_zone": 1.5)", "device.dead_zone");
    refused(R"(, "max_rate_rad_s": "fast")", "device.max_rate_rad_s");
}

}  // namespace
}  // namespace tridex::app
