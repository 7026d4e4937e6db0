// Tests of haptics/ewma_filter and haptics/force_clamp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "devices/haptic_device.hpp"
#include "haptics/ewma_filter.hpp"
#include "haptics/forces/force_clamp.hpp"

namespace tridex::haptics {
namespace {

TEST(EwmaFilter, UnitStepGivesOneMinusAlphaToTheN) {
    for (double a : {0.9, 0.5, 0.99}) {
        EwmaFilter f(a);
        double an = 1.0;
        for (int n = 1; n <= 200; ++n) {
            const Vec3 out = f.apply(Vec3(1.0, -2.0, 0.5));
            an *= a;
            // 1 - a^n; the recursion and the closed form differ only by rounding (< 1e-14 here).
            EXPECT_NEAR(out.x, 1.0 - an, 1e-14) << "a " << a << " n " << n;
            EXPECT_NEAR(out.y, -2.0 * (1.0 - an), 2e-14);
            EXPECT_NEAR(out.z, 0.5 * (1.0 - an), 1e-14);
        }
    }
}

TEST(EwmaFilter, FirstOutputsAreExact) {
    EwmaFilter f;  // a = 0.9 (Peng et al.)
    EXPECT_DOUBLE_EQ(f.alpha(), 0.9);
    EXPECT_DOUBLE_EQ(f.apply(Vec3(1.0)).x, 1.0 - 0.9);           // 0.1
    EXPECT_DOUBLE_EQ(f.apply(Vec3(1.0)).x, 0.1 + 0.9 * 0.1);     // 0.19 = 1 - 0.81
    f.reset();
    EXPECT_EQ(f.value(), Vec3(0.0));
    EXPECT_DOUBLE_EQ(f.apply(Vec3(2.0)).x, 0.2);
}

TEST(EwmaFilter, AlphaZeroPassesThroughAndBadAlphaThrows) {
    EwmaFilter f(0.0);
    EXPECT_EQ(f.apply(Vec3(3.0, -1.0, 2.0)), Vec3(3.0, -1.0, 2.0));
    EXPECT_THROW(EwmaFilter(1.0), Error);
    EXPECT_THROW(EwmaFilter(-0.1), Error);
    EXPECT_THROW(EwmaFilter(std::nan("")), Error);
}

TEST(ForceClamp, LimitsMagnitudeKeepsDirection) {
    const double fmax = devices::DeviceProfile::phantom_omni().max_force_n;  // 0.88 N
    const Vec3 req = Vec3(60.0, 0.0, 80.0);                                  // 100 N
    const Vec3 out = clamp_force(req, fmax);
    EXPECT_NEAR(glm::length(out), fmax, 1e-15);
    EXPECT_NEAR(out.x, 0.6 * fmax, 1e-15);
    EXPECT_NEAR(out.z, 0.8 * fmax, 1e-15);
    // Below the limit: untouched, bit for bit.
    EXPECT_EQ(clamp_force(Vec3(0.3, -0.2, 0.1), fmax), Vec3(0.3, -0.2, 0.1));
    // Components too large to square: direction still kept.
    const Vec3 huge = clamp_force(Vec3(1e308, 0.0, -1e308), 1.0);
    EXPECT_NEAR(huge.x, std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(huge.z, -std::sqrt(0.5), 1e-15);
}

TEST(ForceClamp, NonFiniteGivesZero) {
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(clamp_force(Vec3(std::nan(""), 0.0, 0.0), 0.88), Vec3(0.0));
    EXPECT_EQ(clamp_force(Vec3(0.0, inf, 0.0), 0.88), Vec3(0.0));
    EXPECT_EQ(clamp_force(Vec3(0.1), std::nan("")), Vec3(0.0));
    EXPECT_EQ(clamp_force(Vec3(0.1), inf), Vec3(0.0));
    EXPECT_EQ(clamp_force(Vec3(0.1), 0.0), Vec3(0.0));
    EXPECT_EQ(clamp_force(Vec3(0.1), -1.0), Vec3(0.0));
    EXPECT_EQ(clamp_magnitude(Vec3(0.0, 0.0, 2.0), 0.5), Vec3(0.0, 0.0, 0.5));  // torque, N*m
}

}  // namespace
}  // namespace tridex::haptics
