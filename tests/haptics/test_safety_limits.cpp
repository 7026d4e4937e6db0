// Tests of haptics/safety_limits and haptics/safety: the force ramp-in, per-profile force and torque
// clamps, the velocity limit and the configuration checks, on the SafetyStage directly and through the
// loop in step() mode (deterministic device and loop clocks).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "haptics/safety.hpp"
#include "loop_fixture.hpp"

namespace tridex::haptics {
namespace {

using devices::DeviceProfile;

// A 5-DOF profile with the Quanser wand's limits (Singapogu, chapter 3): 2.1 N and 0.23 N*m are the
// smaller of its per-axis force and torque limits, used here as magnitude limits.
DeviceProfile wand_like() {
    DeviceProfile p = DeviceProfile::phantom_omni();
    p.name = "wand-like";
    p.max_force_n = 2.1;
    p.max_torque_nm = 0.23;
    return p;
}

TEST(SafetyRamp, LinearFromZeroToOne) {
    ForceRamp r(0.05);
    EXPECT_EQ(r.scale(1.0), 0.0);  // not started
    r.restart(1.0);
    EXPECT_EQ(r.scale(1.0), 0.0);
    EXPECT_NEAR(r.scale(1.0125), 0.25, 1e-12);
    EXPECT_NEAR(r.scale(1.025), 0.5, 1e-12);
    EXPECT_EQ(r.scale(1.05), 1.0);
    EXPECT_EQ(r.scale(7.0), 1.0);
    EXPECT_EQ(r.scale(0.5), 0.0);  // before the start
    EXPECT_EQ(r.scale(std::nan("")), 0.0);
    ForceRamp none(0.0);
    none.restart(2.0);
    EXPECT_EQ(none.scale(2.0), 1.0);
}

TEST(SafetyLimits, FromProfileAndChecks) {
    const SafetyLimits omni = SafetyLimits::from(DeviceProfile::phantom_omni(), SafetyConfig{});
    EXPECT_EQ(omni.max_force_n, 0.88);
    EXPECT_EQ(omni.max_torque_nm, 0.0);
    EXPECT_EQ(omni.max_velocity_m_s, 1.5);
    EXPECT_FALSE(omni.over_speed(Vec3(1.5, 0.0, 0.0)));
    EXPECT_TRUE(omni.over_speed(Vec3(1.2, 0.9, 0.1)));  // |v| = 1.503
    EXPECT_TRUE(omni.over_speed(Vec3(std::nan(""), 0.0, 0.0)));

    auto expect_error = [](const DeviceProfile& p, const SafetyConfig& c, const std::string& field) {
        try {
            SafetyLimits::from(p, c);
            ADD_FAILURE() << "no throw for " << field;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    DeviceProfile bad = DeviceProfile::phantom_omni();
    bad.max_force_n = -1.0;
    expect_error(bad, {}, "max_force_n");
    bad = DeviceProfile::phantom_omni();
    bad.max_torque_nm = std::nan("");
    expect_error(bad, {}, "max_torque_nm");
    SafetyConfig c;
    c.max_velocity_m_s = 0.0;
    expect_error(DeviceProfile::phantom_omni(), c, "SafetyConfig.max_velocity_m_s");
    c = {};
    c.ramp_s = -0.1;
    expect_error(DeviceProfile::phantom_omni(), c, "SafetyConfig.ramp_s");
    c = {};
    c.stale_timeout_s = 0.02;  // would let stale data through for more than 10 ms
    expect_error(DeviceProfile::phantom_omni(), c, "SafetyConfig.stale_timeout_s");
    c = {};
    c.stall_factor = 1.0;
    expect_error(DeviceProfile::phantom_omni(), c, "SafetyConfig.stall_factor");
    c = {};
    c.rearm_s = 5.0;
    expect_error(DeviceProfile::phantom_omni(), c, "SafetyConfig.rearm_s");
    c = {};
    c.max_passivity_damping_n_s_per_m = 0.0;
    expect_error(DeviceProfile::phantom_omni(), c, "SafetyConfig.max_passivity_damping_n_s_per_m");
}

TEST(SafetyStage, ClampsForceAndTorqueToTheProfile) {
    SafetyConfig cfg;
    cfg.ramp_s = 0.0;
    SafetyStage wand(SafetyLimits::from(wand_like(), cfg), cfg, false);
    const Vec3 x(0.0), v(0.0);
    SafetyOutput o = wand.apply(Vec3(3.0, 0.0, 4.0), Vec3(0.3, -0.4, 0.0), x, v, 0.001, 1e-3, true);
    EXPECT_TRUE(o.enabled);
    EXPECT_NEAR(glm::length(o.force_n), 2.1, 1e-12);
    EXPECT_NEAR(glm::length(o.force_n - 2.1 * Vec3(0.6, 0.0, 0.8)), 0.0, 1e-12);  // direction kept
    EXPECT_NEAR(glm::length(o.torque_nm - 0.23 * Vec3(0.6, -0.8, 0.0)), 0.0, 1e-12);
    o = wand.apply(Vec3(1.0, 0.0, 0.0), Vec3(0.1, 0.0, 0.0), x, v, 0.002, 1e-3, true);  // within limits: untouched
    EXPECT_EQ(o.force_n, Vec3(1.0, 0.0, 0.0));
    EXPECT_EQ(o.torque_nm, Vec3(0.1, 0.0, 0.0));
    // A 3-DOF device (max torque 0) never gets a torque.
    SafetyStage omni(SafetyLimits::from(DeviceProfile::phantom_omni(), cfg), cfg, false);
    o = omni.apply(Vec3(0.0, 0.0, 2.0), Vec3(0.1, 0.0, 0.0), x, v, 0.001, 1e-3, true);
    EXPECT_EQ(o.torque_nm, Vec3(0.0));
    EXPECT_NEAR(o.force_n.z, 0.88, 1e-15);
}

TEST(SafetyStage, PassivityBooksTheForceTheDeviceWasSent) {
    SafetyConfig cfg;
    cfg.ramp_s = 0.0;
    SafetyStage st(SafetyLimits::from(DeviceProfile::phantom_omni(), cfg), cfg, false);
    // Without sent(): the next tick books apply()'s force, 0.5 N over 1 mm along it: E = -0.5 mJ.
    st.apply(Vec3(0.5, 0.0, 0.0), Vec3(0.0), Vec3(0.0), Vec3(0.0), 0.001, 1e-3, true);
    st.apply(Vec3(0.0), Vec3(0.0), Vec3(0.001, 0.0, 0.0), Vec3(0.0), 0.002, 1e-3, true);
    EXPECT_NEAR(st.passivity().energy_j(), -0.5e-3, 1e-15);
    // With sent(): the device got only 0.2 N (per-axis limit), so the work is 0.2 mJ, not 0.5.
    st.reset();
    st.apply(Vec3(0.5, 0.0, 0.0), Vec3(0.0), Vec3(0.0), Vec3(0.0), 0.001, 1e-3, true);
    st.sent(Vec3(0.2, 0.0, 0.0));
    st.apply(Vec3(0.0), Vec3(0.0), Vec3(0.001, 0.0, 0.0), Vec3(0.0), 0.002, 1e-3, true);
    EXPECT_NEAR(st.passivity().energy_j(), -0.2e-3, 1e-15);
    // A non-finite report counts as zero force: no work booked.
    st.reset();
    st.apply(Vec3(0.5, 0.0, 0.0), Vec3(0.0), Vec3(0.0), Vec3(0.0), 0.001, 1e-3, true);
    st.sent(Vec3(std::nan(""), 0.0, 0.0));
    st.apply(Vec3(0.0), Vec3(0.0), Vec3(0.001, 0.0, 0.0), Vec3(0.0), 0.002, 1e-3, true);
    EXPECT_EQ(st.passivity().energy_j(), 0.0);
}

TEST(SafetyStage, VelocityLimitCutsAndTheRampRestarts) {
    SafetyConfig cfg;
    cfg.ramp_s = 0.01;
    SafetyStage st(SafetyLimits::from(DeviceProfile::phantom_omni(), cfg), cfg, false);
    const Vec3 f(0.0, 0.0, 0.5);
    double t = 0.0;
    for (int k = 0; k <= 12; ++k) st.apply(f, Vec3(0.0), Vec3(0.0), Vec3(0.0), t += 1e-3, 1e-3, true);
    EXPECT_NEAR(st.apply(f, Vec3(0.0), Vec3(0.0), Vec3(0.0), t += 1e-3, 1e-3, true).force_n.z, 0.5, 1e-15);
    // 2 m/s > 1.5 m/s: zero out, flagged.
    const SafetyOutput fast = st.apply(f, Vec3(0.0), Vec3(0.0), Vec3(0.0, 2.0, 0.0), t += 1e-3, 1e-3, true);
    EXPECT_TRUE(fast.over_speed);
    EXPECT_FALSE(fast.enabled);
    EXPECT_EQ(fast.force_n, Vec3(0.0));
    // Back under the limit: the ramp restarts at this tick (factor 0), then 0.1 per ms.
    const double t0 = t += 1e-3;
    EXPECT_EQ(st.apply(f, Vec3(0.0), Vec3(0.0), Vec3(0.0, 1.0, 0.0), t0, 1e-3, true).force_n, Vec3(0.0));
    for (int k = 1; k <= 12; ++k) {
        const SafetyOutput o = st.apply(f, Vec3(0.0), Vec3(0.0), Vec3(0.0, 1.0, 0.0), t += 1e-3, 1e-3, true);
        EXPECT_NEAR(o.ramp, std::min(1.0, (t - t0) / 0.01), 1e-9) << k;
        EXPECT_NEAR(o.force_n.z, 0.5 * o.ramp, 1e-15) << k;
    }
    // The watchdog's veto zeroes the output the same way.
    EXPECT_EQ(st.apply(f, Vec3(0.0), Vec3(0.0), Vec3(0.0), t += 1e-3, 1e-3, false).force_n, Vec3(0.0));
}

// Loop-level: a stylus held 5 mm outside the bubble feels the bubble wall, -k * 5 mm along +x, from the
// first tick: the session starts "in contact". No filter, so the force is exactly ramp * wall force.
struct BubbleScene {
    test::PoseDevice dev{DeviceProfile::phantom_omni()};
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring{4096};
    HapticLoopConfig cfg;
    double rb = 0.8 * 0.5 * 0.0254 * 2.8;  // default bubble radius of the Omni, m
    BubbleScene(double stiffness, double ramp_s) {
        cfg.workspace.mode = WorkspaceMode::kBubble;
        cfg.workspace.bubble_stiffness_n_per_m = stiffness;
        cfg.workspace.bubble_rate_m_s = 0.0;  // no drift: keep the geometry fixed
        cfg.ewma_alpha = 0.0;
        cfg.safety.ramp_s = ramp_s;
        cfg.max_ticks = 1000;
        dev.state.pose.position = Vec3(rb + 0.005, 0.0, 0.0);
    }
};

TEST(SafetyLoop, ForceRampsInWhenASessionStartsInContact) {
    BubbleScene s(100.0, 0.05);  // wall force -0.5 N x
    HapticLoop loop(s.dev, s.surface, s.ring, s.cfg);
    for (int k = 1; k <= 80; ++k) {
        const TickRecord r = loop.step(k * 1e-3);
        // Ramp from the first sample's device time (1 ms) over 50 ms.
        const double ramp = std::min(1.0, (k * 1e-3 - 1e-3) / 0.05);
        EXPECT_NEAR(r.ramp, ramp, 1e-6) << k;
        EXPECT_NEAR(glm::length(r.force_n - ramp * Vec3(-0.5, 0.0, 0.0)), 0.0, 1e-12) << k;
        EXPECT_NEAR(glm::length(s.dev.force - r.force_n), 0.0, 1e-15) << k;  // identity device_to_world
    }
    loop.stop();
    EXPECT_EQ(s.dev.force, Vec3(0.0));  // stop() of a stepped session writes zero
}

TEST(SafetyLoop, ForceClampAndVelocityLimitInTheLoop) {
    BubbleScene s(1000.0, 0.0);  // wall force 5 N: over the Omni's 0.88 N
    HapticLoop loop(s.dev, s.surface, s.ring, s.cfg);
    int k = 0;
    for (; k < 5; ++k) {
        const TickRecord r = loop.step((k + 1) * 1e-3);
        EXPECT_NEAR(glm::length(r.force_n - Vec3(-0.88, 0.0, 0.0)), 0.0, 1e-12);
        EXPECT_EQ(r.torque_nm, Vec3(0.0));
    }
    s.dev.state.velocity_m_s = Vec3(0.0, 2.0, 0.0);  // faster than 1.5 m/s
    for (; k < 8; ++k) {
        const TickRecord r = loop.step((k + 1) * 1e-3);
        EXPECT_FALSE(r.force_enabled);
        EXPECT_EQ(r.force_n, Vec3(0.0));
        EXPECT_EQ(s.dev.force, Vec3(0.0));
    }
    s.dev.state.velocity_m_s = Vec3(0.0, 1.0, 0.0);
    const TickRecord back = loop.step((k + 1) * 1e-3);
    EXPECT_TRUE(back.force_enabled);
    EXPECT_NEAR(back.force_n.x, -0.88, 1e-12);  // ramp_s = 0: full force at once
    EXPECT_EQ(loop.stats().velocity_limit_ticks, 3u);
    EXPECT_EQ(loop.stats().watchdog_trips, 0u);
}

TEST(SafetyLoop, StepRefusesWhileTheThreadRuns) {
    BubbleScene s(100.0, 0.05);
    s.cfg.request_realtime = false;
    HapticLoop loop(s.dev, s.surface, s.ring, s.cfg);
    loop.start();
    EXPECT_THROW(loop.step(1.0), Error);
    loop.stop();
    EXPECT_NO_THROW(loop.step(1.0));  // a new stepped session
    EXPECT_EQ(loop.stats().ticks, 1u);
    loop.stop();
}

}  // namespace
}  // namespace tridex::haptics
