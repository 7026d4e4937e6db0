// Tests of compute/contour/contour_qef: crossing normals estimated from neighbouring rays, and the QEF vertex.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "compute/contour/contour_qef.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute::contour {
namespace {

using namespace testing;

/// Half-space below the plane n . p = d (grid units): chord of ray (u, v) of set a within [0, cells].
std::vector<Interval> half_space_chord(const Vec3& n, double d, double cells, int a, int u, int v) {
    const Vec3 p0 = ray_point(a, u, v, 0.0);
    const double na = n[a], rest = glm::dot(n, p0);  // n . p(t) = rest + na * t
    if (na == 0.0) return rest < d ? std::vector<Interval>{{0.0f, static_cast<float>(cells)}} : std::vector<Interval>{};
    const double t = (d - rest) / na;
    const double lo = na > 0.0 ? 0.0 : std::max(0.0, t), hi = na > 0.0 ? std::min(cells, t) : cells;
    if (!(lo < hi)) return {};
    return {Interval{static_cast<float>(lo), static_cast<float>(hi)}};
}

TEST(CrossingNormal, IsTheOutwardNormalOfATiltedPlaneOnEveryRaySet) {
    const Vec3 n = glm::normalize(Vec3(0.3, -0.5, 0.8));
    const double d = glm::dot(n, Vec3(20.2, 19.7, 20.4));
    TriDexel model = empty_model(cube_lattice(40));
    fill_rays(model, [&](int a, int u, int v) { return half_space_chord(n, d, 40.0, a, u, v); });
    for (int a = 0; a < 3; ++a) {
        // A ray of set a through the plane near the lattice centre: its crossing is an exit when n_a > 0.
        Node node{20, 20, 20};
        const auto& ray = model.sets[a].ray(node[(a + 1) % 3], node[(a + 2) % 3]);
        ASSERT_EQ(ray.size(), 1u) << a;
        const bool exit = n[a] > 0.0;
        const double t = exit ? ray[0].exit : ray[0].enter;
        node[a] = static_cast<int>(std::floor(t));
        Vec3 got(0.0);
        if (a == 0) {
            // Seen from X rays the plane's slope along z is 0.8 / 0.3 = 2.7 > kNormalWindow: no normal.
            EXPECT_FALSE(crossing_normal(model, a, node, exit, t, got));
            continue;
        }
        ASSERT_TRUE(crossing_normal(model, a, node, exit, t, got)) << a;
        // Central differences of float depths: the slopes are exact up to float rounding (~4e-6 cells).
        EXPECT_NEAR(got.x, n.x, 1e-5) << a;
        EXPECT_NEAR(got.y, n.y, 1e-5) << a;
        EXPECT_NEAR(got.z, n.z, 1e-5) << a;
        EXPECT_NEAR(glm::length(got), 1.0, 1e-12);
        // Asked as the other kind of end (an enter where the ray exits), no neighbour end matches.
        Vec3 none(7.0);
        EXPECT_FALSE(crossing_normal(model, a, node, !exit, t, none)) << a;
        EXPECT_EQ(none, Vec3(7.0));
    }
}

TEST(CrossingNormal, NoneAtACreaseOneSidedAtAnEdgeAndNeedsBothDirections) {
    // Z rays, a roof: exit depth 10 for x <= 12, rising with slope 1.5 for x > 12 (a crease at x = 12).
    TriDexel model = empty_model(cube_lattice(24));
    fill_rays(model, [&](int a, int u, int v) -> std::vector<Interval> {
        if (a != 2) return {};
        const double top = u <= 12 ? 10.0 : 10.0 + 1.5 * (u - 12);
        (void)v;
        return {Interval{2.0f, static_cast<float>(top)}};
    });
    Vec3 nrm(0.0);
    // At the crease ray x = 12: slopes 0 (left) and 1.5 (right) differ by more than kCentralSlopeTol; the
    // left side is exactly flat, so the crossing lies on that face: its normal, marked as a crease side.
    bool crease = false;
    ASSERT_TRUE(crossing_normal(model, 2, Node{12, 5, 10}, true, 10.0, nrm, &crease));
    EXPECT_TRUE(crease);
    EXPECT_NEAR(nrm.x, 0.0, 1e-12);
    EXPECT_NEAR(nrm.z, 1.0, 1e-12);
    // Beside it (x = 11) both sides are flat.
    ASSERT_TRUE(crossing_normal(model, 2, Node{11, 5, 10}, true, 10.0, nrm));
    EXPECT_NEAR(nrm.x, 0.0, 1e-12);
    EXPECT_NEAR(nrm.z, 1.0, 1e-12);
    // On the slope (x = 16, depth 16): both sides agree, central difference -> normal (-1.5, 0, 1)/|.|.
    ASSERT_TRUE(crossing_normal(model, 2, Node{16, 5, 16}, true, 16.0, nrm, &crease));
    EXPECT_NEAR(nrm.x, -1.5 / std::sqrt(3.25), 1e-12);
    EXPECT_NEAR(nrm.z, 1.0 / std::sqrt(3.25), 1e-12);
    EXPECT_FALSE(crease);
    // A roof with no flat side (slopes -0.75 and 1.5 meeting at x = 12): no normal at the crease.
    fill_rays(model, [&](int a, int u, int v) -> std::vector<Interval> {
        if (a != 2) return {};
        (void)v;
        return {Interval{2.0f, static_cast<float>(u <= 12 ? 10.0 + 0.75 * (u - 12) : 10.0 + 1.5 * (u - 12))}};
    });
    EXPECT_FALSE(crossing_normal(model, 2, Node{12, 5, 10}, true, 10.0, nrm));
    // A step higher than kNormalWindow on one side only (a sharp edge): that side is ignored.
    fill_rays(model, [&](int a, int u, int v) -> std::vector<Interval> {
        if (a != 2) return {};
        (void)v;
        return {Interval{2.0f, u <= 12 ? 10.0f : 13.0f}};
    });
    ASSERT_TRUE(crossing_normal(model, 2, Node{12, 5, 10}, true, 10.0, nrm));
    EXPECT_NEAR(nrm.z, 1.0, 1e-12);
    // A lone ray (no neighbour end within the window in u): no normal.
    fill_rays(model, [&](int a, int u, int v) -> std::vector<Interval> {
        if (a != 2 || u != 12) return {};
        (void)v;
        return {Interval{2.0f, 10.0f}};
    });
    EXPECT_FALSE(crossing_normal(model, 2, Node{12, 5, 10}, true, 10.0, nrm));
    // At the lattice border (u = 0) the one side present is used.
    fill_rays(model, [&](int a, int u, int v) -> std::vector<Interval> {
        if (a != 2) return {};
        (void)v;
        return {Interval{2.0f, static_cast<float>(10.0 + 0.5 * u)}};
    });
    ASSERT_TRUE(crossing_normal(model, 2, Node{0, 5, 10}, true, 10.0, nrm));
    EXPECT_NEAR(nrm.x, -0.5 / std::sqrt(1.25), 1e-12);
    // ... but not a steep one (slope 1.5 > kOneSidedSlopeMax: it may be another sheet's end).
    fill_rays(model, [&](int a, int u, int v) -> std::vector<Interval> {
        if (a != 2) return {};
        (void)v;
        return {Interval{2.0f, static_cast<float>(10.0 + 1.5 * u)}};
    });
    EXPECT_FALSE(crossing_normal(model, 2, Node{0, 5, 10}, true, 10.0, nrm));
    ASSERT_TRUE(crossing_normal(model, 2, Node{1, 5, 11}, true, 11.5, nrm));  // both sides: fine
}

TEST(CrossingNormal, DropsAOneSidedSlopeReadAcrossAGapBetweenTheRays) {
    // Z rays: the crossing's ray x = 12 exits at depth 10, air at x < 12 (a cliff beyond the window), the ray x = 13
    // and beyond exit at 10.8 (a one-sided slope 0.8 <= kOneSidedSlopeMax); flat along y. The X ray through
    // (y = 5, z = 9), the lattice line below both exits, either runs solid from x = 12 to 13 (the same surface) or
    // has an air gap between them (a valley narrower than a cell: x = 13 reads the valley's far wall).
    TriDexel model = empty_model(cube_lattice(24));
    const auto fill = [&](double gap_lo, double gap_hi, bool mirrored) {
        fill_rays(model, [&](int a, int u, int v) -> std::vector<Interval> {
            const int x = mirrored ? 24 - u : u;  // mirrored: the crossing reads its neighbour on the -x side
            if (a == 2) {
                if (x < 12) return {};
                return {Interval{2.0f, x == 12 ? 10.0f : 10.8f}};
            }
            if (a == 0 && u == 5 && v == 9) {
                if (!(gap_lo < gap_hi)) return {Interval{0.0f, 24.0f}};
                const double lo = mirrored ? 24.0 - gap_hi : gap_lo, hi = mirrored ? 24.0 - gap_lo : gap_hi;
                return {Interval{0.0f, static_cast<float>(lo)}, Interval{static_cast<float>(hi), 24.0f}};
            }
            return {};
        });
    };
    for (const bool mirrored : {false, true}) {
        const Node n{12, 5, 10};
        const double sx = mirrored ? 0.8 : -0.8;  // outward normal's x over its z
        Vec3 nrm(0.0);
        fill(0.0, 0.0, mirrored);  // solid between the rays: the slope stands
        ASSERT_TRUE(crossing_normal(model, 2, n, true, 10.0, nrm)) << mirrored;
        EXPECT_NEAR(nrm.x / nrm.z, sx, 1e-6) << mirrored;
        EXPECT_EQ(nrm.y, 0.0) << mirrored;
        fill(12.3, 12.7, mirrored);  // an air valley between them: the far wall's end is not this surface's
        Vec3 none(7.0);
        EXPECT_FALSE(crossing_normal(model, 2, n, true, 10.0, none)) << mirrored;
        EXPECT_EQ(none, Vec3(7.0)) << mirrored;
        fill(11.2, 12.0, mirrored);  // ends at the rays themselves or beyond them do not cut the line between them
        ASSERT_TRUE(crossing_normal(model, 2, n, true, 10.0, nrm)) << mirrored;
        EXPECT_NEAR(nrm.x / nrm.z, sx, 1e-6) << mirrored;
    }
    // Enters (material above): the line is the node at or above the higher enter (half-open occupancy: a node at
    // an enter is inside). A spike hanging down: the ray x = 12 enters at 14, x = 13 at 13.4 (slope -0.6), x < 12
    // air; the X ray through (y = 5, z = 14) decides, the one through z = 15 is not read.
    fill_rays(model, [&](int a, int u, int v) -> std::vector<Interval> {
        if (a == 2) return u < 12 ? std::vector<Interval>{} : std::vector<Interval>{{u == 12 ? 14.0f : 13.4f, 22.0f}};
        if (a == 0 && u == 5 && v == 14) return {Interval{0.0f, 12.5f}, Interval{12.6f, 24.0f}};
        return {};
    });
    Vec3 none(7.0);
    EXPECT_FALSE(crossing_normal(model, 2, Node{12, 5, 14}, false, 14.0, none));
    model.sets[0].ray(5, 14) = {Interval{0.0f, 24.0f}};
    model.sets[0].ray(5, 15) = {Interval{0.0f, 12.5f}, Interval{12.6f, 24.0f}};
    Vec3 nrm(0.0);
    ASSERT_TRUE(crossing_normal(model, 2, Node{12, 5, 14}, false, 14.0, nrm));
    EXPECT_NEAR(nrm.x / nrm.z, 0.6, 1e-6);  // outward (-0.6, 0, -1) / |.|
    EXPECT_LT(nrm.z, 0.0);
}

TEST(QefVertex, FindsCornersAndEdgesAndKeepsTheMassPointAlongFreeDirections) {
    const Vec3 lo(4.0, 5.0, 6.0);
    // Three planes x = 4.9, y = 5.2, z = 6.7 meeting inside the cell: the corner.
    const Vec3 p[3] = {Vec3(4.9, 5.0, 6.0), Vec3(4.0, 5.2, 6.0), Vec3(4.0, 5.0, 6.7)};
    const Vec3 n[3] = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    const Vec3 mass = (p[0] + p[1] + p[2]) / 3.0;
    const Vec3 corner = qef_vertex(mass, p, n, 3, lo);
    EXPECT_NEAR(glm::length(corner - Vec3(4.9, 5.2, 6.7)), 0.0, 1e-12);
    // Two planes: the edge line x = 4.9, y = 5.2; z stays the mass point's.
    const Vec3 edge = qef_vertex(mass, p, n, 2, lo);
    EXPECT_NEAR(glm::length(edge - Vec3(4.9, 5.2, mass.z)), 0.0, 1e-12);
    // Two nearly parallel normals (10 degrees apart): below the truncation, only their mean direction acts.
    const double s = std::sin(0.0873), c = std::cos(0.0873);
    const Vec3 pn[2] = {Vec3(4.5, 5.5, 6.5), Vec3(4.5, 5.5, 6.5)};
    const Vec3 nn[2] = {Vec3(0, 0, 1), Vec3(s, 0, c)};
    const Vec3 flat = qef_vertex(Vec3(4.5, 5.5, 6.2), pn, nn, 2, lo);
    EXPECT_NEAR(flat.y, 5.5, 1e-12);
    EXPECT_GT(flat.z, 6.2);
    // A rotated corner: three orthonormal normals not aligned with the axes.
    const Vec3 u = glm::normalize(Vec3(1, 1, 0)), v = glm::normalize(Vec3(-1, 1, 1)), w = glm::cross(u, v);
    const Vec3 k(4.45, 5.55, 6.35);
    const Vec3 rp[3] = {k + 0.2 * v, k + 0.3 * w, k - 0.25 * u};
    const Vec3 rn[3] = {u, v, w};
    EXPECT_NEAR(glm::length(qef_vertex(Vec3(4.5, 5.5, 6.5), rp, rn, 3, lo) - k), 0.0, 1e-12);
}

TEST(QefVertex, MinimisesOverTheCellAndFallsBackOnlyOnBadInput) {
    const Vec3 lo(0.0);
    const Vec3 p[2] = {Vec3(0.5, 0.5, 0.2), Vec3(0.5, 0.5, 0.9)};
    const Vec3 up[2] = {Vec3(0, 0, 1), Vec3(0, 0, 1)};
    // No normals: the mass point, clamped into the cell.
    EXPECT_EQ(qef_vertex(Vec3(0.5, 1.25, 0.5), p, up, 0, lo), Vec3(0.5, 1.0, 0.5));
    // Parallel planes at z = 0.2 and 0.9: their least-squares plane z = 0.55.
    EXPECT_NEAR(qef_vertex(Vec3(0.5, 0.5, 0.1), p, up, 2, lo).z, 0.55, 1e-12);
    // Planes x = 0.5 and one 40 degrees from it through (1.4, 0.5): their line meets z = const at
    // y = 1.57, outside the cell. Over the cell the QEF is least on the face y = 1, at the x minimising
    // (x - 0.5)^2 + (c x + s - k')^2 with k' = c 1.4 + s 0.5, i.e. x = (0.5 + c (k' - s)) / (1 + c^2); z stays
    // the mass point's (no normal constrains it). Through (1.2, 0.5) the line meets the face at y = 1.33.
    const double c = std::cos(0.698132), sn = std::sin(0.698132);
    const Vec3 tilt[2] = {Vec3(1, 0, 0), Vec3(c, sn, 0.0)};
    const Vec3 m(0.3, 0.4, 0.5);
    for (const double px : {1.4, 1.2}) {
        const Vec3 pts[2] = {Vec3(0.5, 0.5, 0.5), Vec3(px, 0.5, 0.5)};
        const double k = c * px + sn * 0.5;
        const Vec3 got = qef_vertex(m, pts, tilt, 2, lo);
        EXPECT_NEAR(got.x, (0.5 + c * (k - sn)) / (1.0 + c * c), 1e-12) << px;
        EXPECT_EQ(got.y, 1.0) << px;
        EXPECT_EQ(got.z, 0.5) << px;
    }
    // A corner whose free minimiser lies beyond two faces (x = 1.3, y = -0.4): both fixed, z still solved.
    const Vec3 cp[3] = {Vec3(1.3, 0.5, 0.5), Vec3(0.5, -0.4, 0.5), Vec3(0.5, 0.5, 0.7)};
    const Vec3 cn[3] = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    const Vec3 corner = qef_vertex(Vec3(0.5), cp, cn, 3, lo);
    EXPECT_NEAR(glm::length(corner - Vec3(1.0, 0.0, 0.7)), 0.0, 1e-12);
    // NaN normals never leak a NaN vertex.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Vec3 bad[2] = {Vec3(nan, 0, 0), Vec3(0, 0, 1)};
    const Vec3 r = qef_vertex(Vec3(0.5), p, bad, 2, lo);
    EXPECT_TRUE(std::isfinite(r.x) && std::isfinite(r.y) && std::isfinite(r.z));
    EXPECT_EQ(r, Vec3(0.5));
}

TEST(QefVertex, PlacesAThinFinOnItsRidge) {
    // A fin with a 30 degree tip (the material left between two cuts): side normals 150 degrees apart, so
    // the QEF's second eigenvalue is 2 sin^2(15 deg) = 0.134 against 1.866 (ratio 0.072). The ridge runs along
    // y at x = 0.5, z = 0.6; crossings 0.4 cells down each side, so the mass point lies 0.39 cells under the
    // ridge. Keeping that direction puts the vertex on the ridge (exact planes: to rounding).
    const double c = std::cos(0.261799), s = std::sin(0.261799);
    const Vec3 lo(0.0), ridge(0.5, 0.5, 0.6);
    const Vec3 n[4] = {Vec3(-c, 0, s), Vec3(-c, 0, s), Vec3(c, 0, s), Vec3(c, 0, s)};
    const Vec3 down1(-s, 0, -c), down2(s, 0, -c);  // down each side, in its plane
    const Vec3 p[4] = {ridge + 0.4 * down1 - Vec3(0, 0.5, 0), ridge + 0.4 * down1 + Vec3(0, 0.5, 0),
                       ridge + 0.4 * down2 - Vec3(0, 0.5, 0), ridge + 0.4 * down2 + Vec3(0, 0.5, 0)};
    const Vec3 mass = (p[0] + p[1] + p[2] + p[3]) / 4.0;
    QefOutcome o;
    const Vec3 v = qef_vertex(mass, p, n, 4, lo, &o);
    EXPECT_NEAR(glm::length(v - ridge), 0.0, 1e-12);
    EXPECT_TRUE(o.truncated);  // only the ridge direction (y) is free
    EXPECT_FALSE(o.clamped);
    // The same fin with its ridge 0.3 cells above the cell: the vertex is the QEF's least point in the cell,
    // on the top face z = 1 between the two sides (x = 0.5), not the mass point below.
    Vec3 hp[4];
    for (int i = 0; i < 4; ++i) hp[i] = p[i] + Vec3(0, 0, 0.7);
    const Vec3 top = qef_vertex((hp[0] + hp[1] + hp[2] + hp[3]) / 4.0, hp, n, 4, lo, &o);
    EXPECT_NEAR(top.x, 0.5, 1e-12);
    EXPECT_EQ(top.z, 1.0);
    EXPECT_TRUE(o.clamped);
}

TEST(QefVertex, ReportsWhichBranchPlacedTheVertex) {
    const Vec3 lo(4.0, 5.0, 6.0);
    const Vec3 p[3] = {Vec3(4.9, 5.0, 6.0), Vec3(4.0, 5.2, 6.0), Vec3(4.0, 5.0, 6.7)};
    const Vec3 n[3] = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    const Vec3 mass = (p[0] + p[1] + p[2]) / 3.0;
    QefOutcome o;
    qef_vertex(mass, p, n, 3, lo, &o);  // a corner: all three directions, inside the cell
    EXPECT_EQ(o.normals, 3);
    EXPECT_FALSE(o.truncated || o.rejected || o.clamped);
    qef_vertex(mass, p, n, 2, lo, &o);  // an edge: one direction dropped
    EXPECT_EQ(o.normals, 2);
    EXPECT_TRUE(o.truncated);
    EXPECT_FALSE(o.rejected || o.clamped);
    qef_vertex(mass, p, n, 0, lo, &o);  // no normal: the mass point
    EXPECT_EQ(o.normals, 0);
    EXPECT_FALSE(o.truncated || o.rejected || o.clamped);
    // The 40-degree pair of MinimisesOverTheCellAndFallsBackOnlyOnBadInput: minimised on the cell face.
    const Vec3 cell(0.0);
    const Vec3 tilt[2] = {Vec3(1, 0, 0), Vec3(std::cos(0.698132), std::sin(0.698132), 0.0)};
    const Vec3 far_pts[2] = {Vec3(0.5, 0.5, 0.5), Vec3(1.4, 0.5, 0.5)};
    qef_vertex(Vec3(0.3, 0.4, 0.5), far_pts, tilt, 2, cell, &o);
    EXPECT_FALSE(o.rejected);
    EXPECT_TRUE(o.clamped);
    EXPECT_TRUE(o.truncated);  // z is free
    // NaN normals: rejected, never a NaN vertex.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Vec3 bad[2] = {Vec3(nan, 0, 0), Vec3(0, 0, 1)};
    qef_vertex(Vec3(0.5), far_pts, bad, 2, cell, &o);
    EXPECT_TRUE(o.rejected);
}

}  // namespace
}  // namespace tridex::compute::contour
