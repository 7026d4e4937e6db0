// Coulomb friction on the god-object: the friction cone function alone, and a HIP pressed into a plane
// and dragged sideways (the force's angle from the normal stays within atan(mu_s) while it sticks and
// settles at atan(mu_d) while it slides).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "haptics/forces/friction.hpp"
#include "haptics/god_object.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

constexpr double kH = 1e-3;    // cell, m
constexpr float kC = 10.25f;   // plane height, cells
constexpr double kKp = 700.0;  // N/m
constexpr double kDt = 1e-3;   // s

Vec3 mm(double x, double y, double z) { return Vec3(x, y, z) * 1e-3; }

TEST(FrictionCone, SticksInsideStaticConeAndSlidesToDynamicEdge) {
    const Vec3 frictionless(0.0), stick(0.4, 0.3, 0.0);  // |t| = 0.5
    // depth 1, mu_s 0.6: 0.5 <= 0.6 -> sticks.
    FrictionStep s = friction_cone(stick, frictionless, 1.0, 0.6, 0.2, false);
    EXPECT_FALSE(s.sliding);
    EXPECT_EQ(s.proxy_m, stick);
    // mu_s 0.4: slides to |t| = mu_d * depth = 0.2 along the drag direction (0.8, 0.6).
    s = friction_cone(stick, frictionless, 1.0, 0.4, 0.2, false);
    EXPECT_TRUE(s.sliding);
    EXPECT_NEAR(s.proxy_m.x, 0.16, 1e-15);
    EXPECT_NEAR(s.proxy_m.y, 0.12, 1e-15);
    // Once sliding, the dynamic cone decides: 0.5 > 0.2 * 1 -> keeps sliding even though mu_s = 0.6.
    EXPECT_TRUE(friction_cone(stick, frictionless, 1.0, 0.6, 0.2, true).sliding);
    // No friction, or no normal force: the frictionless proxy exactly.
    EXPECT_EQ(friction_cone(stick, frictionless, 1.0, 0.0, 0.0, false).proxy_m, frictionless);
    EXPECT_EQ(friction_cone(stick, frictionless, 0.0, 0.6, 0.2, false).proxy_m, frictionless);
}

// Angle (rad) of the force from the plane's normal +z, signed by its x component (the force's x is
// opposite to the drag).
double force_angle(const Vec3& f) { return std::atan2(-f.x, f.z); }

TEST(FrictionCone, HipDraggedOverPlaneFollowsTheCone) {
    const double mu_s = 0.5, mu_d = 0.3, depth_mm = 2.0, step_mm = 0.02;
    const auto s = test::z_plane(kH, kC);
    ContactParams p{kKp, 0.0, 0.0, mu_s, mu_d};
    GodObject g(p);
    g.update(*s, mm(10, 10, 12), kDt);
    const double z = kC - depth_mm;
    ASSERT_TRUE(g.update(*s, mm(10, 10, z), kDt).contact);  // pressed in straight: no tangential force
    const double tol = 1e-9;  // rad: double rounding of mm-sized positions
    // Drag along +x. Sticking: the proxy stays at x = 10 mm, the angle is atan(dx / depth) <= atan(mu_s).
    double x = 10.0, max_stick_angle = 0.0;
    int tick = 0;
    ContactResult c;
    for (;; ++tick) {
        x += step_mm;
        c = g.update(*s, mm(x, 10, z), kDt);
        ASSERT_TRUE(c.contact);
        if (c.sliding) break;
        ASSERT_LT(tick, 1000);
        EXPECT_NEAR(c.proxy_m.x, 10e-3, 1e-12);
        EXPECT_NEAR(force_angle(c.force_n), std::atan((x - 10.0) / depth_mm), tol);
        max_stick_angle = std::max(max_stick_angle, force_angle(c.force_n));
    }
    // It broke away within one step of the static cone: dx in (mu_s*d, mu_s*d + step].
    EXPECT_GT(x - 10.0, mu_s * depth_mm);
    EXPECT_LE(x - 10.0, mu_s * depth_mm + step_mm + 1e-9);
    EXPECT_LE(max_stick_angle, std::atan(mu_s) + tol);
    EXPECT_GT(max_stick_angle, std::atan((mu_s * depth_mm - step_mm) / depth_mm) - tol);
    // Sliding: |F_t| = mu_d * |F_n| on every tick, the proxy trailing the HIP by mu_d * depth.
    for (int k = 0; k < 100; ++k) {
        x += step_mm;
        c = g.update(*s, mm(x, 10, z), kDt);
        ASSERT_TRUE(c.contact);
        EXPECT_TRUE(c.sliding);
        EXPECT_NEAR(force_angle(c.force_n), std::atan(mu_d), tol);
        EXPECT_NEAR(c.proxy_m.x, (x - mu_d * depth_mm) * 1e-3, 1e-12);
        EXPECT_NEAR(c.force_n.z, kKp * depth_mm * 1e-3, 1e-9);
    }
    // Held still: it sticks where it slid to; the force stays on the dynamic cone's edge.
    for (int k = 0; k < 10; ++k) {
        c = g.update(*s, mm(x, 10, z), kDt);
        EXPECT_NEAR(force_angle(c.force_n), std::atan(mu_d), tol);
    }
    EXPECT_FALSE(c.sliding);
    // Dragged back: it sticks until the HIP has crossed to mu_s * depth on the other side.
    const double proxy_x = x - mu_d * depth_mm;
    for (;;) {
        x -= step_mm;
        c = g.update(*s, mm(x, 10, z), kDt);
        if (c.sliding) break;
        EXPECT_NEAR(c.proxy_m.x, proxy_x * 1e-3, 1e-12);
        EXPECT_GE(force_angle(c.force_n), -std::atan(mu_s) - tol);
    }
    EXPECT_LT(x - proxy_x, -mu_s * depth_mm);
    EXPECT_GE(x - proxy_x, -mu_s * depth_mm - step_mm - 1e-9);
    x -= step_mm;
    c = g.update(*s, mm(x, 10, z), kDt);
    EXPECT_NEAR(force_angle(c.force_n), -std::atan(mu_d), tol);
    std::printf("friction cone: stuck up to %.4f rad (atan mu_s %.4f), slid at atan mu_d = %.4f rad\n",
                max_stick_angle, std::atan(mu_s), std::atan(mu_d));
}

TEST(FrictionCone, RejectsBadCoefficients) {
    EXPECT_THROW(GodObject(ContactParams{kKp, 0.0, 0.0, -0.1, 0.0}), Error);
    EXPECT_THROW(GodObject(ContactParams{kKp, 0.0, 0.0, 0.2, 0.3}), Error);  // mu_d > mu_s
    EXPECT_THROW(GodObject(ContactParams{kKp, 0.0, 0.0, std::nan(""), 0.0}), Error);
}

}  // namespace
}  // namespace tridex::haptics
