// Cutting reaction: the chip cross-section of a ball against the circular-segment formula, the force's
// size and direction, and the god-object adding it while a ball is dragged through material.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "haptics/forces/cutting_force.hpp"
#include "haptics/god_object.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

using std::numbers::pi;

// Circular segment of a circle of radius r cut at depth d, from the central angle: r^2/2 (t - sin t),
// t = 2 acos((r - d)/r) (an independent form of the same area).
double segment(double r, double d) {
    const double t = 2.0 * std::acos((r - d) / r);
    return 0.5 * r * r * (t - std::sin(t));
}

TEST(CuttingForce, ChipAreaIsTheCircularSegment) {
    const double r = 2e-3;
    EXPECT_EQ(chip_area_m2(r, 0.0), 0.0);
    EXPECT_EQ(chip_area_m2(r, -1e-3), 0.0);
    EXPECT_EQ(chip_area_m2(0.0, 1e-3), 0.0);
    EXPECT_NEAR(chip_area_m2(r, r), 0.5 * pi * r * r, 1e-18);     // half the disc
    EXPECT_NEAR(chip_area_m2(r, 2 * r), pi * r * r, 1e-18);       // the whole disc
    EXPECT_NEAR(chip_area_m2(r, 5 * r), pi * r * r, 1e-18);       // deeper: still the whole ball
    for (const double d : {1e-5, 2e-4, 7e-4, 1.3e-3, 3.1e-3})
        EXPECT_NEAR(chip_area_m2(r, d), segment(r, d), 1e-17) << d;  // m^2, ~1e-11 relative
    EXPECT_EQ(chip_area_m2(r, std::nan("")), 0.0);
}

TEST(CuttingForce, OpposesMotionAndFadesInWithSpeed) {
    const double kc = 2e5, r = 2e-3, d = 1e-3, fade = 0.01;
    const Vec3 n(0, 0, 1);
    const double full = kc * chip_area_m2(r, d);  // N
    // Fast tangential feed along +x: the full force along -x.
    Vec3 f = cutting_force(kc, r, d, Vec3(0.05, 0, 0), n, fade);
    EXPECT_NEAR(f.x, -full, 1e-12);
    EXPECT_EQ(f.y, 0.0);
    EXPECT_EQ(f.z, 0.0);
    // Plunging obliquely (down and along y): against the velocity.
    const Vec3 v(0.0, 0.03, -0.04);
    f = cutting_force(kc, r, d, v, n, fade);
    EXPECT_NEAR(glm::length(f), full, 1e-12);
    EXPECT_NEAR(glm::dot(glm::normalize(f), glm::normalize(v)), -1.0, 1e-15);
    // Slow: faded linearly, |v| / v_fade.
    EXPECT_NEAR(glm::length(cutting_force(kc, r, d, Vec3(0.0025, 0, 0), n, fade)), 0.25 * full, 1e-12);
    // At rest, withdrawing, not engaged, or bad input: nothing.
    EXPECT_EQ(cutting_force(kc, r, d, Vec3(0.0), n, fade), Vec3(0.0));
    EXPECT_EQ(cutting_force(kc, r, d, Vec3(0.01, 0, 0.001), n, fade), Vec3(0.0));
    EXPECT_EQ(cutting_force(kc, r, 0.0, Vec3(0.05, 0, 0), n, fade), Vec3(0.0));
    EXPECT_EQ(cutting_force(kc, r, d, Vec3(std::nan(""), 0, 0), n, fade), Vec3(0.0));
}

TEST(CuttingForce, GodObjectAddsItWhileCutting) {
    constexpr double kH = 1e-3, kDt = 1e-3, kC = 10.25;
    const double r = 2e-3, d = 1e-3, kc = 3e5;
    const auto s = test::z_plane(kH, static_cast<float>(kC));
    ContactParams p{700.0, 0.0, r};
    p.cutting = true;
    p.cutting_coefficient_n_per_m2 = kc;
    p.force_shading = false;
    GodObject g(p);
    const double z = (kC * kH) + r - d;  // centre height giving depth d
    g.update(*s, Vec3(8e-3, 10e-3, z + 2e-3), kDt);
    g.update(*s, Vec3(8e-3, 10e-3, z), kDt);  // plunge: 2 mm/ms down -> against the motion, +z
    // Feed along +x at 0.05 m/s (0.05 mm per tick): full cutting force against the feed.
    ContactResult c;
    for (int k = 1; k <= 20; ++k) c = g.update(*s, Vec3(8e-3 + k * 5e-5, 10e-3, z), kDt);
    ASSERT_TRUE(c.contact);
    const double expected = kc * chip_area_m2(r, d);
    EXPECT_NEAR(c.cutting_force_n.x, -expected, 1e-9);
    EXPECT_NEAR(c.force_n.x, -expected, 1e-9);
    EXPECT_NEAR(c.force_n.z, 700.0 * d, 1e-9);
    // Held still: no cutting force (faded out at rest).
    c = g.update(*s, Vec3(8e-3 + 20 * 5e-5, 10e-3, z), kDt);
    EXPECT_EQ(c.cutting_force_n, Vec3(0.0));
    // Cutting off: never.
    p.cutting = false;
    GodObject off(p);
    off.update(*s, Vec3(8e-3, 10e-3, z), kDt);
    EXPECT_EQ(off.update(*s, Vec3(8.05e-3, 10e-3, z), kDt).cutting_force_n, Vec3(0.0));
    // Bad parameters.
    p.cutting_fade_speed_m_per_s = 0.0;
    EXPECT_THROW(GodObject{p}, Error);
    p.cutting_fade_speed_m_per_s = 0.01;
    p.cutting_coefficient_n_per_m2 = -1.0;
    EXPECT_THROW(GodObject{p}, Error);
}

}  // namespace
}  // namespace tridex::haptics
