// The god-object in contact stays on the surface nearest the HIP (Zilles & Salisbury; Peng's active triangle): a
// ball tool pressed into a sphere and moved over it faster than the proxy's straight path allows (a mouse or a
// tracker has no force to hold the hand back, and a cut the snapshot has not seen yet holds the proxy behind) must
// find the HIP again, not stay behind with the force at its limit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "haptics/god_object.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

using test::fill_set;
using test::make_surface;

constexpr double kCell = 1e-3;  // m
constexpr double kDt = 1e-3;    // s
const Vec3 kCentre(16e-3, 16e-3, 12e-3);
constexpr double kR = 10e-3;      // the sphere, m
constexpr double kTool = 3e-3;    // the ball tool's radius, m

std::unique_ptr<ActiveSurface> sphere_surface() {
    auto s = make_surface(kCell);
    const test::RayFn rays = test::ball_rays(kCentre, kR, kCell);
    for (int a = 0; a < 3; ++a) fill_set(*s, a, 0, 0, [&](int u, int v) { return rays(a, u, v); });
    return s;
}

// The HIP pressed `depth_m` into the sphere at angle theta (rad) from the top, in the x-z plane.
Vec3 hip_at(double theta, double depth_m) {
    return kCentre + (kR + kTool - depth_m) * Vec3(std::sin(theta), 0.0, std::cos(theta));
}

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// Brings the tool down onto the sphere at angle theta from 2 mm above it to `depth_m` in, a tenth of a mm a tick (a
// HIP that starts inside material feels nothing until it leaves).
void press_in(GodObject& g, const ActiveSurface& s, double theta, double depth_m) {
    for (double d = -2e-3; d <= depth_m + 1e-9; d += 0.1e-3) (void)g.update(s, hip_at(theta, d), kDt);
}

TEST(ContactTracking, AProxyLeftBehindByAJumpReturnsOverTheHip) {
    const auto s = sphere_surface();
    GodObject g(ContactParams{700.0, 0.5, kTool});
    const double d = 1.5e-3;
    press_in(g, *s, 0.0, d);
    ContactResult c;
    for (int t = 0; t < 5; ++t) c = g.update(*s, hip_at(45.0 * kDeg, d), kDt);  // 8 mm over the sphere in a tick
    const double gap = glm::length(c.proxy_m - hip_at(45.0 * kDeg, d));
    std::printf("[tracking] after a 45 degree jump: proxy %.2f mm from the HIP (pressed %.1f mm), %.2f mm off the "
                "sphere's offset surface, force %.2f N\n",
                1e3 * gap, 1e3 * d, 1e3 * (glm::length(c.proxy_m - kCentre) - kR - kTool), glm::length(c.force_n));
    EXPECT_TRUE(c.contact);
    EXPECT_LT(gap, d + 0.5e-3) << "the proxy stayed behind the hand";
    EXPECT_NEAR(glm::length(c.proxy_m - kCentre), kR + kTool, 0.5e-3) << "the proxy left the surface";
}

TEST(ContactTracking, AFastSweepKeepsTheProxyOverTheHipAndARestingToolFindsIt) {
    const auto s = sphere_surface();
    GodObject g(ContactParams{700.0, 0.5, kTool});
    const double d = 1.5e-3;
    double worst = 0.0;
    press_in(g, *s, -30.0 * kDeg, d);
    for (int t = 0; t <= 60; ++t) {  // 1 degree a tick: 0.23 m/s at the tool's centre
        const Vec3 hip = hip_at(t * kDeg - 30.0 * kDeg, d);
        const ContactResult c = g.update(*s, hip, kDt);
        ASSERT_TRUE(c.contact) << t;
        worst = std::max(worst, glm::length(c.proxy_m - hip));
    }
    std::printf("[tracking] sweep at 1 degree a tick: proxy at most %.2f mm from the HIP (pressed %.1f mm)\n",
                1e3 * worst, 1e3 * d);
    EXPECT_LT(worst, d + 0.5e-3);
    // The hand jumps back 40 degrees and rests on the surface (the mouse releases its button): the proxy joins it.
    ContactResult c;
    for (int t = 0; t < 3; ++t) c = g.update(*s, hip_at(-10.0 * kDeg, 0.0), kDt);
    EXPECT_LT(glm::length(c.proxy_m - hip_at(-10.0 * kDeg, 0.0)), 0.5e-3) << "a resting tool left its proxy behind";
    EXPECT_LT(glm::length(c.force_n), 0.5) << "a resting tool still pulled";
}

}  // namespace
}  // namespace tridex::haptics
