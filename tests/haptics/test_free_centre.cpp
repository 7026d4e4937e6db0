// The free ball centre near the HIP that the god-object's last step takes the proxy to (snapshot_depth.hpp,
// free_centre_within_radius): the HIP itself when the ball there is free, the nearest free point found over a face,
// the nearest lattice point in a tube whose free core lies between the 26 directions, and none inside a cavity
// smaller than the ball.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "haptics/snapshot_depth.hpp"
#include "surfaces.hpp"

namespace tridex::haptics::contact {
namespace {

constexpr double kCell = 1e-3;  // m
constexpr double kR = 4e-3;     // ball radius, m: 4 cells

// A slab z < 10 cells, seen by all three ray sets around (32, 32, 12) cells.
std::unique_ptr<ActiveSurface> slab() {
    return test::published_surface(kCell, 64, Vec3(32e-3, 32e-3, 12e-3), 0.0, [](int a, int u, int v) {
        if (a == 2) return test::Intervals{{0.0f, 10.0f}};
        const int z = a == 0 ? v : u;  // X rays run at height v, Y rays at height u
        return z < 10 ? test::Intervals{{0.0f, 63.0f}} : test::Intervals{};
    });
}

TEST(FreeCentre, TheHipWhenFreeElseTheNearestFreePointFound) {
    const auto s = slab();
    Vec3 out(-1.0);
    // Free: the ball's bottom 1 cell above the slab.
    EXPECT_TRUE(free_centre_within_radius(*s, Vec3(32e-3, 32e-3, 15e-3), kR, Vec3(32e-3, 32e-3, 20e-3), out));
    EXPECT_EQ(out, Vec3(32e-3, 32e-3, 15e-3));
    // Pressed 2 cells in: a quarter radius up still overlaps by a cell, half a radius up it rests on the face.
    const Vec3 hip(32e-3, 32e-3, 12e-3);
    ASSERT_TRUE(free_centre_within_radius(*s, hip, kR, hip + Vec3(0.3e-3, 0.0, 8e-3), out));
    EXPECT_NEAR(out.z - hip.z, 0.5 * kR, 1e-12);
    EXPECT_NEAR(glm::length(out - hip), 0.5 * kR, 1e-12);  // straight up: no sideways point at that distance is free
    EXPECT_TRUE(ball_free(*s, out, kR));
    EXPECT_FALSE(ball_free(*s, hip, kR));
    // No radius, no answer; a point tool's "ball" is its centre.
    out = Vec3(-1.0);
    EXPECT_FALSE(free_centre_within_radius(*s, hip, 0.0, hip, out));
    EXPECT_EQ(out, Vec3(-1.0));
    EXPECT_TRUE(ball_free(*s, Vec3(32e-3, 32e-3, 11e-3), 0.0));
}

TEST(FreeCentre, TheLatticeFindsAFreeCoreBetweenTheDirections) {
    // Solid everywhere but a tube of radius 4.6 cells about the axis through c along a = (1, 2, 0) / sqrt(5). A ball
    // of 4 cells (3.75 with the quarter-spacing margin) is free only within 0.85 cells of the axis. The HIP lies 3
    // cells off the axis along z, outside the solid: the nearest free centre is 2.15 cells below it, a spot none of
    // the 26 points one radius out reaches.
    const Vec3 c(32.0, 32.0, 32.0);
    const Vec3 a = glm::normalize(Vec3(1.0, 2.0, 0.0));
    constexpr double kTube = 4.6;
    const auto perp = [&](const Vec3& w) { return w - glm::dot(w, a) * a; };
    const auto s = test::published_surface(kCell, 64, c * kCell, 0.0, [&](int ax, int u, int v) {
        Vec3 w0(0.0), e(0.0);
        w0[(ax + 1) % 3] = u;
        w0[(ax + 2) % 3] = v;
        w0 -= c;
        w0[ax] = -c[ax];
        e[ax] = 1.0;
        const Vec3 wp = perp(w0), ep = perp(e);
        const double qa = glm::dot(ep, ep), qb = glm::dot(wp, ep), qc = glm::dot(wp, wp) - kTube * kTube;
        const double disc = qb * qb - qa * qc;
        if (!(qa > 0.0) || !(disc > 0.0)) return test::Intervals{{0.0f, 63.0f}};
        const double t0 = (-qb - std::sqrt(disc)) / qa, t1 = (-qb + std::sqrt(disc)) / qa;
        test::Intervals in;
        if (t0 > 0.0) in.push_back({0.0f, static_cast<float>(std::min(t0, 63.0))});
        if (t1 < 63.0) in.push_back({static_cast<float>(std::max(t1, 0.0)), 63.0f});
        return in;
    });
    const Vec3 hip = (c + Vec3(0.0, 0.0, 3.0)) * kCell;
    Vec3 out(-1.0);
    ASSERT_FALSE(ball_free(*s, hip, kR));
    EXPECT_FALSE(free_centre_within_radius(*s, hip, kR, hip, out, false)) << "the 26 directions alone";
    EXPECT_EQ(out, Vec3(-1.0));
    ASSERT_TRUE(free_centre_within_radius(*s, hip, kR, hip, out));
    EXPECT_TRUE(ball_free(*s, out, kR));
    const double gap_cells = glm::length(out - hip) / kCell;
    EXPECT_LE(gap_cells, kR / kCell + 1e-9);
    // The lattice's spacing is r / 6 = 0.67 cells: the point found is the analytic nearest (2.15 cells) or a
    // lattice step farther, and lies in the free core (0.85 cells of the axis, plus what the rays between them miss).
    EXPECT_GE(gap_cells, 2.15 - 0.25) << gap_cells;
    EXPECT_LE(gap_cells, 2.15 + 4.0 / 6.0 * std::sqrt(3.0)) << gap_cells;
    EXPECT_LE(glm::length(perp(out / kCell - c)), 0.85 + 0.25);
    Vec3 direct(-1.0);
    ASSERT_TRUE(free_centre_on_lattice(*s, hip, kR, hip, direct));
    EXPECT_EQ(direct, out);
}

TEST(FreeCentre, NoneInACavitySmallerThanTheBall) {
    // Solid everywhere but a ball-shaped cavity of 2 cells about (32, 32, 32) cells: a HIP at its centre is outside
    // the solid, yet no ball of 4 cells fits within a radius of it.
    const Vec3 c(32.0, 32.0, 32.0);
    const auto s = test::published_surface(kCell, 64, c * kCell, 0.0, [&](int a, int u, int v) {
        Vec3 p(0.0);
        p[(a + 1) % 3] = u;
        p[(a + 2) % 3] = v;
        const double du = p[(a + 1) % 3] - c[(a + 1) % 3], dv = p[(a + 2) % 3] - c[(a + 2) % 3];
        const double h2 = 4.0 - du * du - dv * dv;
        if (!(h2 > 0.0)) return test::Intervals{{0.0f, 63.0f}};
        const double h = std::sqrt(h2);
        return test::Intervals{{0.0f, static_cast<float>(c[a] - h)}, {static_cast<float>(c[a] + h), 63.0f}};
    });
    Vec3 out(-1.0);
    EXPECT_FALSE(free_centre_within_radius(*s, c * kCell, kR, c * kCell, out));
    EXPECT_EQ(out, Vec3(-1.0));
}

}  // namespace
}  // namespace tridex::haptics::contact
