// Accuracy of dual contouring at the creases of flat-end cuts: a box minus flat-bottomed vertical cylinders
// (the swept volume of a flat-end mill plunged to two depths), exact chords, vertex distance to the exact
// solid in cells; and the plane fitted to a cell's crossings that stands in for missing crossing normals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_qef.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

/// A flat-end pocket: the vertical cylinder of radius r about (x, y) = (c.x, c.y), from z = c.z up (grid units).
struct Pocket {
    Vec3 c;
    double r;
};

/// Exact chords of ray (u, v) of set a through the box [lo, hi] minus the pockets (grid units).
std::vector<Interval> pocket_chord(const Vec3& lo, const Vec3& hi, const std::vector<Pocket>& pockets, int a, int u, int v) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    if (u < lo[b] || u > hi[b] || v < lo[c] || v > hi[c]) return {};
    std::vector<std::pair<double, double>> spans{{lo[a], hi[a]}};
    for (const Pocket& p : pockets) {
        double e0 = 0.0, e1 = 0.0;  // the pocket's span along the ray
        Vec3 at(0.0);
        at[b] = u;
        at[c] = v;
        if (a == 2) {
            const double dx = at.x - p.c.x, dy = at.y - p.c.y;
            if (dx * dx + dy * dy >= p.r * p.r) continue;
            e0 = p.c.z;
            e1 = 1e9;
        } else {
            if (at.z < p.c.z) continue;
            const double d = a == 0 ? at.y - p.c.y : at.x - p.c.x;
            if (d * d >= p.r * p.r) continue;
            const double half = std::sqrt(p.r * p.r - d * d), mid = a == 0 ? p.c.x : p.c.y;
            e0 = mid - half;
            e1 = mid + half;
        }
        subtract_span(spans, e0, e1);
    }
    return spans_to_intervals(spans);
}

/// Signed distance to the box minus the pockets (grid units): exact for each piece, CSG max of the box's
/// and the pockets' negated distances.
double pocket_sdf(const Vec3& lo, const Vec3& hi, const std::vector<Pocket>& pockets, const Vec3& p) {
    const Vec3 q = glm::max(lo - p, p - hi);
    double d = std::min(std::max(q.x, std::max(q.y, q.z)), 0.0) + glm::length(glm::max(q, Vec3(0.0)));
    for (const Pocket& k : pockets) {
        const double radial = std::hypot(p.x - k.c.x, p.y - k.c.y) - k.r, below = k.c.z - p.z;
        const double inside = std::min(std::max(radial, below), 0.0) + std::hypot(std::max(radial, 0.0), std::max(below, 0.0));
        d = std::max(d, -inside);
    }
    return d;
}

/// Largest |sdf| (cells) of the contour's vertices; `with_normals` receives the share of crossing-generated
/// dual vertices the QEF placed with at least one normal.
double max_vertex_error(const Vec3& lo, const Vec3& hi, const std::vector<Pocket>& pockets, double& with_normals) {
    TriDexel model = empty_model(cube_lattice(48));
    fill_rays(model, [&](int a, int u, int v) { return pocket_chord(lo, hi, pockets, a, u, v); });
    Contourer contourer(model);
    contourer.update(model);
    const TriMesh m = contourer.mesh();
    const ContourStats st = contourer.stats();
    with_normals = static_cast<double>(st.qef_vertices) / static_cast<double>(st.vertices);
    double worst = 0.0;
    for (const Vec3& w : m.positions) worst = std::max(worst, std::abs(pocket_sdf(lo, hi, pockets, model.lattice.to_grid(w))));
    return worst;
}

TEST(ContourCreases, FlatEndPocketsAtTwoDepthsKeepTheirCreases) {
    // Two overlapping flat-end pockets of radius 3 cells under the top face z = 40 (on the lattice nodes), one
    // 1.3 and one 2.1 cells deep, centres 4.6 cells apart: a top rim (convex), two floors with their wall
    // creases (concave), the step between the floors, and two vertical ridges where the walls meet. Twelve
    // lattice phases of the pockets. Every vertex within the accuracy target of the exact solid.
    double worst = 0.0, least_normals = 1.0;
    for (int i = 0; i < 12; ++i) {
        const double s = 0.083 * i, t = 0.057 * i;
        const std::vector<Pocket> pockets{{Vec3(20.0 + s, 22.0 + t, 40.0 - 1.3 - 0.04 * i), 3.0},
                                          {Vec3(24.6 + s, 23.1 + t, 40.0 - 2.1 + 0.03 * i), 3.0}};
        double share = 0.0;
        worst = std::max(worst, max_vertex_error(Vec3(8.0), Vec3(40.0), pockets, share));
        least_normals = std::min(least_normals, share);
    }
    std::printf("flat-end pockets: max vertex error %.3f cells, vertices placed with normals >= %.3f\n", worst, least_normals);
    EXPECT_LE(worst, 0.45);
}

TEST(ContourCreases, FittedNormalIsThePlaneThroughTheCrossingsFacingOut) {
    // Three crossings on the plane x + y + z = 1.5 in the unit cell, one per axis, each leaving material going
    // +axis: the fitted normal is (1, 1, 1) / sqrt(3); entering instead flips it; collinear points give none.
    const Vec3 pts[3] = {Vec3(0.5, 0.0, 1.0), Vec3(0.0, 1.0, 0.5), Vec3(1.0, 0.5, 0.0)};
    const Vec3 mass = (pts[0] + pts[1] + pts[2]) / 3.0;
    const int axes[3] = {0, 1, 2};
    const bool exits[3] = {true, true, true}, enters[3] = {false, false, false};
    Vec3 n(0.0);
    ASSERT_TRUE(contour::fit_normal(mass, pts, axes, exits, 3, n));
    EXPECT_NEAR(n.x, 1.0 / std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(n.y, 1.0 / std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(n.z, 1.0 / std::sqrt(3.0), 1e-12);
    ASSERT_TRUE(contour::fit_normal(mass, pts, axes, enters, 3, n));
    EXPECT_NEAR(n.x, -1.0 / std::sqrt(3.0), 1e-12);
    const Vec3 line[3] = {Vec3(0.0), Vec3(0.5), Vec3(1.0)};
    EXPECT_FALSE(contour::fit_normal(Vec3(0.5), line, axes, exits, 3, n));
    EXPECT_FALSE(contour::fit_normal(mass, pts, axes, exits, 2, n));
}

}  // namespace
}  // namespace tridex::compute
