// Contact against analytic shapes, scan-converted exactly into all three ray sets: a point and a ball pressed into
// a tilted flat face, into a sphere and next to a convex edge at known depths give the spring force k*d along the
// analytic normal within 1 % (force shading, friction, cutting and damping off), and the proxy rests on the
// analytic surface (or the ball's centre at its radius from it) within a tenth of a cell. A ball met by a convex
// edge on its diagonal is measured and printed (not felt yet).
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
    // A ball pressed onto the edge itself along the bisector: the analytic force is k * (r - the centre's distance
    // from the edge line) along the bisector. The ball is sampled at its centre, its contact point and six axis
    // points, none of which reaches into a convex edge met on the diagonal, so this overlap is not felt yet: the
    // figure is printed, and the contact must at least never pull or leave the proxy inside the solid.
    const Vec3 bisector = glm::normalize(Vec3(1, 0, 1));
    const Vec3 edge(40.3e-3, 31.1e-3, 30.2e-3);
    const double r = 3e-3;
    for (const double d : {0.3e-3, 0.8e-3}) {
        const Press p = press(solid, r, edge, bisector, d);
        std::printf("[analytic] ball onto a convex edge, bisector, d %.2f cells: F (%.3f, %.3f, %.3f) N against k*d = "
                    "%.3f N; force error %.1f %%\n",
                    d / kCell, p.last.force_n.x, p.last.force_n.y, p.last.force_n.z, kK * d, 100.0 * p.force_error);
        EXPECT_GE(glm::dot(p.last.force_n, bisector), 0.0);
        EXPECT_GE(solid.sdf(p.last.proxy_m), -0.1 * kCell);
    }
}

}  // namespace
}  // namespace tridex::haptics
