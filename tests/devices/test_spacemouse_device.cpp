// The 3D-mouse driver against a stand-in spacenavd: rate control, buttons, garbage, a vanished daemon.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include <array>
#include <cmath>
#include <cstdint>

#include "core/error.hpp"
#include "devices/registry/device_registry.hpp"
#include "devices/spacemouse_device.hpp"
#include "spnav_standin.hpp"

namespace tridex::devices {
namespace {

using test::SpnavStandIn;

SpaceMouseParams params_at(const std::string& path) {
    SpaceMouseParams p;
    p.socket_path = path;
    return p;  // full scale 350, dead zone 5 %, 0.1 m/s, 1.5 rad/s
}

struct Rig {
    SpnavStandIn daemon;
    SpaceMouseDevice dev{DeviceProfile::phantom_omni(), Vec3(0.0), 1e-3, params_at(daemon.path())};
    Rig() {
        dev.bring_up();
        daemon.wait_client();
    }
    DeviceState read() {
        DeviceState s;
        EXPECT_TRUE(dev.read(s));
        return s;
    }
};

TEST(SpaceMouseDevice, NoDaemonGivesOneClearLine) {
    SpaceMouseDevice dev(DeviceProfile::phantom_omni(), Vec3(0.0), 1e-3, params_at("/tmp/tridex-no-such-spnav.sock"));
    try {
        dev.open();
        FAIL() << "open() without a daemon must throw";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(),
                     "spacemouse: no spacenavd at /tmp/tridex-no-such-spnav.sock: is the daemon running? "
                     "(Debian package spacenavd)");
    }
    EXPECT_EQ(dev.state(), DeviceLifecycle::kClosed);
}

TEST(SpaceMouseDevice, TranslationIsRateControlled) {
    Rig r;
    EXPECT_EQ(r.read().pose.position, Vec3(0.0));  // at rest until the puck moves
    r.daemon.motion(350, 0, 0, 0, 0, 0);          // full deflection: 0.1 m/s
    DeviceState s;
    for (int i = 0; i < 10; ++i) s = r.read();
    EXPECT_NEAR(s.pose.position.x, 1e-3, 1e-12);  // 10 ticks of 1 ms at 0.1 m/s
    EXPECT_NEAR(s.velocity_m_s.x, 0.1, 1e-9);
    r.daemon.motion(0, -175, 0, 0, 0, 0);  // half deflection, past the dead zone: rescaled
    s = r.read();
    EXPECT_NEAR(s.pose.position.y, -0.1 * 1e-3 * (0.5 - 0.05) / 0.95, 1e-12);
    EXPECT_NEAR(s.pose.position.x, 1e-3, 1e-12);
    r.daemon.motion(10, 0, -12, 0, 0, 0);  // inside the dead zone: held
    const Vec3 held = r.read().pose.position;
    EXPECT_EQ(r.read().pose.position, held);
    EXPECT_EQ(r.read().velocity_m_s, Vec3(0.0));
}

TEST(SpaceMouseDevice, RotationIsRateControlled) {
    Rig r;
    r.daemon.motion(0, 0, 0, 0, 0, 700);  // beyond full scale: clamped to 1.5 rad/s about spacenavd's +rz
    DeviceState s;
    for (int i = 0; i < 100; ++i) s = r.read();
    EXPECT_NEAR(glm::angle(s.pose.orientation), 0.15, 1e-9);
    // spacenavd's +rz is the right-handed frame's -z (libspnav src/util.c, spnav_posrot_moveobj negates rz).
    EXPECT_NEAR(glm::axis(s.pose.orientation).z, -1.0, 1e-9);
    EXPECT_EQ(s.pose.position, Vec3(0.0));
}

TEST(SpaceMouseDevice, TheTipStaysInTheWorkspace) {
    Rig r;
    r.daemon.motion(350, 350, -350, 0, 0, 0);  // spacenavd's -z: toward the viewer, +z in the device frame
    DeviceState s;
    for (int i = 0; i < 2000; ++i) s = r.read();  // 0.2 m of travel asked for
    const Aabb ws = DeviceProfile::phantom_omni().workspace_m;
    EXPECT_EQ(s.pose.position, Vec3(ws.hi.x, ws.hi.y, ws.hi.z));
    EXPECT_EQ(s.velocity_m_s, Vec3(0.0));
}

TEST(SpaceMouseDevice, ButtonsMapToButtonBits) {
    Rig r;
    r.daemon.button(0, true);
    EXPECT_EQ(r.read().buttons, 1u);  // button 0: the stylus button
    r.daemon.button(1, true);
    EXPECT_EQ(r.read().buttons, 3u);
    r.daemon.button(0, false);
    EXPECT_EQ(r.read().buttons, 2u);
}

// spacenavd numbers up to 64 buttons (MAX_BUTTONS, src/cfgfile.h; spnavrc's bnmapN = M may send any of them). Every
// one is kept: the low 32 in DeviceState::buttons, all of them in all_buttons().
TEST(SpaceMouseDevice, ButtonsAbove31AreKept) {
    Rig r;
    r.daemon.button(40, true);
    r.daemon.button(63, true);
    r.daemon.button(2, true);
    DeviceState s = r.read();
    EXPECT_EQ(r.dev.all_buttons(), (std::uint64_t{1} << 40) | (std::uint64_t{1} << 63) | 4u);
    EXPECT_EQ(s.buttons, 4u);
    r.daemon.button(40, false);
    s = r.read();
    EXPECT_EQ(r.dev.all_buttons(), (std::uint64_t{1} << 63) | 4u);
    EXPECT_EQ(r.dev.link_stats().malformed_frames, 0u);
}

TEST(SpaceMouseDevice, GarbageIsDroppedAndSplitPacketsJoin) {
    Rig r;
    r.daemon.send_packet({99, 1, 2, 3, 4, 5, 6, 7});                  // no such event type
    r.daemon.send_packet({0, 1000000, 0, 0, 0, 0, 0, 8});             // an impossible deflection
    r.daemon.send_packet({1, 64, 1, 0, 0, 0, 0, 0});                  // no such button (spacenavd has 0..63)
    r.daemon.send_packet({3, 0, 1, 0x200, 0x46d, 0xc626, 0, 0});      // a device event: valid, ignored
    DeviceState s = r.read();
    EXPECT_EQ(s.pose.position, Vec3(0.0));
    EXPECT_EQ(s.buttons, 0u);
    EXPECT_EQ(r.dev.link_stats().malformed_frames, 3u);
    const std::array<std::int32_t, 8> m{0, 350, 0, 0, 0, 0, 0, 8};
    r.daemon.send_bytes(m.data(), 13);  // half a packet: nothing yet
    EXPECT_EQ(r.read().pose.position, Vec3(0.0));
    r.daemon.send_bytes(reinterpret_cast<const unsigned char*>(m.data()) + 13, sizeof m - 13);
    EXPECT_NEAR(r.read().pose.position.x, 1e-4, 1e-12);
    EXPECT_EQ(r.dev.link_stats().malformed_frames, 3u);
}

TEST(SpaceMouseDevice, AVanishedDaemonRaisesTheFaultAndHoldsThePose) {
    Rig r;
    r.daemon.motion(350, 0, 0, 0, 0, 0);
    r.daemon.button(0, true);
    const DeviceState before = r.read();
    const std::array<std::int32_t, 8> m{0, -350, 0, 0, 0, 0, 0, 8};
    r.daemon.send_bytes(m.data(), 9);  // a partial packet, then the daemon dies
    r.daemon.close_client();
    DeviceState s = r.read();
    EXPECT_NE(r.dev.status().faults & kFaultVanished, 0u);
    EXPECT_EQ(s.pose.position, before.pose.position);
    EXPECT_EQ(s.buttons, 0u);
    for (int i = 0; i < 5; ++i) s = r.read();
    EXPECT_EQ(s.pose.position, before.pose.position);
    EXPECT_EQ(s.velocity_m_s, Vec3(0.0));
    EXPECT_EQ(r.dev.link_stats().missed_frames, 6u);
}

TEST(SpaceMouseDevice, ForcesAreBoundedAndIgnored) {
    Rig r;
    r.dev.write(Vec3(100.0, 0.0, 0.0), Vec3(0.0));
    r.dev.write(Vec3(std::nan("")), Vec3(0.0));
    EXPECT_EQ(r.dev.status().writes_clamped, 2u);
    EXPECT_EQ(r.read().pose.position, Vec3(0.0));
}

TEST(SpaceMouseDevice, TheRegistryDriverUsesTheSerialAsSocketPath) {
    bool listed = false;
    for (const DriverInfo& d : builtin_registry().drivers()) listed = listed || d.name == "spacemouse";
    EXPECT_TRUE(listed);
    SpnavStandIn daemon;
    DeviceSpec spec;
    spec.driver = "spacemouse";
    spec.serial = daemon.path();
    auto dev = builtin_registry().create(spec, DeviceInputs{});
    dev->bring_up();
    daemon.wait_client();
    daemon.motion(0, 0, 350, 0, 0, 0);  // pushing the cap away from the user: spacenavd's +z, into the screen
    DeviceState s;
    ASSERT_TRUE(dev->read(s));
    EXPECT_NEAR(s.pose.position.z, -1e-4, 1e-12);  // the right-handed device frame's -z
    EXPECT_EQ(dev->profile().name, "spacemouse (" + DeviceProfile::phantom_omni().name + " limits)");
}

// The socket as libspnav finds it: the scene's serial, else $SPNAV_SOCKET, else /etc/spnavrc's `socket = PATH`,
// else spacenavd's default.
TEST(SpaceMouseDevice, TheSocketPathFollowsLibspnavsOrderAndReadsSpnavrc) {
    const std::string rc = ::testing::TempDir() + "/tridex_spnavrc";
    {
        std::ofstream out(rc);
        out << "# spacenavd configuration\n\nsensitivity = 2.0\nsocketx = /nope\n   socket =  /run/user/spnav.sock  \n"
               "socket = /second\n";
    }
    EXPECT_EQ(spnav_socket_from_config(rc), "/run/user/spnav.sock");
    EXPECT_EQ(spnav_socket_path("", "", rc), "/run/user/spnav.sock");
    EXPECT_EQ(spnav_socket_path("", "/env.sock", rc), "/env.sock");
    EXPECT_EQ(spnav_socket_path("/serial.sock", "/env.sock", rc), "/serial.sock");
    {
        std::ofstream out(rc);
        out << "# socket = /commented\nsocket =\n";
    }
    EXPECT_EQ(spnav_socket_from_config(rc), "");
    EXPECT_EQ(spnav_socket_path("", "", rc), kSpnavDefaultSocket);
    EXPECT_EQ(spnav_socket_path("", "", rc + ".absent"), kSpnavDefaultSocket);
    std::remove(rc.c_str());
}

// A spnavrc that moves the socket: the driver connects to the daemon listening there and reads its events.
TEST(SpaceMouseDevice, TheSocketSetInSpnavrcIsWhereTheDriverConnects) {
    SpnavStandIn daemon;
    const std::string rc = ::testing::TempDir() + "/tridex_spnavrc_live";
    std::ofstream(rc) << "# moved by the user\nsocket = " << daemon.path() << "\n";
    SpaceMouseDevice dev(DeviceProfile::phantom_omni(), Vec3(0.0), 1e-3, params_at(spnav_socket_path("", "", rc)));
    dev.bring_up();
    daemon.wait_client();
    daemon.motion(0, 350, 0, 0, 0, 0);
    DeviceState s;
    ASSERT_TRUE(dev.read(s));
    EXPECT_NEAR(s.pose.position.y, 1e-4, 1e-12);
    std::remove(rc.c_str());
}

}  // namespace
}  // namespace tridex::devices
