// Tests of devices/simulated_device and the device profile: the hand follows its path, written forces
// act on the mass, injected faults fire exactly when asked, bad parameters are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "core/units.hpp"
#include "devices/simulated_device.hpp"

namespace tridex::devices {
namespace {

TEST(DeviceProfile, PhantomOmniNumbers) {
    const DeviceProfile p = DeviceProfile::phantom_omni();
    EXPECT_EQ(p.name, "PHANTOM Omni");
    const Vec3 size = p.workspace_m.size();
    EXPECT_NEAR(size.x, 6.4 * 0.0254, 1e-15);
    EXPECT_NEAR(size.y, 4.8 * 0.0254, 1e-15);
    EXPECT_NEAR(size.z, 2.8 * 0.0254, 1e-15);
    EXPECT_NEAR(glm::length(p.workspace_m.centre()), 0.0, 1e-15);
    EXPECT_DOUBLE_EQ(p.max_force_n, 0.88);
    EXPECT_DOUBLE_EQ(p.max_torque_nm, 0.0);
    EXPECT_DOUBLE_EQ(p.max_stiffness_n_per_m, 700.0);
    EXPECT_EQ(p.dof_in, 6);
    EXPECT_EQ(p.dof_out, 3);
}

// A straight line at constant speed v (m/s) along x, waypoints every 0.1 s for 1 s.
ScriptedPath line(double v) {
    std::vector<double> t;
    std::vector<Vec3> p;
    for (int i = 0; i <= 10; ++i) {
        t.push_back(0.1 * i);
        p.push_back(Vec3(v * 0.1 * i, 0.0, 0.0));
    }
    return ScriptedPath(t, p);
}

TEST(SimulatedDevice, FreeHandFollowsThePath) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), line(0.1));
    dev.bring_up();  // forces pass only while enabled
    DeviceState s;
    double max_err_steady = 0.0, max_err_all = 0.0;
    for (int i = 0; i < 1000; ++i) {
        ASSERT_TRUE(dev.read(s));
        EXPECT_DOUBLE_EQ(s.t_s, (i + 1) * 1e-3);
        const double err = glm::length(s.pose.position - dev.path().position_at(s.t_s));
        max_err_all = std::max(max_err_all, err);
        // Steady speed from 0.1 s to 0.9 s; allow 0.3 s (12 time constants 2m/b = 25 ms) to settle.
        if (s.t_s >= 0.4 && s.t_s <= 0.9) {
            max_err_steady = std::max(max_err_steady, err);
            EXPECT_NEAR(s.velocity_m_s.x, 0.1, 1e-6);
        }
    }
    std::printf("free hand: max tracking error %.3g m overall, %.3g m at steady speed\n", max_err_all, max_err_steady);
    // The spring-damper on position and velocity error tracks a ramp with zero steady-state error;
    // what remains is the decayed start-up transient (about 0.3 mm * e^-12).
    EXPECT_LT(max_err_steady, 1e-6);
    EXPECT_LT(max_err_all, 1e-3);  // the start-up lag stays below 1 mm
}

TEST(SimulatedDevice, WrittenForceDisplacesTheHandSpring) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    dev.bring_up();  // forces pass only while enabled
    dev.write(Vec3(0.0, 0.0, 0.3), Vec3(0.0));
    DeviceState s;
    for (int i = 0; i < 2000; ++i) ASSERT_TRUE(dev.read(s));
    // Equilibrium k_h * x = F: x = 0.3 N / 300 N/m = 1 mm; the transient (e^-t/25ms) is gone after 2 s.
    EXPECT_NEAR(s.pose.position.z, 1e-3, 1e-12);
    EXPECT_NEAR(s.pose.position.x, 0.0, 1e-15);
    EXPECT_NEAR(s.velocity_m_s.z, 0.0, 1e-12);
    EXPECT_EQ(dev.writes(), 1u);
}

TEST(SimulatedDevice, FirstStepIsSemiImplicitEuler) {
    SimulatedHandParams hand;  // m = 0.05 kg, k = 300 N/m, b = 4 N*s/m
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.01, 0.0, 0.0)), hand, 1e-3);
    dev.bring_up();  // forces pass only while enabled
    // Starts at rest on the path (x = 0.01); push with 0.5 N along -y.
    dev.write(Vec3(0.0, -0.5, 0.0), Vec3(0.0));
    DeviceState s;
    ASSERT_TRUE(dev.read(s));
    // v1 = dt/m * F = 1e-3 / 0.05 * (-0.5) = -0.01 m/s; x1 = x0 + dt * v1.
    EXPECT_DOUBLE_EQ(s.velocity_m_s.y, -0.01);
    EXPECT_DOUBLE_EQ(s.pose.position.y, -1e-5);
    EXPECT_DOUBLE_EQ(s.pose.position.x, 0.01);
    ASSERT_TRUE(dev.read(s));
    // a1 = (k * (0 - x1) + b * (0 - v1) + F) / m, v2 = v1 + dt * a1.
    const double a1 = (300.0 * 1e-5 + 4.0 * 0.01 - 0.5) / 0.05;
    EXPECT_NEAR(s.velocity_m_s.y, -0.01 + 1e-3 * a1, 1e-15);
}

TEST(SimulatedDevice, SubstepsIntegrateTheHeldForceAndDeviceDampingBrakes) {
    // Free mass (no hand), 0.5 N held for one 1 ms read in 4 sub-steps: v = F*dt/m exactly, and
    // x = h^2 * F/m * (1 + 2 + 3 + 4) = 10 h^2 a (semi-implicit Euler per sub-step).
    SimulatedHandParams hand{0.05, 0.0, 0.0, 0.0, 4};
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)), hand, 1e-3);
    dev.bring_up();  // forces pass only while enabled
    dev.write(Vec3(0.5, 0.0, 0.0), Vec3(0.0));
    DeviceState s;
    ASSERT_TRUE(dev.read(s));
    const double a = 0.5 / 0.05, h = 0.25e-3;
    EXPECT_NEAR(s.velocity_m_s.x, a * 1e-3, 1e-15);
    EXPECT_NEAR(s.pose.position.x, 10.0 * h * h * a, 1e-15);
    EXPECT_EQ(s.t_s, 1e-3);
    // Device damping to the ground: a coasting mass slows as exp(-b t / m) (b = 0.1, m = 0.05: e^-2 at 1 s).
    SimulatedHandParams coast{0.05, 0.0, 0.0, 0.1, 20};
    SimulatedDevice d2(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)), coast, 1e-3);
    d2.bring_up();  // forces pass only while enabled
    d2.write(Vec3(0.05, 0.0, 0.0), Vec3(0.0));  // 1 ms push: v = 1e-3 m/s
    ASSERT_TRUE(d2.read(s));
    d2.write(Vec3(0.0), Vec3(0.0));
    const double v0 = s.velocity_m_s.x;
    for (int i = 0; i < 1000; ++i) ASSERT_TRUE(d2.read(s));
    EXPECT_NEAR(s.velocity_m_s.x / v0, std::exp(-2.0), 2e-4);
    EXPECT_NEAR(d2.energy_j(), 0.5 * 0.05 * s.velocity_m_s.x * s.velocity_m_s.x, 1e-18);
}

TEST(SimulatedDevice, TraceRecordsStepsUpToItsCapacity) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    dev.bring_up();  // forces pass only while enabled
    dev.enable_trace(10);
    dev.write(Vec3(0.1, 0.0, 0.0), Vec3(0.0));
    DeviceState s;
    for (int i = 0; i < 20; ++i) ASSERT_TRUE(dev.read(s));
    ASSERT_EQ(dev.trace().size(), 10u);
    EXPECT_EQ(dev.trace()[9].device_force_n, Vec3(0.1, 0.0, 0.0));
    EXPECT_DOUBLE_EQ(dev.trace()[9].t_s, 0.010);
    EXPECT_EQ(dev.steps(), 20u);
}

TEST(SimulatedDevice, VanishFaultFiresAfterNReads) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    dev.bring_up();  // forces pass only while enabled
    SimulatedFaults f;
    f.vanish_after_reads = 5;
    dev.set_faults(f);
    DeviceState s;
    for (int i = 0; i < 5; ++i) EXPECT_TRUE(dev.read(s)) << i;
    EXPECT_FALSE(dev.read(s));
    EXPECT_FALSE(dev.read(s));  // stays gone
    EXPECT_EQ(dev.steps(), 5u);
    EXPECT_EQ(dev.reads(), 7u);
}

TEST(SimulatedDevice, NanFaultHitsExactlyTheRequestedReads) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), line(0.1));
    dev.bring_up();  // forces pass only while enabled
    SimulatedFaults f;
    f.nan_first_read = 3;
    f.nan_count = 2;
    dev.set_faults(f);
    DeviceState s;
    for (int i = 1; i <= 6; ++i) {
        ASSERT_TRUE(dev.read(s));
        const bool expect_nan = i == 3 || i == 4;
        EXPECT_EQ(std::isnan(s.pose.position.x), expect_nan) << "read " << i;
        EXPECT_TRUE(is_finite(dev.position_m()));  // the dynamics are untouched
    }
}

TEST(SimulatedDevice, NonFiniteWriteIsAppliedAsZero) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    dev.bring_up();  // forces pass only while enabled
    dev.write(Vec3(std::nan(""), 0.0, 0.0), Vec3(0.0));
    EXPECT_EQ(dev.last_force_n(), Vec3(0.0));  // the device seam sends a non-finite force as zero
    EXPECT_TRUE(dev.status().faults & devices::kFaultNonFinite);
    DeviceState s;
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.pose.position, Vec3(0.0));
    EXPECT_EQ(s.velocity_m_s, Vec3(0.0));
}

TEST(SimulatedDevice, ButtonsAreReported) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    dev.bring_up();  // forces pass only while enabled
    DeviceState s;
    ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.buttons, 0u);
    dev.set_buttons(0x5u);
    ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.buttons, 0x5u);
}

TEST(SimulatedDevice, RejectsBadParameters) {
    const DeviceProfile p = DeviceProfile::phantom_omni();
    const ScriptedPath path = ScriptedPath::hold(Vec3(0.0));
    EXPECT_THROW(SimulatedDevice(p, path, SimulatedHandParams{0.0, 300.0, 4.0}), Error);
    EXPECT_THROW(SimulatedDevice(p, path, SimulatedHandParams{0.05, -1.0, 4.0}), Error);
    EXPECT_THROW(SimulatedDevice(p, path, SimulatedHandParams{0.05, 300.0, std::nan("")}), Error);
    EXPECT_THROW(SimulatedDevice(p, path, SimulatedHandParams{}, 0.0), Error);
    EXPECT_THROW(SimulatedDevice(p, path, SimulatedHandParams{0.05, 300.0, 4.0, -0.1}), Error);
    EXPECT_THROW(SimulatedDevice(p, path, SimulatedHandParams{0.05, 300.0, 4.0, 0.0, 0}), Error);
    EXPECT_THROW(SimulatedDevice(p, path, SimulatedHandParams{0.05, 300.0, 4.0, 0.0, 1001}), Error);
    EXPECT_THROW(SimulatedDevice(p, path, SimulatedHandParams{}, -1e-3), Error);
    try {
        SimulatedDevice(p, path, SimulatedHandParams{-0.05, 300.0, 4.0});
        FAIL() << "no throw";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("mass_kg"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace tridex::devices
