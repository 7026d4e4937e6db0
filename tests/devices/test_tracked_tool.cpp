// Tests of devices/tracking/tracked_tool_device over loopback UDP: a Flystick's calibrated pose reaches the stylus
// as a speed-limited glide, its trigger engages the tool, an untracked or stale Flystick disengages it and holds
// the pose, a standard body is always engaged while tracked, and the view and device readers of one receiver read
// the same datagrams independently (run under ThreadSanitizer with the devices tests).
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"
#include "devices/tracking/tracked_tool_device.hpp"
#include "dtrack_sender.hpp"

namespace tridex::devices {
namespace {

using test::dtrack_datagram;
using test::dtrack_flystick_datagram;
using test::DTrackSender;

constexpr double kDt = 1e-3;

/// Reads the device until `done(state)` holds (up to 5 s of wall time); the last state read.
template <class Done>
DeviceState read_until(TrackedToolDevice& dev, Done done) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    DeviceState s;
    for (;;) {
        EXPECT_TRUE(dev.read(s));
        if (done(s) || std::chrono::steady_clock::now() > until) return s;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
}

std::shared_ptr<DTrackReceiver> loopback() { return std::make_shared<DTrackReceiver>(0, "127.0.0.1"); }

TEST(TrackedTool, FlystickPoseThroughTheCalibrationWithTheTriggerEngaging) {
    auto rx = loopback();
    TrackedToolParams p;
    p.id = 1;
    p.tracker_to_device.position = Vec3(0.0, -1.0, 0.0);  // tracker origin 1 m above the wall frame's
    p.timeout_s = 5.0;  // the glide below takes about a second of reads on a loaded machine
    TrackedToolDevice dev(tracked_tool_profile(), rx, p, kDt);
    dev.open();
    dev.home();
    DTrackSender tx(rx->port());
    // Before any sample: at rest at the workspace centre, disengaged.
    DeviceState s;
    ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.buttons, 0u);
    EXPECT_NEAR(glm::length(s.pose.position - tracked_tool_profile().workspace_m.centre()), 0.0, 1e-12);
    // Flystick 1 at (100, 1500, 800) mm with the trigger held: acquired by a jump there, at rest and disengaged
    // for that read; engaged on the next.
    ASSERT_TRUE(tx.send(dtrack_flystick_datagram(1, 1, Vec3(100.0, 1500.0, 800.0), glm::dmat3(1.0), 0x1, 0.0, 0.0)));
    const Vec3 start(0.1, 0.5, 0.8);
    DeviceState first = read_until(dev, [&](const DeviceState& st) { return glm::length(st.pose.position - start) < 1e-12; });
    EXPECT_EQ(first.buttons, 0u);
    EXPECT_EQ(glm::length(first.velocity_m_s), 0.0);
    ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.buttons, tracked_tool_buttons::kEngage);
    // Moved 0.3 m: the stylus glides there at most 1 m/s (1 mm per read).
    ASSERT_TRUE(tx.send(dtrack_flystick_datagram(2, 1, Vec3(400.0, 1500.0, 800.0), glm::dmat3(1.0), 0x1, 0.0, 0.0)));
    const Vec3 target(0.4, 0.5, 0.8);
    s = read_until(dev, [&](const DeviceState& st) { return st.pose.position.x > 0.1 + 1e-9; });
    EXPECT_LE(glm::length(s.velocity_m_s), 1.0 + 1e-9);
    EXPECT_GT(glm::length(s.velocity_m_s), 0.5);
    EXPECT_LE(s.pose.position.x, 0.1 + 1e-3 + 1e-9);
    s = read_until(dev, [&](const DeviceState& st) { return glm::length(st.pose.position - target) < 1e-12; });
    EXPECT_NEAR(glm::length(s.pose.position - target), 0.0, 1e-12);
    // Trigger released: still tracked, not engaged; button 2 becomes bit 3.
    ASSERT_TRUE(tx.send(dtrack_flystick_datagram(3, 1, Vec3(400.0, 1500.0, 800.0), glm::dmat3(1.0), 0x4, 0.0, 0.0)));
    s = read_until(dev, [](const DeviceState& st) { return st.buttons != tracked_tool_buttons::kEngage; });
    EXPECT_EQ(s.buttons, 1u << 3);
    // Untracked (quality -1) at another place: the pose holds, the tool disengages, the read counts as missed.
    const std::uint64_t missed = dev.link_stats().missed_frames;
    ASSERT_TRUE(tx.send(dtrack_flystick_datagram(4, 1, Vec3(900.0, 1500.0, 800.0), glm::dmat3(1.0), 0x1, 0.0, 0.0,
                                                 false)));
    s = read_until(dev, [&](const DeviceState& st) { return st.buttons == 0 && dev.link_stats().missed_frames > missed; });
    EXPECT_EQ(s.buttons, 0u);
    EXPECT_NEAR(glm::length(s.pose.position - target), 0.0, 1e-12);
    EXPECT_EQ(glm::length(s.velocity_m_s), 0.0);
}

TEST(TrackedTool, AStaleFlystickDisengagesAndABodyIsAlwaysEngaged) {
    auto rx = loopback();
    DTrackSender tx(rx->port());
    TrackedToolParams fp;
    fp.timeout_s = 0.05;
    TrackedToolDevice fly(tracked_tool_profile(), rx, fp, kDt);
    TrackedToolParams bp;
    bp.flystick = false;
    bp.id = 3;
    bp.timeout_s = 0.05;
    TrackedToolDevice body(tracked_tool_profile(), rx, bp, kDt);  // reads the same kDevice reader, one at a time
    for (TrackedToolDevice* d : {&fly, &body}) {
        d->open();
        d->home();
    }
    ASSERT_TRUE(tx.send(dtrack_flystick_datagram(1, 0, Vec3(0.0, 1000.0, 500.0), glm::dmat3(1.0), 0x1, 0.0, 0.0)));
    DeviceState s = read_until(fly, [](const DeviceState& st) { return st.buttons != 0; });
    EXPECT_EQ(s.buttons, tracked_tool_buttons::kEngage);
    // No datagram for longer than the timeout: stale, disengaged.
    s = read_until(fly, [](const DeviceState& st) { return st.buttons == 0; });
    EXPECT_EQ(s.buttons, 0u);
    EXPECT_GT(fly.link_stats().missed_frames, 0u);
    // A standard body has no buttons: engaged whenever it is tracked and fresh.
    ASSERT_TRUE(tx.send(dtrack_datagram(2, 3, Vec3(0.0, 1000.0, 500.0), glm::dmat3(1.0))));
    s = read_until(body, [](const DeviceState& st) { return st.buttons != 0; });
    EXPECT_EQ(s.buttons, tracked_tool_buttons::kEngage);
}

TEST(TrackedTool, ViewAndDeviceReadersSeeTheSameDatagrams) {
    DTrackReceiver rx(0, "127.0.0.1");
    DTrackSender tx(rx.port());
    ASSERT_TRUE(tx.send(dtrack_datagram(5, 0, Vec3(10.0, 20.0, 30.0), glm::dmat3(1.0))));
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (rx.latest(DTrackReader::kDevice).accepted < 1 && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    EXPECT_EQ(rx.latest(DTrackReader::kDevice).bodies[0].frame_counter, 5u);
    EXPECT_EQ(rx.latest(DTrackReader::kView).bodies[0].frame_counter, 5u);  // not taken by the other reader
}

TEST(TrackedTool, ButtonBitsAndBadParameters) {
    EXPECT_EQ(tracked_tool_button_bits(0x1), tracked_tool_buttons::kEngage);
    EXPECT_EQ(tracked_tool_button_bits(0x6), (1u << 2) | (1u << 3));
    EXPECT_EQ(tracked_tool_button_bits(0x0) & 1u, 0u);  // never the workspace techniques' stylus bit
    auto rx = std::make_shared<DTrackReceiver>(0, "127.0.0.1");
    TrackedToolParams p;
    p.id = kDTrackKeptFlysticks;
    EXPECT_THROW(TrackedToolDevice(tracked_tool_profile(), rx, p, kDt), Error);
    p.id = 0;
    p.timeout_s = 0.0;
    EXPECT_THROW(TrackedToolDevice(tracked_tool_profile(), rx, p, kDt), Error);
    p.timeout_s = 0.1;
    EXPECT_THROW(TrackedToolDevice(tracked_tool_profile(), nullptr, p, kDt), Error);
    EXPECT_THROW(TrackedToolDevice(tracked_tool_profile(), rx, p, 0.0), Error);
}

}  // namespace
}  // namespace tridex::devices
