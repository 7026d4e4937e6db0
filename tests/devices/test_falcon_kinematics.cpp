// tests/devices/test_falcon_kinematics.cpp - Falcon kinematics: forward of inverse over the workspace, the Jacobian
// against finite differences, force/torque duality, encoder quantisation, motor command clamping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "devices/device_profiles.hpp"
#include "devices/falcon/falcon_kinematics.hpp"

namespace tridex::devices::falcon {
namespace {

// Points on an 11^3 grid over the Falcon profile's workspace box.
template <class F>
void over_workspace(F&& f) {
    const Aabb box = novint_falcon().workspace_m;
    const int n = 10;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            for (int k = 0; k <= n; ++k) f(box.lo + (box.hi - box.lo) * Vec3(i, j, k) / double(n));
}

Vec3 motor_angles(const FalconAngles& a) { return Vec3(a[0].theta1, a[1].theta1, a[2].theta1); }

TEST(FalconKinematics, ForwardOfInverseWithinAMicrometreOverTheWorkspace) {
    const FalconKinematics k;
    double worst = 0.0;
    int worst_it = 0;
    over_workspace([&](const Vec3& p) {
        const auto a = k.inverse(p);
        ASSERT_TRUE(a) << p.x << " " << p.y << " " << p.z;
        const auto fk = k.forward(motor_angles(*a), FalconKinematics::home_m());
        ASSERT_TRUE(fk.converged) << p.x << " " << p.y << " " << p.z;
        worst = std::max(worst, glm::length(fk.position - p));
        worst_it = std::max(worst_it, fk.iterations);
    });
    std::printf(
        "falcon kinematics: forward(inverse(p)) max error %.3g m over 1331 points, max %d Newton steps from home\n",
        worst, worst_it);
    EXPECT_LT(worst, 1e-6);
}

TEST(FalconKinematics, JacobianMatchesFiniteDifferences) {
    const FalconKinematics k;
    const double h = 1e-7;
    double worst = 0.0;
    over_workspace([&](const Vec3& p) {
        const JointJacobian g = k.jacobian(*k.inverse(p));
        for (int d = 0; d < 3; ++d) {
            Vec3 e(0.0);
            e[d] = h;
            const Vec3 fd = (motor_angles(*k.inverse(p + e)) - motor_angles(*k.inverse(p - e))) / (2.0 * h);
            for (int i = 0; i < 3; ++i)
                worst = std::max(worst, std::abs(fd[i] - g[i][d]) / std::max(1.0, std::abs(g[i][d])));
        }
    });
    std::printf("falcon kinematics: Jacobian vs central differences (h = 1e-7 m), max relative error %.3g\n", worst);
    EXPECT_LT(worst, 1e-4);
}

TEST(FalconKinematics, TorqueAndForceAreDualAndPowerIsConserved) {
    const FalconKinematics k;
    over_workspace([&](const Vec3& p) {
        const Vec3 f(1.5, -2.0, 3.0);
        const auto tau = k.force_to_torque(p, f);
        ASSERT_TRUE(tau);
        const auto back = k.torque_to_force(p, *tau);
        ASSERT_TRUE(back);
        EXPECT_LT(glm::length(*back - f), 1e-9);
        // Virtual work: tau . dtheta = F . dp for a small dp.
        const Vec3 dp(1e-7, -2e-7, 1.5e-7);
        const Vec3 dth = motor_angles(*k.inverse(p + dp)) - motor_angles(*k.inverse(p));
        EXPECT_NEAR(glm::dot(*tau, dth), glm::dot(f, dp), 1e-9);
    });
    // Out of reach: no torque rather than a wild one.
    EXPECT_FALSE(k.force_to_torque(Vec3(0.0, 0.0, 0.5), Vec3(1.0)));
}

TEST(FalconKinematics, EncoderScalingAndQuantisation) {
    const FalconKinematics k;
    // libnifalcon getTheta: 35 degrees at count 0, 360 * 0.01425 / (1280 * 0.110) degrees per count.
    EXPECT_NEAR(glm::degrees(k.encoder_to_theta(0)), 35.0, 1e-12);
    EXPECT_NEAR(glm::degrees(k.encoder_to_theta(1000)), 35.0 + 1000.0 * 360.0 * 0.01425 / (1280.0 * 0.110), 1e-9);
    EXPECT_EQ(k.theta_to_encoder(k.encoder_to_theta(-319)), -319);
    EXPECT_EQ(k.theta_to_encoder(k.encoder_to_theta(5) + 0.4 * k.geometry().rad_per_count), 5);
    // One count moves the grip by tens of micrometres at home (Novint: over 400 dpi = 63.5 um).
    const Vec3 home = FalconKinematics::home_m();
    const JointJacobian g = k.jacobian(*k.inverse(home));
    const glm::dmat3 gt(g[0], g[1], g[2]);
    const Vec3 dp = glm::inverse(glm::transpose(gt)) * Vec3(k.geometry().rad_per_count, 0.0, 0.0);
    EXPECT_GT(glm::length(dp), 10e-6);
    EXPECT_LT(glm::length(dp), 100e-6);
}

TEST(FalconKinematics, MotorCommandsKeepTheirRatioWhenClamped) {
    bool clamped = true;
    auto c = torque_to_command(Vec3(0.1, -0.2, 0.0), kMaxMotorCommand, &clamped);
    EXPECT_FALSE(clamped);
    EXPECT_EQ(c[0], -1000);  // libnifalcon's sign and scale: -10000 per N*m
    EXPECT_EQ(c[1], 2000);
    c = torque_to_command(Vec3(10.0, -5.0, 2.5), 4000, &clamped);
    EXPECT_TRUE(clamped);
    EXPECT_EQ(c[0], -4000);
    EXPECT_EQ(c[1], 2000);
    EXPECT_EQ(c[2], -1000);
    c = torque_to_command(Vec3(std::nan(""), 0.0, 0.0), kMaxMotorCommand, &clamped);
    EXPECT_EQ(c, (std::array<std::int16_t, 3>{0, 0, 0}));
    EXPECT_NEAR(command_to_torque({-1000, 2000, 0}).x, 0.1, 1e-12);
}

}  // namespace
}  // namespace tridex::devices::falcon
