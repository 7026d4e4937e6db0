// The loop with the pie menu open: no carving, the detent added to the contact force (through the same filter and
// safety), and carving back on closing without a sweep bridging the time the menu was open.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "haptics/haptic_loop.hpp"
#include "haptics/menu_detent.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

std::vector<ToolSample> drain(SpscRing<ToolSample>& ring) {
    std::vector<ToolSample> s;
    ToolSample x;
    while (ring.try_pop(x)) s.push_back(x);
    return s;
}

// Unfiltered, no ramp, fixed mapping: the force sent is the world force itself (up to the clamps).
HapticLoopConfig config() {
    HapticLoopConfig cfg;
    cfg.contact = ContactParams{700.0, 0.0, 0.002};
    cfg.op = ToolOp::kSubtract;
    cfg.ewma_alpha = 0.0;
    cfg.safety.ramp_s = 0.0;
    cfg.workspace.mode = WorkspaceMode::kScaling;  // no stylus-button semantics in the way
    cfg.request_realtime = false;
    cfg.max_ticks = 200;
    return cfg;
}

// A horizontal ring (right = +x, up = +y) around (15, 15) mm, at the height of the plane's surface (z = 10 mm).
MenuDetent ring_menu() {
    MenuDetent m;
    m.open = true;
    m.centre_m = Vec3(0.015, 0.015, 0.010);
    m.slices = 8;
    m.dead_radius_m = 0.004;
    m.amplitude_n = 0.3;  // 0.3 * 8 / 0.004 = 600 N/m, under the Omni's 700
    return m;
}

// The HIP on a circle of 10 mm around the ring's centre at angle theta, `depth_m` into the plane (tool radius 2 mm).
Vec3 hand(double theta, double depth_m) {
    return Vec3(0.015 + 0.01 * std::cos(theta), 0.015 + 0.01 * std::sin(theta), 0.012 - depth_m);
}

TEST(LoopMenu, OpenMenuStopsCarvingAndAddsTheDetentToTheContactForce) {
    auto plane = test::z_plane(1e-3, 10.0f);
    TripleBuffer<ActiveSurface> surface_a, surface_b;
    test::publish(surface_a, *plane);
    test::publish(surface_b, *plane);
    SpscRing<ToolSample> ring_a(1024), ring_b(1024);
    test::PoseDevice dev_a(devices::DeviceProfile::phantom_omni()), dev_b(devices::DeviceProfile::phantom_omni());
    HapticLoop closed(dev_a, surface_a, ring_a, config());
    HapticLoop open(dev_b, surface_b, ring_b, config());
    const MenuDetent m = ring_menu();
    open.set_menu(m);
    int felt = 0;
    for (int t = 0; t < 60; ++t) {
        // Down onto the surface, then 0.5 mm into it, sweeping half a turn across several slice borders.
        const Vec3 p = hand(0.05 * t, t < 5 ? -0.001 : 0.0005);
        dev_a.state.pose.position = p;
        dev_b.state.pose.position = p;
        const TickRecord a = closed.step(t * 1e-3);
        const TickRecord b = open.step(t * 1e-3);
        EXPECT_FALSE(a.menu_open);
        EXPECT_TRUE(b.menu_open);
        EXPECT_TRUE(open.latest_view().menu_open);
        EXPECT_FALSE(closed.latest_view().menu_open);
        ASSERT_EQ(a.contact, t >= 5) << t;
        ASSERT_EQ(b.contact, t >= 5) << t;  // the workpiece is still felt
        ASSERT_EQ(a.force_enabled, b.force_enabled) << t;
        if (!b.force_enabled) continue;
        const Vec3 detent = menu_detent_force(m, b.hip_m);
        EXPECT_NEAR(glm::length(b.force_n - a.force_n - detent), 0.0, 1e-9) << t;
        EXPECT_NEAR(b.force_n.z, a.force_n.z, 1e-12) << t;  // the contact's push out of the surface is unchanged
        if (t >= 5) {
            EXPECT_GT(b.force_n.z, 0.2) << t;
        }
        if (glm::length(detent) > 0.05) ++felt;
    }
    EXPECT_GT(felt, 20);
    const std::vector<ToolSample> sa = drain(ring_a), sb = drain(ring_b);
    ASSERT_EQ(sa.size(), 60u);
    ASSERT_EQ(sb.size(), 60u);
    for (const ToolSample& s : sa) EXPECT_EQ(s.op, ToolOp::kSubtract);
    for (const ToolSample& s : sb) EXPECT_EQ(s.op, ToolOp::kNone);
}

TEST(LoopMenu, TheDetentIsBoundedByTheDeviceForceLimit) {
    auto plane = test::z_plane(1e-3, 10.0f);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *plane);
    SpscRing<ToolSample> ring(1024);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoop loop(dev, surface, ring, config());
    MenuDetent m;
    m.open = true;
    m.centre_m = Vec3(0.015, 0.015, 0.05);
    m.slices = 1;
    m.dead_radius_m = 0.05;
    m.amplitude_n = 5.0;  // 100 N/m: passive, but far beyond the Omni's 0.88 N
    loop.set_menu(m);
    dev.state.pose.position = m.centre_m + Vec3(0.15, 0.0, 0.0);  // 3 o'clock: midway for one slice at 12
    for (int t = 0; t < 10; ++t) {
        const TickRecord r = loop.step(t * 1e-3);
        EXPECT_NEAR(glm::length(menu_detent_force(m, r.hip_m)), 5.0, 1e-9);
        EXPECT_LE(glm::length(r.force_n), dev.profile().max_force_n * (1.0 + 1e-12)) << t;
        if (r.force_enabled) {
            EXPECT_GT(r.force_n.y, 0.5) << t;  // toward 12 o'clock
        }
    }
}

TEST(LoopMenu, CarvingResumesOnCloseWithoutASweepFromWhereTheMenuOpened) {
    auto plane = test::z_plane(1e-3, 10.0f);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *plane);
    SpscRing<ToolSample> ring(1024);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoop loop(dev, surface, ring, config());
    MenuDetent m = ring_menu();
    const Vec3 before(0.015, 0.015, 0.0115), after(0.045, 0.015, 0.0115);  // 30 mm apart
    int t = 0;
    dev.state.pose.position = before;
    for (; t < 10; ++t) loop.step(t * 1e-3);
    loop.set_menu(m);
    for (; t < 30; ++t) {  // the hand moves away while the menu is open
        dev.state.pose.position = before + (after - before) * ((t - 9) / 20.0);
        loop.step(t * 1e-3);
    }
    m.open = false;
    loop.set_menu(m);
    for (; t < 40; ++t) EXPECT_FALSE(loop.step(t * 1e-3).menu_open);
    const std::vector<ToolSample> s = drain(ring);
    ASSERT_EQ(s.size(), 40u);
    for (int k = 0; k < 10; ++k) EXPECT_EQ(s[k].op, ToolOp::kSubtract) << k;
    for (int k = 10; k < 30; ++k) EXPECT_EQ(s[k].op, ToolOp::kNone) << k;
    for (int k = 30; k < 40; ++k) EXPECT_EQ(s[k].op, ToolOp::kSubtract) << k;  // from the first tick after closing
    // The sweep ending at the first carving sample starts at the sample before it (the sculpt thread's rule), the
    // menu's last, where the hand already was, not where it was when the menu opened.
    EXPECT_LT(glm::length(s[30].position - s[29].position), 1e-9);
    EXPECT_GT(glm::length(s[29].position - before), 0.029);
}

TEST(LoopMenu, ADroppedLastMenuSampleKeepsTheFirstSampleAfterClosingFromCarving) {
    auto plane = test::z_plane(1e-3, 10.0f);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *plane);
    SpscRing<ToolSample> ring(16);  // the sculpt thread stalls while the menu is open
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoop loop(dev, surface, ring, config());
    MenuDetent m = ring_menu();
    const Vec3 before(0.015, 0.015, 0.0115), after(0.045, 0.015, 0.0115);
    int t = 0;
    dev.state.pose.position = before;
    for (; t < 5; ++t) loop.step(t * 1e-3);
    ASSERT_EQ(drain(ring).size(), 5u);
    loop.set_menu(m);
    for (; t < 40; ++t) {  // the hand moves away: the first 16 samples pushed (near `before`), the rest dropped
        dev.state.pose.position = before + (after - before) * ((t - 4) / 35.0);
        loop.step(t * 1e-3);
    }
    EXPECT_EQ(loop.stats().samples_dropped, 35u - ring.capacity());
    std::vector<ToolSample> s = drain(ring);  // the sculpt thread catches up
    ASSERT_EQ(s.size(), ring.capacity());
    const Vec3 last_got = s.back().position;
    m.open = false;
    loop.set_menu(m);
    loop.step(t++ * 1e-3);  // pushed, but the menu's last samples never reached the sculpt thread
    loop.step(t++ * 1e-3);
    s = drain(ring);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s[0].op, ToolOp::kNone);  // would have swept from last_got
    EXPECT_EQ(s[1].op, ToolOp::kSubtract);
    EXPECT_GT(glm::length(s[0].position - last_got), 0.015);
}

TEST(LoopMenu, AMenuStifferThanTheDeviceAllowsIsRefusedAndAClosedOneAlwaysTaken) {
    auto plane = test::z_plane(1e-3, 10.0f);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *plane);
    SpscRing<ToolSample> ring(64);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoop loop(dev, surface, ring, config());
    MenuDetent m = ring_menu();
    m.slices = 16;  // 0.3 * 16 / 0.004 = 1200 N/m > 700 N/m
    EXPECT_THROW(loop.set_menu(m), Error);
    MenuDetent bad = m;
    bad.slices = 0;
    EXPECT_THROW(loop.set_menu(bad), Error);
    dev.state.pose.position = Vec3(0.015, 0.015, 0.0115);
    EXPECT_FALSE(loop.step(0.0).menu_open);  // nothing was published
    m.open = false;
    EXPECT_NO_THROW(loop.set_menu(m));
    bad.open = false;
    EXPECT_NO_THROW(loop.set_menu(bad));
    EXPECT_FALSE(loop.step(1e-3).menu_open);
    const std::vector<ToolSample> s = drain(ring);
    ASSERT_EQ(s.size(), 2u);
    for (const ToolSample& x : s) EXPECT_EQ(x.op, ToolOp::kSubtract);
}

TEST(LoopMenu, TheRenderThreadOpensAndClosesTheMenuWhileTheLoopRuns) {
    devices::SimulatedDevice dev(devices::DeviceProfile::phantom_omni(),
                                 devices::ScriptedPath::hold(Vec3(0.025, 0.015, 0.03)));
    TripleBuffer<ActiveSurface> surface;  // nothing published: free space
    SpscRing<ToolSample> ring(4096);
    HapticLoopConfig cfg = config();
    cfg.max_ticks = 4000;
    HapticLoop loop(dev, surface, ring, cfg);
    MenuDetent m = ring_menu();
    m.centre_m = Vec3(0.015, 0.015, 0.03);
    loop.start();
    int views_open = 0;
    for (int i = 0; i < 40; ++i) {  // this thread is the render thread: the one writer and the one view reader
        m.open = i % 2 == 0;
        loop.set_menu(m);
        std::this_thread::sleep_for(std::chrono::milliseconds(3));
        views_open += loop.latest_view().menu_open ? 1 : 0;
    }
    loop.stop();
    const std::vector<TickRecord>& recs = loop.records();
    const std::vector<ToolSample> s = drain(ring);
    ASSERT_EQ(loop.stats().samples_dropped, 0u);
    ASSERT_EQ(s.size(), recs.size());
    std::size_t open_ticks = 0;
    for (std::size_t i = 0; i < recs.size(); ++i) {
        if (!recs[i].menu_open) continue;
        ++open_ticks;
        EXPECT_EQ(s[i].op, ToolOp::kNone) << i;
    }
    EXPECT_GT(open_ticks, 0u);
    EXPECT_LT(open_ticks, recs.size());
    EXPECT_GT(views_open, 0);
}

}  // namespace
}  // namespace tridex::haptics
