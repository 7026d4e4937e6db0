// Contact against analytic shapes, scan-converted exactly into all three ray sets: a point and a ball pressed into
// a tilted flat face, into a sphere and next to a convex edge at known depths give the spring force k*d along the
// analytic normal within 1 % (force shading, friction, cutting and damping off), and the proxy rests on the
// analytic surface (or the ball's centre at its radius from it) within a tenth of a cell, a ball met by a convex
// edge on its bisector or off it, and by a convex corner on its diagonal, included.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "follow_rig.hpp"

namespace tridex::haptics {
namespace {

constexpr double kCell = 1e-3;  // m
constexpr int kNodes = 64;
constexpr double kK = 700.0;  // N/m

ContactParams plain(double radius_m) {
    ContactParams p;
    p.stiffness_n_per_m = kK;
    p.damping_n_s_per_m = 0.0;
    p.tool_radius_m = radius_m;
    p.force_shading = false;
    return p;
}

struct Press {
    ContactResult last;
    double force_error = 0.0;    // |F - k d n_exact| / (k d)
    double surface_error = 0.0;  // |sdf(proxy) - r| / cell
};

// Brings the tool from 3 cells outside along n_exact (unit, outward at the touched point `surface_m`) to `depth_m`
// in, a tenth of a cell a tick, holds it 20 ticks, and compares with the analytic answer.
Press press(const test::AnalyticSolid& solid, double radius_m, const Vec3& surface_m, const Vec3& n_exact,
            double depth_m) {
    test::FollowRig rig(kCell, kNodes, plain(radius_m), solid, 0);
    const Vec3 target = surface_m + (radius_m - depth_m) * n_exact;
    for (double out = 3.0 * kCell; out > 0.0; out -= 0.1 * kCell) (void)rig.tick(target + out * n_exact);
    Press p;
    for (int t = 0; t < 20; ++t) p.last = rig.tick(target);
    const Vec3 expected = kK * depth_m * n_exact;
    p.force_error = glm::length(p.last.force_n - expected) / (kK * depth_m);
    p.surface_error = std::abs(solid.sdf(p.last.proxy_m) - radius_m) / kCell;
    return p;
}

void check(const std::string& what, const Press& p, double depth_m) {
    std::printf("[analytic] %-34s d %.2f cells: |F| %.4f N, force error %.3f %%, proxy %.4f cells off the surface\n",
                what.c_str(), depth_m / kCell, glm::length(p.last.force_n), 100.0 * p.force_error, p.surface_error);
    EXPECT_TRUE(p.last.contact) << what;
    EXPECT_LE(p.force_error, 0.01) << what << " at depth " << depth_m;
    EXPECT_LE(p.surface_error, 0.1) << what << " at depth " << depth_m;
}

TEST(ContactAnalytic, PointAndBallPressedIntoATiltedFace) {
    const Vec3 n = glm::normalize(Vec3(0.3, -0.2, 1.0));
    const Vec3 on(31.3e-3, 30.6e-3, 30.2e-3);
    const test::AnalyticSolid solid = test::half_space_solid(n, glm::dot(n, on), kCell, kNodes);
    for (const double r : {0.0, 3e-3})
        for (const double d : {0.3e-3, 1e-3, 2.5e-3})
            check(std::string(r > 0.0 ? "ball" : "point") + " into a tilted face", press(solid, r, on, n, d), d);
}

TEST(ContactAnalytic, PointAndBallPressedIntoASphere) {
    const Vec3 c(32.2e-3, 31.7e-3, 30.9e-3);
    const double R = 18.5e-3;
    const test::AnalyticSolid solid = test::ball_solid(c, R, kCell);
    const Vec3 dirs[] = {glm::normalize(Vec3(0.2, 0.1, 1.0)), glm::normalize(Vec3(0.6, -0.5, 0.62)),
                         glm::normalize(Vec3(-0.7, 0.1, 0.7))};
    for (const double r : {0.0, 3e-3})
        for (const Vec3& n : dirs)
            for (const double d : {0.5e-3, 1.5e-3})
                check(std::string(r > 0.0 ? "ball" : "point") + " into a sphere", press(solid, r, c + R * n, n, d), d);
}

// The quarter-space x < 40 mm, z < 30 mm: its top face meets its side face in a convex edge along y.
test::AnalyticSolid quarter_space() {
    const double x1 = 40.3e-3, z1 = 30.2e-3;
    const test::RayFn top = test::half_space_rays(Vec3(0, 0, 1), z1, kCell, kNodes);
    const test::RayFn side = test::half_space_rays(Vec3(1, 0, 0), x1, kCell, kNodes);
    return {[=](int a, int u, int v) {
                // Intersect the two half-spaces' intervals on this ray (each has at most one).
                const test::Intervals p = top(a, u, v), q = side(a, u, v);
                if (p.empty() || q.empty()) return test::Intervals{};
                const float lo = std::max(p[0].first, q[0].first), hi = std::min(p[0].second, q[0].second);
                return hi > lo ? test::Intervals{{lo, hi}} : test::Intervals{};
            },
            [=](const Vec3& x) {
                const double dx = x.x - x1, dz = x.z - z1;
                if (dx <= 0.0 && dz <= 0.0) return std::max(dx, dz);
                return std::sqrt(std::max(dx, 0.0) * std::max(dx, 0.0) + std::max(dz, 0.0) * std::max(dz, 0.0));
            }};
}

TEST(ContactAnalytic, PressedNextToAndOntoAConvexEdge) {
    const test::AnalyticSolid solid = quarter_space();
    // A point and a ball pressed into the top face 2.5 cells from the edge: the top face's normal.
    for (const double r : {0.0, 2e-3}) {
        const Vec3 on(37.8e-3, 31.1e-3, 30.2e-3);
        check(std::string(r > 0.0 ? "ball" : "point") + " by an edge, into its top face",
              press(solid, r, on, Vec3(0, 0, 1), 1e-3), 1e-3);
    }
    // A ball pressed onto the edge itself, along the bisector and 30 degrees off it: no face lies under its centre;
    // the analytic force is k * (r - the centre's distance from the edge line) along the line from the edge to it.
    const Vec3 edge(40.3e-3, 31.1e-3, 30.2e-3);
    for (const double angle : {45.0, 15.0, 75.0}) {
        const double a = glm::radians(angle);
        const Vec3 n(std::cos(a), 0.0, std::sin(a));
        for (const double d : {0.3e-3, 0.8e-3, 1.5e-3})
            check("ball onto a convex edge at " + std::to_string(static_cast<int>(angle)) + " deg",
                  press(solid, 3e-3, edge, n, d), d);
    }
}

// The wedge n1 . x <= n1 . e, n2 . x <= n2 . e (n1, n2 unit, not along any ray set): two tilted faces meeting in a
// convex edge through e along n1 x n2.
test::AnalyticSolid wedge(const Vec3& n1, const Vec3& n2, const Vec3& e) {
    const double c1 = glm::dot(n1, e), c2 = glm::dot(n2, e);
    const test::RayFn f1 = test::half_space_rays(n1, c1, kCell, kNodes), f2 = test::half_space_rays(n2, c2, kCell, kNodes);
    const Vec3 t = glm::normalize(glm::cross(n1, n2));
    return {[=](int a, int u, int v) {
                const test::Intervals p = f1(a, u, v), q = f2(a, u, v);
                if (p.empty() || q.empty()) return test::Intervals{};
                const float lo = std::max(p[0].first, q[0].first), hi = std::min(p[0].second, q[0].second);
                return hi > lo ? test::Intervals{{lo, hi}} : test::Intervals{};
            },
            [=](const Vec3& x) {
                const double d1 = glm::dot(n1, x) - c1, d2 = glm::dot(n2, x) - c2;
                if (d1 <= 0.0 && d2 <= 0.0) return std::max(d1, d2);
                // Outside: the nearest point is on a face when the foot point on it lies on the other face's inner
                // side, else on the edge line.
                if (d1 > 0.0 && glm::dot(n2, x - d1 * n1) - c2 <= 0.0) return d1;
                if (d2 > 0.0 && glm::dot(n1, x - d2 * n2) - c1 <= 0.0) return d2;
                const Vec3 off = x - e - glm::dot(x - e, t) * t;
                return glm::length(off);
            }};
}

TEST(ContactAnalytic, BallRolledOverATiltedConvexEdge) {
    // Two faces tilted off every axis, meeting at 100 degrees. The ball's centre is carried around the edge at a
    // fixed distance r - d from it, from one face's normal to the other's; its force must stay k*d along the
    // radial direction (the analytic normal of the cylinder the grown solid has there).
    const Vec3 n1 = glm::normalize(Vec3(0.2, 0.15, 1.0));
    const Vec3 t = glm::normalize(glm::cross(n1, Vec3(0.3, 1.0, -0.1)));
    const Vec3 b = glm::cross(t, n1);  // unit, in the plane normal to the edge, 90 degrees from n1
    const double turn = glm::radians(80.0);
    const Vec3 n2 = std::cos(turn) * n1 + std::sin(turn) * b;
    const Vec3 e(32.4e-3, 31.8e-3, 30.5e-3);
    const test::AnalyticSolid solid = wedge(n1, n2, e);
    const double r = 3e-3, d = 0.6e-3;
    test::FollowRig rig(kCell, kNodes, plain(r), solid, 0);
    const auto at = [&](double phi) { return e + (r - d) * (std::cos(phi) * n1 + std::sin(phi) * b); };
    for (double out = 3.0 * kCell; out > 0.0; out -= 0.1 * kCell) (void)rig.tick(at(0.0) + out * n1);
    double worst_force = 0.0, worst_angle = 0.0, worst_surface = 0.0;
    const int steps = 400;
    for (int i = 0; i <= steps; ++i) {
        const double phi = turn * i / steps;
        const ContactResult c = rig.tick(at(phi));
        const Vec3 radial = std::cos(phi) * n1 + std::sin(phi) * b;
        worst_force = std::max(worst_force, glm::length(c.force_n - kK * d * radial) / (kK * d));
        worst_angle = std::max(worst_angle, glm::degrees(std::acos(std::min(1.0, glm::dot(glm::normalize(c.force_n), radial)))));
        worst_surface = std::max(worst_surface, std::abs(solid.sdf(c.proxy_m) - r) / kCell);
    }
    std::printf("[analytic] ball rolled over a tilted convex edge (d %.2f cells, %d ticks): force error %.3f %%, "
                "direction %.3f deg, proxy %.4f cells off the grown surface\n",
                d / kCell, steps + 1, 100.0 * worst_force, worst_angle, worst_surface);
    EXPECT_LE(worst_force, 0.01);
    EXPECT_LE(worst_surface, 0.1);
}

// The octant x < 40.3 mm, y < 35.4 mm, z < 30.2 mm: three faces meeting in a convex corner.
test::AnalyticSolid octant(const Vec3& corner) {
    const test::RayFn f[3] = {test::half_space_rays(Vec3(1, 0, 0), corner.x, kCell, kNodes),
                              test::half_space_rays(Vec3(0, 1, 0), corner.y, kCell, kNodes),
                              test::half_space_rays(Vec3(0, 0, 1), corner.z, kCell, kNodes)};
    return {[=](int a, int u, int v) {
                float lo = -1e30f, hi = 1e30f;
                for (const test::RayFn& g : f) {
                    const test::Intervals p = g(a, u, v);
                    if (p.empty()) return test::Intervals{};
                    lo = std::max(lo, p[0].first);
                    hi = std::min(hi, p[0].second);
                }
                return hi > lo ? test::Intervals{{lo, hi}} : test::Intervals{};
            },
            [=](const Vec3& x) {
                const Vec3 d = x - corner;
                if (d.x <= 0.0 && d.y <= 0.0 && d.z <= 0.0) return std::max(d.x, std::max(d.y, d.z));
                return glm::length(glm::max(d, Vec3(0.0)));
            }};
}

TEST(ContactAnalytic, BallPressedOntoAConvexCorner) {
    const Vec3 corner(40.3e-3, 35.4e-3, 30.2e-3);
    const test::AnalyticSolid solid = octant(corner);
    for (const Vec3& dir : {Vec3(1, 1, 1), Vec3(1, 0.5, 2)})
        for (const double d : {0.3e-3, 1.0e-3})
            check("ball onto a convex corner", press(solid, 3e-3, corner, glm::normalize(dir), d), d);
}

}  // namespace
}  // namespace tridex::haptics
