// The proxy follows the hand at 1 kHz on a snapshot that follows the proxy, as the publisher does: after quick moves
// of every kind over a sphere (a tick's jump, a frame's, a tenth of a second's; pressed and resting) no tick has the
// proxy more than one tool radius from a HIP outside the solid, and a resting tool whose surface changes under it
// (material added, taken away, undone) ends on the surface nearest the HIP, outside the solid, its force rising
// without a spike.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "follow_rig.hpp"

namespace tridex::haptics {
namespace {

using test::AnalyticSolid;
using test::FollowRig;

constexpr double kCell = 1e-3;  // m
constexpr int kNodes = 128;
constexpr double kTool = 6e-3;  // ball radius, m
const Vec3 kCentre(64e-3, 64e-3, 50e-3);
constexpr double kR = 30e-3;  // sphere radius, m

ContactParams params() {
    ContactParams p;
    p.tool_radius_m = kTool;
    p.force_shading = true;
    return p;
}

// A point of the sphere's offset surface at `depth` inside it (m), in direction (theta from +z, phi about z).
Vec3 on_sphere(double theta, double phi, double depth) {
    return kCentre + (kR + kTool - depth) * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                                 std::cos(theta));
}

void print(const std::string& what, const test::FollowFigures& f) {
    std::printf("[follow] %s: %d ticks; HIP outside: worst gap %.2f mm, %d ticks over the radius; worst gap %.2f mm; "
                "largest force rise %.3f N, step %.3f N; contact point at most %.3f cells inside\n",
                what.c_str(), f.ticks, 1e3 * f.worst_gap_hip_outside_m, f.ticks_over_radius_hip_outside,
                1e3 * f.worst_gap_m, f.worst_force_rise_n, f.worst_force_step_n, f.worst_proxy_inside_m / kCell);
}

// Forty moves between random points of the upper sphere, each in `move_ticks` ticks along the straight chord (which
// runs through the solid, as a mouse's target does), pressed 0, 0.3 or 1 radius in, resting 200 ticks at each.
test::FollowFigures quick_moves(int move_ticks, unsigned seed) {
    FollowRig rig(kCell, kNodes, params(), test::ball_solid(kCentre, kR, kCell));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> theta(0.0, 1.2), phi(0.0, 6.283);
    const double depths[3] = {0.0, 0.3 * kTool, kTool};
    Vec3 at = on_sphere(0.0, 0.0, -2e-3);
    for (int t = 0; t < 50; ++t) (void)rig.tick(at);
    for (int m = 0; m < 40; ++m) {
        const Vec3 to = on_sphere(theta(rng), phi(rng), depths[rng() % 3]);
        for (int t = 1; t <= move_ticks; ++t) (void)rig.tick(at + (to - at) * (static_cast<double>(t) / move_ticks));
        for (int t = 0; t < 200; ++t) (void)rig.tick(to);
        at = to;
    }
    return rig.figures();
}

TEST(ProxyFollow, QuickMovesOverASphereNeverLeaveTheProxyBehindAFreeHip) {
    for (const int ticks : {1, 16, 100}) {
        const test::FollowFigures f = quick_moves(ticks, 7u + static_cast<unsigned>(ticks));
        print("moves of " + std::to_string(ticks) + " ticks", f);
        EXPECT_EQ(f.ticks_over_radius_hip_outside, 0) << ticks;
        EXPECT_LE(f.worst_gap_hip_outside_m, kTool + 0.01 * kCell) << ticks;
        EXPECT_LT(f.worst_proxy_inside_m, 1.0 * kCell) << ticks;
    }
}

// Sweeps over the sphere at 0.75 m/s with the ball pressed 0.9 radius in (its centre just outside the surface, as a
// mouse carving at its default depth of one radius nearly has it) and Coulomb friction on: the proxy lags the HIP by
// the friction cone and no more. With mu_s = 0.2 the god-object may stand up to r * sqrt(1 + mu_s^2) from the HIP.
TEST(ProxyFollow, FastSweepsWithFrictionLagByTheFrictionConeOnly) {
    for (const double cell : {1e-3, 1.875e-3}) {
        ContactParams p = params();
        p.static_friction = 0.2;
        p.dynamic_friction = 0.15;
        FollowRig rig(cell, static_cast<int>(std::lround(128e-3 / cell)), p, test::ball_solid(kCentre, kR, cell));
        std::mt19937 rng(11u);
        std::uniform_real_distribution<double> theta(0.0, 1.2), phi(0.0, 6.283);
        Vec3 at = on_sphere(0.0, 0.0, -2e-3);
        for (int t = 0; t < 50; ++t) (void)rig.tick(at);
        for (int m = 0; m < 40; ++m) {
            // An arc over the sphere at the depth of one radius, 0.75 mm a tick.
            const double t0 = theta(rng), p0 = phi(rng), t1 = theta(rng), p1 = phi(rng);
            const double length = (kR + kTool) * std::hypot(t1 - t0, (p1 - p0) * std::sin(0.5 * (t0 + t1)));
            const int ticks = std::max(1, static_cast<int>(length / 0.75e-3));
            for (int t = 0; t <= ticks; ++t) {
                const double s = static_cast<double>(t) / ticks;
                (void)rig.tick(on_sphere(t0 + s * (t1 - t0), p0 + s * (p1 - p0), 0.9 * kTool));
            }
            for (int t = 0; t < 100; ++t) (void)rig.tick(on_sphere(t1, p1, 0.9 * kTool));
        }
        const test::FollowFigures f = rig.figures();
        print("sweeps at 0.75 m/s, friction 0.2, cell " + std::to_string(cell * 1e3).substr(0, 5) + " mm", f);
        EXPECT_LE(f.worst_gap_hip_outside_m, kTool * std::sqrt(1.0 + 0.2 * 0.2) + 0.1 * cell);
    }
}

// A rested, pressed tool; then the solid changes under it and the hand stays put: after 50 ticks the proxy rests on
// the new surface over the HIP (within a tenth of a cell of the analytic point), outside the solid.
struct Change {
    std::string name;
    AnalyticSolid after;
    double surface_z_m;  // the new face's height over the HIP
};

TEST(ProxyFollow, ASurfaceChangedUnderARestingToolTakesTheProxyToItsNearestPoint) {
    const Vec3 n(0.0, 0.0, 1.0);
    const double face = 40e-3, press = 1e-3;
    const Vec3 hip(61.3e-3, 63.7e-3, face + kTool - press);
    const Change changes[] = {
        {"material added (union, redo, another person's add)", test::half_space_solid(n, face + 3e-3, kCell, kNodes),
         face + 3e-3},
        {"material taken away (a cut, undo of an add)", test::half_space_solid(n, face - 0.6e-3, kCell, kNodes),
         face - 0.6e-3},
        {"a cut deeper than the press (the tool is free)", test::half_space_solid(n, face - 5e-3, kCell, kNodes),
         face - 5e-3},
        {"a tilted face (push, pull, grab, resample)",
         test::half_space_solid(glm::normalize(Vec3(0.2, 0.1, 1.0)), glm::dot(glm::normalize(Vec3(0.2, 0.1, 1.0)),
                                                                              Vec3(61.3e-3, 63.7e-3, face + 1e-3)),
                                kCell, kNodes),
         std::nan("")},
    };
    for (const Change& ch : changes) {
        FollowRig rig(kCell, kNodes, params(), test::half_space_solid(n, face, kCell, kNodes));
        for (double z = hip.z + 3e-3; z > hip.z; z -= 0.1e-3) (void)rig.tick(Vec3(hip.x, hip.y, z));
        ContactResult c;
        for (int t = 0; t < 100; ++t) c = rig.tick(hip);
        ASSERT_TRUE(c.contact) << ch.name;
        EXPECT_NEAR(glm::length(c.force_n), 700.0 * press, 0.01 * 700.0 * press) << ch.name;
        rig.reset_figures();
        (void)rig.tick(hip);  // the last force before the change, for the force steps
        rig.set_solid(ch.after);
        for (int t = 0; t < 50; ++t) c = rig.tick(hip);
        print(ch.name, rig.figures());
        // The analytic answer: the ball touching the new surface at the point nearest the HIP.
        const double sd = ch.after.sdf(hip);
        if (sd >= kTool) {
            EXPECT_FALSE(c.contact) << ch.name;
            EXPECT_LT(glm::length(c.proxy_m - hip), 1e-9) << ch.name;
            continue;
        }
        ASSERT_TRUE(c.contact) << ch.name;
        const double depth = kTool - sd;
        const double off_surface = ch.after.sdf(c.proxy_m) - kTool;
        EXPECT_NEAR(off_surface, 0.0, 0.1 * kCell) << ch.name << ": the proxy is not on the new surface";
        EXPECT_NEAR(glm::length(c.force_n), 700.0 * depth, 0.01 * 700.0 * depth) << ch.name;
        if (std::isfinite(ch.surface_z_m)) {
            EXPECT_NEAR(c.proxy_m.z, ch.surface_z_m + kTool, 0.1 * kCell) << ch.name;
        }
        // No spike: with the hand still, the force rises by at most 0.1 N a tick (100 N/s).
        EXPECT_LE(rig.figures().worst_force_rise_n, 0.1 + 1e-9) << ch.name;
    }
}

}  // namespace
}  // namespace tridex::haptics
