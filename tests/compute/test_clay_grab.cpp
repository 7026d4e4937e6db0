// Tests of the grab (move) operation on the CPU reference: a whole small sphere grabbed and moved translates (centroid
// by the motion, volume kept), a cap of a large sphere drawn out (volume added), no grip no change, and the two
// bodies fusing where the moved one meets the other.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "clay_test_models.hpp"
#include "compute/tools/clay_grab.hpp"
#include "compute/tools/clay_sweep.hpp"

namespace tridex::compute {
namespace {

using clay_test::clay_sweep;
using clay_test::cube_lattice;
using clay_test::from_implicit;
using clay_test::volume_cells;

/// Centroid (grid units) of the model, the mean of the three sets' (each set's intervals as columns).
std::array<double, 3> centroid(const TriDexel& m) {
    std::array<double, 3> c{0.0, 0.0, 0.0};
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = m.sets[a];
        double v = 0.0, s[3] = {0.0, 0.0, 0.0};
        for (int vv = 0; vv < set.nv; ++vv)
            for (int u = 0; u < set.nu; ++u)
                for (const Interval& iv : set.ray(u, vv)) {
                    const double len = static_cast<double>(iv.exit) - iv.enter;
                    v += len;
                    s[(a + 1) % 3] += len * u;
                    s[(a + 2) % 3] += len * vv;
                    s[a] += len * 0.5 * (static_cast<double>(iv.exit) + iv.enter);
                }
        for (int k = 0; k < 3; ++k) c[k] += s[k] / v / 3.0;
    }
    return c;
}

clay_test::Implicit sphere(double cx, double cy, double cz, double rho) {
    return [=](double x, double y, double z) {
        return std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz)) - rho;
    };
}

/// Moves the ball from p to `to` in segments of at most `step` cells, op grab; p ends at `to`.
void grab_to(TriDexel& m, Vec3& p, const Vec3& to, double R, double step = 0.25) {
    const int n = std::max(1, static_cast<int>(std::ceil(glm::length(to - p) / step)));
    const Vec3 from = p;
    for (int k = 1; k <= n; ++k) {
        const Vec3 q = from + (to - from) * (static_cast<double>(k) / n);
        apply_clay(m, clay_sweep(ToolOp::kGrab, p, q, R));
        p = q;
    }
}

TEST(ClayGrab, FalloffIsFlatInTheCoreAndSmoothToZero) {
    EXPECT_EQ(clay_grab_falloff(0.0f, 8.0f, 16.0f), 1.0f);
    EXPECT_EQ(clay_grab_falloff(8.0f, 8.0f, 16.0f), 1.0f);
    EXPECT_NEAR(clay_grab_falloff(12.0f, 8.0f, 16.0f), 0.5625f, 1e-6f);
    EXPECT_LT(clay_grab_falloff(15.9f, 8.0f, 16.0f), 1e-3f);
    EXPECT_EQ(clay_grab_falloff(16.0f, 8.0f, 16.0f), 0.0f);
}

TEST(ClayGrab, AWholeSphereMovesByTheGrabbedDistance) {
    // A sphere of radius 3.5 cells; a ball of R = 4 touching its top grips it at the top: the whole sphere lies within
    // the core (2R = 8 cells) of the grabbed point.
    const double R = 4.0, rho = 3.5;
    const Vec3 c0(22.3, 24.2, 22.4);
    TriDexel m = from_implicit(cube_lattice(64), sphere(c0.x, c0.y, c0.z, rho));
    const double v0 = volume_cells(m);
    const std::array<double, 3> g0 = centroid(m);
    Vec3 p = c0 + Vec3(0.0, 0.0, rho + R);
    const Vec3 D(9.0, -3.0, 6.0);
    const auto t0 = std::chrono::steady_clock::now();
    grab_to(m, p, p + D, R);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::printf("grab stroke: %.2f ms per 0.25-cell sweep (R %.0f cells, one thread)\n", ms / 45.0, R);
    const std::array<double, 3> g1 = centroid(m);
    const double v1 = volume_cells(m);
    double err = 0.0;
    for (int k = 0; k < 3; ++k) err = std::max(err, std::fabs(g1[k] - g0[k] - D[k]));
    std::printf("grab whole sphere (rho %.1f, R %.1f) by (%.1f, %.1f, %.1f) = %.2f cells: centroid moved (%.3f, %.3f, "
                "%.3f), error %.3f cells; volume %.1f -> %.1f cells^3 (%.2f%%)\n",
                rho, R, D.x, D.y, D.z, glm::length(D), g1[0] - g0[0], g1[1] - g0[1], g1[2] - g0[2], err, v0, v1,
                100.0 * (v1 - v0) / v0);
    EXPECT_LT(err, 0.1);
    EXPECT_LT(std::fabs(v1 - v0) / v0, 0.01);
}

TEST(ClayGrab, OneLongSweepGoesInStepsAndKeepsTheGrip) {
    // The same grab as one sweep of 11 cells (a jump of the hand): in steps, the sphere still follows all the way.
    const double R = 4.0, rho = 3.5;
    const Vec3 c0(22.3, 24.2, 22.4);
    TriDexel m = from_implicit(cube_lattice(64), sphere(c0.x, c0.y, c0.z, rho));
    const double v0 = volume_cells(m);
    const std::array<double, 3> g0 = centroid(m);
    const Vec3 p = c0 + Vec3(0.0, 0.0, rho + R), D(9.0, -3.0, 6.0);
    apply_clay(m, clay_sweep(ToolOp::kGrab, p, p + D, R));
    const std::array<double, 3> g1 = centroid(m);
    double err = 0.0;
    for (int k = 0; k < 3; ++k) err = std::max(err, std::fabs(g1[k] - g0[k] - D[k]));
    std::printf("grab whole sphere in one sweep: centroid error %.3f cells, volume %+.2f%%\n", err,
                100.0 * (volume_cells(m) - v0) / v0);
    EXPECT_LT(err, 0.1);
    EXPECT_LT(std::fabs(volume_cells(m) - v0) / v0, 0.01);
}

TEST(ClayGrab, ACapDrawnOutOfALargeSphereRisesAndAddsVolume) {
    const double R = 3.0, rho = 14.0;
    TriDexel m = from_implicit(cube_lattice(64), sphere(32.0, 32.0, 24.0, rho));
    const TriDexel start = m;
    const double v0 = volume_cells(m);
    Vec3 p(32.2, 31.9, 24.0 + rho + R);
    grab_to(m, p, p + Vec3(0.0, 0.0, 6.0), R);
    const float top = m.sets[2].ray(32, 32).back().exit;
    const double v1 = volume_cells(m);
    std::printf("grab a cap 6 cells out of a sphere of radius %.0f (R %.0f): top %.2f cells higher, volume %+.1f "
                "cells^3 (%+.2f%%)\n",
                rho, R, top - (24.0 + rho), v1 - v0, 100.0 * (v1 - v0) / v0);
    EXPECT_NEAR(top, 24.0 + rho + 6.0, 0.5);
    EXPECT_GT(v1, v0);
    // Beyond the radius of influence (4R from the grabbed point) nothing moved: the bottom half, bit for bit.
    for (int j = 0; j <= 64; ++j)
        for (int i = 0; i <= 64; ++i) {
            const auto& a = m.sets[2].ray(i, j);
            const auto& b = start.sets[2].ray(i, j);
            ASSERT_EQ(a.size(), b.size());
            if (!a.empty()) {
                EXPECT_EQ(a.front().enter, b.front().enter) << i << "," << j;
            }
        }
}

TEST(ClayGrab, NoGripOrNoMotionChangesNothing) {
    const double R = 3.0, rho = 10.0;
    TriDexel m = from_implicit(cube_lattice(48), sphere(24.0, 24.0, 20.0, rho));
    const Vec3 touch(24.0, 24.0, 20.0 + rho + R);
    EXPECT_EQ(apply_clay(m, clay_sweep(ToolOp::kGrab, touch, touch, R)).rays.rays_changed, 0u);
    const Vec3 above = touch + Vec3(0.0, 0.0, 1.0);
    EXPECT_EQ(apply_clay(m, clay_sweep(ToolOp::kGrab, above, above + Vec3(0.0, 0.0, 1.0), R)).rays.rays_changed, 0u);
    EXPECT_GT(apply_clay(m, clay_sweep(ToolOp::kGrab, touch, touch + Vec3(0.0, 0.0, 1.0), R)).rays.rays_changed, 0u);
}

TEST(ClayGrab, ABodyInTheWayIsPushedAheadNotPenetrated) {
    // A small sphere grabbed and carried down towards a slab below it: the slab's top lies within the radius of
    // influence, so it gives way ahead of the sphere (a dent), and the gap between them narrows but stays open.
    const double R = 4.0, rho = 3.0, top0 = 18.3;
    TriDexel m = from_implicit(cube_lattice(48), [&](double x, double y, double z) {
        const double s = std::sqrt((x - 24.0) * (x - 24.0) + (y - 24.0) * (y - 24.0) + (z - 30.0) * (z - 30.0)) - rho;
        const double slab = std::max({6.4 - x, x - 41.6, 6.4 - y, y - 41.6, 6.4 - z, z - top0});
        return std::min(s, slab);
    });
    ASSERT_EQ(m.sets[2].ray(24, 24).size(), 2u);
    const double v0 = volume_cells(m);
    Vec3 p(24.0, 24.0, 30.0 + rho + R);
    grab_to(m, p, p - Vec3(0.0, 0.0, 9.0), R);
    const auto& ray = m.sets[2].ray(24, 24);
    ASSERT_EQ(ray.size(), 2u);
    const double gap = ray[1].enter - ray[0].exit;
    std::printf("sphere carried 9 cells down onto a slab 8.7 cells below: slab top pushed %.2f cells down, gap %.2f "
                "cells, sphere %.2f .. %.2f (expected %.2f .. %.2f), volume %+.2f%%\n",
                top0 - ray[0].exit, gap, ray[1].enter, ray[1].exit, 30.0 - rho - 9.0, 30.0 + rho - 9.0,
                100.0 * (volume_cells(m) - v0) / v0);
    EXPECT_LT(ray[0].exit, top0 - 1.0);  // the slab gave way
    EXPECT_GT(gap, 0.5);                 // and was not penetrated
    // The sphere arrives; squeezing the slab takes volume the single volume correction shares over the field, so the
    // carried sphere is smaller by a fraction of a cell.
    EXPECT_NEAR(ray[1].exit, 30.0 + rho - 9.0, 0.75);
    EXPECT_LT(volume_cells(m), v0);
}

}  // namespace
}  // namespace tridex::compute
