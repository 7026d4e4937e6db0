// Tests of the simulated device's wrist: a written torque turns the stylus by tau / k_r the right way,
// a torque spring closing the loop turns it back, positions do not depend on the torque, energy stays
// bounded, non-finite torque is ignored, the hand follows an orientation path, the trace keeps it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"
#include "devices/rotation_vector.hpp"
#include "devices/simulated_device.hpp"

namespace tridex::devices {
namespace {

const Quat kIdentity(1.0, 0.0, 0.0, 0.0);

Vec3 angle_of(const SimulatedDevice& dev) { return rotation_vector(dev.orientation()); }

TEST(SimulatedWrist, ConstantTorqueAboutZTurnsToTauOverK) {
    SimulatedDevice dev(quanser_wand_5dof(), ScriptedPath::hold(Vec3(0.0, 0.21, 0.01)));
    dev.bring_up();  // forces pass only while enabled
    const double tau = 0.1, k = dev.hand().hand_torsion_stiffness_nm_per_rad;  // 0.5 N*m/rad
    dev.write(Vec3(0.0), Vec3(0.0, 0.0, tau));
    DeviceState s;
    ASSERT_TRUE(dev.read(s));
    // Right-hand rule: +tau_z starts a +z rotation.
    EXPECT_GT(dev.angular_velocity_rad_s().z, 0.0);
    EXPECT_GT(rotation_vector(s.pose.orientation).z, 0.0);
    for (int i = 1; i < 2000; ++i) ASSERT_TRUE(dev.read(s));
    // Steady state k_r theta = tau: 0.2 rad about z (transient e^{-zeta w_n t}, w_n = 70.7 rad/s, gone in 2 s).
    const Vec3 theta = rotation_vector(s.pose.orientation);
    EXPECT_NEAR(theta.z, tau / k, 1e-12);
    EXPECT_NEAR(theta.x, 0.0, 1e-15);
    EXPECT_NEAR(theta.y, 0.0, 1e-15);
    EXPECT_NEAR(glm::length(dev.angular_velocity_rad_s()), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(s.pose.orientation), 1.0, 1e-15);
}

TEST(SimulatedWrist, TorqueOnAnUnactuatedAxisIsStillApplied) {
    // The wand does not actuate device y (its roll), but the device applies whatever the loop writes.
    SimulatedDevice dev(quanser_wand_5dof(), ScriptedPath::hold(Vec3(0.0, 0.21, 0.01)));
    dev.bring_up();  // forces pass only while enabled
    dev.write(Vec3(0.0), Vec3(0.0, -0.05, 0.0));
    DeviceState s;
    for (int i = 0; i < 2000; ++i) ASSERT_TRUE(dev.read(s));
    EXPECT_NEAR(rotation_vector(s.pose.orientation).y, -0.1, 1e-12);
}

TEST(SimulatedWrist, WithoutTorqueOrPathTheStylusStaysExactlyAtIdentity) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath({0.0, 0.5}, {Vec3(0.0), Vec3(0.02, -0.01, 0.0)}));
    dev.bring_up();  // forces pass only while enabled
    DeviceState s;
    for (int i = 0; i < 600; ++i) {
        dev.write(Vec3(0.1 * std::sin(0.01 * i), 0.2, -0.1), Vec3(0.0));
        ASSERT_TRUE(dev.read(s));
        ASSERT_EQ(s.pose.orientation, kIdentity) << i;
    }
    EXPECT_EQ(dev.angular_velocity_rad_s(), Vec3(0.0));
}

TEST(SimulatedWrist, TorqueDoesNotChangeThePositions) {
    const ScriptedPath path({0.0, 0.5}, {Vec3(0.0), Vec3(0.02, -0.01, 0.0)});
    SimulatedHandParams hand;
    hand.substeps = 7;
    SimulatedDevice a(generic_6dof(), path, hand), b(generic_6dof(), path, hand);
    a.bring_up();  // forces pass only while enabled
    b.bring_up();
    DeviceState sa, sb;
    for (int i = 0; i < 600; ++i) {
        const Vec3 f(0.1 * std::sin(0.01 * i), 0.2, -0.1);
        a.write(f, Vec3(0.0));
        b.write(f, Vec3(0.05 * std::cos(0.02 * i), 0.1, -0.2));
        ASSERT_TRUE(a.read(sa));
        ASSERT_TRUE(b.read(sb));
        ASSERT_EQ(sa.pose.position, sb.pose.position) << i;  // bit for bit
        ASSERT_EQ(sa.velocity_m_s, sb.velocity_m_s) << i;
    }
    EXPECT_GT(glm::length(angle_of(b)), 0.1);
}

TEST(SimulatedWrist, TorqueSpringInTheLoopTurnsTheStylusBack) {
    // The hand wants 0.4 rad about x; a virtual torsion spring K_c (what a haptic loop would render)
    // pulls toward identity. Equilibrium k_r (0.4 - theta) = K_c theta: theta = 0.4 k_r / (k_r + K_c).
    SimulatedDevice dev(quanser_wand_5dof(), ScriptedPath::hold(Vec3(0.0, 0.21, 0.01)));
    dev.bring_up();  // forces pass only while enabled
    dev.set_orientation_path(ScriptedOrientation({0.0, 0.2}, {kIdentity, glm::angleAxis(0.4, Vec3(1, 0, 0))}));
    const double kr = dev.hand().hand_torsion_stiffness_nm_per_rad, kc = 0.3;
    DeviceState s;
    double max_angle = 0.0;
    for (int i = 0; i < 3000; ++i) {
        ASSERT_TRUE(dev.read(s));
        const Vec3 theta = rotation_vector(s.pose.orientation);
        max_angle = std::max(max_angle, glm::length(theta));
        dev.write(Vec3(0.0), -kc * theta);  // the loop's torque, device frame, one tick late (as the loop)
    }
    const Vec3 theta = rotation_vector(s.pose.orientation);
    EXPECT_NEAR(theta.x, 0.4 * kr / (kr + kc), 1e-9);
    EXPECT_NEAR(theta.y, 0.0, 1e-12);
    EXPECT_NEAR(theta.z, 0.0, 1e-12);
    EXPECT_LT(max_angle, 0.4);  // held back all the way, never reached the hand's target
}

TEST(SimulatedWrist, EnergyStaysBounded) {
    // Undamped wrist: a torque pulse, then free oscillation; the semi-implicit step keeps the energy
    // (kinetic + torsion spring) within a few percent and it never grows.
    SimulatedHandParams hand;
    hand.hand_torsion_damping_nm_s_per_rad = 0.0;
    hand.substeps = 4;
    SimulatedDevice dev(generic_6dof(), ScriptedPath::hold(Vec3(0.0)), hand);
    dev.bring_up();  // forces pass only while enabled
    DeviceState s;
    dev.write(Vec3(0.0), Vec3(0.1, -0.05, 0.2));
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(dev.read(s));
    dev.write(Vec3(0.0), Vec3(0.0));
    ASSERT_TRUE(dev.read(s));
    const double e0 = dev.energy_j();
    ASSERT_GT(e0, 1e-6);
    double lo = e0, hi = e0;
    for (int i = 0; i < 20000; ++i) {
        ASSERT_TRUE(dev.read(s));
        lo = std::min(lo, dev.energy_j());
        hi = std::max(hi, dev.energy_j());
    }
    std::printf("undamped wrist: energy %.6g J, range [%.6g, %.6g] over 20 s\n", e0, lo, hi);
    EXPECT_LT(hi, 1.05 * e0);
    EXPECT_GT(lo, 0.95 * e0);
    // With the default damping the same pulse dies out.
    SimulatedDevice damped(generic_6dof(), ScriptedPath::hold(Vec3(0.0)));
    damped.bring_up();  // forces pass only while enabled
    damped.write(Vec3(0.0), Vec3(0.1, -0.05, 0.2));
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(damped.read(s));
    damped.write(Vec3(0.0), Vec3(0.0));
    for (int i = 0; i < 2000; ++i) ASSERT_TRUE(damped.read(s));
    EXPECT_LT(damped.energy_j(), 1e-12);
}

TEST(SimulatedWrist, NonFiniteTorqueIsAppliedAsZero) {
    SimulatedDevice dev(quanser_wand_5dof(), ScriptedPath::hold(Vec3(0.0, 0.21, 0.01)));
    dev.bring_up();  // forces pass only while enabled
    const double nan = std::numeric_limits<double>::quiet_NaN();
    dev.write(Vec3(0.0), Vec3(0.0, 0.0, nan));
    DeviceState s;
    for (int i = 0; i < 100; ++i) ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.pose.orientation, kIdentity);
    EXPECT_EQ(dev.last_torque_nm(), Vec3(0.0));  // the device seam sends a non-finite torque as zero
    dev.write(Vec3(0.0), Vec3(std::numeric_limits<double>::infinity(), 0.0, 0.0));
    for (int i = 0; i < 100; ++i) ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.pose.orientation, kIdentity);
}

TEST(SimulatedWrist, HandFollowsAnOrientationPath) {
    // 1 rad about z over 1 s, then hold; the torsion spring-damper lags by about b_r w / k_r = 0.02 rad
    // while turning and settles on the target.
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    dev.bring_up();  // forces pass only while enabled
    dev.set_orientation_path(ScriptedOrientation({0.0, 1.0}, {kIdentity, glm::angleAxis(1.0, Vec3(0, 0, 1))}));
    DeviceState s;
    for (int i = 0; i < 2000; ++i) {
        ASSERT_TRUE(dev.read(s));
        const double err = glm::length(rotation_vector(dev.orientation_path()->orientation_at(s.t_s) *
                                                        glm::conjugate(s.pose.orientation)));
        if (s.t_s > 0.2 && s.t_s < 1.0) {
            EXPECT_LT(err, 0.03) << s.t_s;
        }
        if (s.t_s > 1.5) {
            EXPECT_LT(err, 1e-6) << s.t_s;
        }
    }
    EXPECT_NEAR(rotation_vector(s.pose.orientation).z, 1.0, 1e-6);
}

TEST(SimulatedWrist, TraceKeepsTheOrientation) {
    SimulatedDevice dev(generic_6dof(), ScriptedPath::hold(Vec3(0.0)));
    dev.bring_up();  // forces pass only while enabled
    dev.enable_trace(5);
    dev.write(Vec3(0.0), Vec3(0.0, 0.0, 0.1));
    DeviceState s;
    for (int i = 0; i < 8; ++i) ASSERT_TRUE(dev.read(s));
    ASSERT_EQ(dev.trace().size(), 5u);
    const SimulatedTraceEntry& e = dev.trace()[4];
    EXPECT_EQ(e.device_torque_nm, Vec3(0.0, 0.0, 0.1));
    EXPECT_EQ(e.target_orientation, kIdentity);
    EXPECT_GT(e.angular_velocity_rad_s.z, 0.0);
    EXPECT_GT(rotation_vector(e.orientation).z, rotation_vector(dev.trace()[3].orientation).z);
    EXPECT_LT(e.hand_torque_nm.z, 0.0);  // the hand resists the turn
}

TEST(SimulatedWrist, BadWristParametersAreRefused) {
    const auto refused = [](SimulatedHandParams h, const std::string& field) {
        try {
            SimulatedDevice dev(generic_6dof(), ScriptedPath::hold(Vec3(0.0)), h);
            dev.bring_up();  // forces pass only while enabled
            ADD_FAILURE() << "no error for " << field;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    SimulatedHandParams h;
    h.inertia_kg_m2 = 0.0;
    refused(h, "inertia_kg_m2");
    h = {};
    h.hand_torsion_stiffness_nm_per_rad = -1.0;
    refused(h, "hand_torsion_stiffness_nm_per_rad");
    h = {};
    h.hand_torsion_damping_nm_s_per_rad = std::numeric_limits<double>::infinity();
    refused(h, "hand_torsion_damping_nm_s_per_rad");
    h = {};
    h.device_torsion_damping_nm_s_per_rad = -0.1;
    refused(h, "device_torsion_damping_nm_s_per_rad");
}

}  // namespace
}  // namespace tridex::devices
