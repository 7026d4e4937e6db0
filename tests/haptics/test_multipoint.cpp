// Tests of haptics/tool_points and haptics/multipoint (independent proxies): the thesis's cube torque test,
// torque about the tool centre under translation, axis-angle poses, per-point K*x + D*xdot, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "core/error.hpp"
#include "haptics/god_object.hpp"
#include "haptics/multipoint.hpp"
#include "haptics/tool_points.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

using test::fill_set;
using test::Intervals;
using test::make_surface;

constexpr double kH = 4e-3;      // cell, m
constexpr double kKp = 700.0;    // N/m
constexpr double kDt = 1e-3;     // s
constexpr double kL = 40e-3;     // wand half length, m

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

// A solid box lo..hi (grid units along x, y, z) seen by all three ray sets; every window covers lattice
// indices [0, 31] on its two axes, i.e. world [origin, origin + 31 cells] = 124 mm.
std::unique_ptr<ActiveSurface> box_surface(const Vec3& origin_m, const Vec3& lo, const Vec3& hi) {
    auto s = make_surface(kH, origin_m);
    for (int a = 0; a < 3; ++a) {
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        fill_set(*s, a, 0, 0, [&](int u, int v) {
            if (u >= lo[ua] && u <= hi[ua] && v >= lo[va] && v <= hi[va])
                return Intervals{{static_cast<float>(lo[a]), static_cast<float>(hi[a])}};
            return Intervals{};
        });
    }
    return s;
}

// The thesis's cube test (Singapogu ch. 3), our geometry: the wand lies along the tool's +y axis (top point
// (0, +L, 0), bottom (0, -L, 0)), tilted by theta = asin(1/40) about x so the top leans 1 mm further into
// the cube than the centre and the bottom 1 mm less. The cube's face is the plane z = 60 mm with outward
// normal -z (the cube fills x 16..112 mm, z 61..112 mm: the face lies between lattice planes, as a carved
// surface does); the wand pushes along +z into it, so each point
// feels F = -z*K*depth. tau_x = r_y*F_z - r_z*F_y: the top point (r_y > 0) gives a NEGATIVE torque about x,
// the bottom (r_y < 0) a POSITIVE one, as in the thesis. The cube's y extent chooses who touches:
// y 80..120 mm only the top, 8..48 mm only the bottom, 8..120 mm both.
struct CubeCase {
    Vec3 origin_m{0.0};
    double lo_y = 0, hi_y = 0;  // cells
};

const double kTheta = std::asin(1e-3 / kL);

MultiPointResult cube_test(const CubeCase& c) {
    const auto s = box_surface(c.origin_m, Vec3(4, c.lo_y, 15.25), Vec3(28, c.hi_y, 28));
    MultiPointRenderer mp(ToolPoints::wand(kL), ContactParams{kKp, 0.0, 0.0});
    Pose tool;
    tool.orientation = rotation_from_axis_angle(Vec3(1, 0, 0), kTheta);
    tool.position = c.origin_m + Vec3(64e-3, 64e-3, 55e-3);  // both points in front of the face
    EXPECT_EQ(mp.update(*s, tool, kDt).in_contact, 0);
    tool.position = c.origin_m + Vec3(64e-3, 64e-3, 64e-3);  // centre 3 mm in: top 4 mm, bottom 2 mm deep
    return mp.update(*s, tool, kDt);
}

TEST(MultiPoint, ThesisCubeTestTorqueSigns) {
    const double ry = kL * std::cos(kTheta);
    const MultiPointResult top = cube_test({Vec3(0.0), 20, 30});
    ASSERT_EQ(top.points, 2);
    ASSERT_EQ(top.in_contact, 1);
    EXPECT_TRUE(top.point[0].contact);
    EXPECT_FALSE(top.point[1].contact);
    EXPECT_NEAR(top.point[0].depth_m, 4e-3, 1e-12);
    expect_vec(top.wrench.force_n, Vec3(0, 0, -kKp * 4e-3), 1e-9);
    expect_vec(top.wrench.torque_nm, Vec3(-ry * kKp * 4e-3, 0, 0), 1e-12);  // -0.11199 N*m
    EXPECT_LT(top.wrench.torque_nm.x, -0.1);

    const MultiPointResult bottom = cube_test({Vec3(0.0), 2, 12});
    ASSERT_EQ(bottom.in_contact, 1);
    EXPECT_TRUE(bottom.point[1].contact);
    EXPECT_NEAR(bottom.point[1].depth_m, 2e-3, 1e-12);
    expect_vec(bottom.wrench.force_n, Vec3(0, 0, -kKp * 2e-3), 1e-9);
    expect_vec(bottom.wrench.torque_nm, Vec3(ry * kKp * 2e-3, 0, 0), 1e-12);  // +0.05598 N*m
    EXPECT_GT(bottom.wrench.torque_nm.x, 0.05);

    const MultiPointResult both = cube_test({Vec3(0.0), 2, 30});
    ASSERT_EQ(both.in_contact, 2);
    expect_vec(both.wrench.force_n, top.wrench.force_n + bottom.wrench.force_n, 1e-12);
    expect_vec(both.wrench.torque_nm, top.wrench.torque_nm + bottom.wrench.torque_nm, 1e-12);
    EXPECT_NEAR(both.wrench.torque_nm.x, -ry * kKp * 2e-3, 1e-12);  // -0.05598 N*m: the deeper top wins
}

TEST(MultiPoint, TorqueIsAboutTheToolCentreNotTheWorldOrigin) {
    const MultiPointResult here = cube_test({Vec3(0.0), 2, 30});
    const Vec3 offset(12.3, -4.56, 7.89);  // m: move the cube and the wand together
    const MultiPointResult there = cube_test({offset, 2, 30});
    ASSERT_EQ(there.in_contact, 2);
    expect_vec(there.wrench.force_n, here.wrench.force_n, 1e-9);
    expect_vec(there.wrench.torque_nm, here.wrench.torque_nm, 1e-9);
    // A torque about the world origin, sum P_i x F_i, would change by offset x F (about 0.025 N*m here).
    Vec3 about_origin(0.0), about_origin_here(0.0);
    for (int i = 0; i < 2; ++i) {
        about_origin += glm::cross(there.point[i].world_m, there.point[i].force_n);
        about_origin_here += glm::cross(here.point[i].world_m, here.point[i].force_n);
    }
    expect_vec(about_origin - about_origin_here, glm::cross(offset, here.wrench.force_n), 1e-9);
    EXPECT_GT(glm::length(about_origin - about_origin_here), 0.02);
}

TEST(ToolPoints, AxisAngleAndQuaternionPosesAgree) {
    // 90 deg about z maps the top point (0, L, 0) to (-L, 0, 0): P = R*T + P_w.
    Pose tool;
    tool.position = Vec3(1.0, 2.0, 3.0);
    tool.orientation = rotation_from_axis_angle(Vec3(0, 0, 5), std::numbers::pi / 2);  // axis length ignored
    expect_vec(tool_point_world(tool, Vec3(0, kL, 0)), Vec3(1.0 - kL, 2.0, 3.0), 1e-15);
    const Quat q = glm::angleAxis(0.7, glm::normalize(Vec3(1, -2, 0.5)));
    const Quat p = rotation_from_axis_angle(Vec3(2, -4, 1), 0.7);
    EXPECT_NEAR(std::abs(glm::dot(p, q)), 1.0, 1e-15);
    tool.orientation = q;
    const Vec3 t(0.01, -0.02, 0.03);
    expect_vec(tool_point_world(tool, t), q * t + tool.position, 0.0);
    EXPECT_THROW(rotation_from_axis_angle(Vec3(0.0), 1.0), Error);
    EXPECT_THROW(rotation_from_axis_angle(Vec3(NAN, 0, 1), 1.0), Error);
    EXPECT_THROW(rotation_from_axis_angle(Vec3(0, 0, 1), INFINITY), Error);
}

TEST(ToolPoints, FactoriesAndSphereMeshSpread) {
    const ToolPoints one = ToolPoints::single(3e-3);
    EXPECT_EQ(one.count, 1);
    EXPECT_EQ(one.radius_m, 3e-3);
    expect_vec(one.local_m[0], Vec3(0.0), 0.0);
    const ToolPoints w = ToolPoints::wand(kL);
    EXPECT_EQ(w.count, 2);
    expect_vec(w.local_m[0], Vec3(0, kL, 0), 0.0);
    expect_vec(w.local_m[1], Vec3(0, -kL, 0), 0.0);
    for (int n : {16, 64}) {
        const double r = 5e-3;
        const ToolPoints m = ToolPoints::sphere_mesh(r, n);
        ASSERT_EQ(m.count, n);
        double min_gap = 1e9, sum_z = 0;
        for (int i = 0; i < n; ++i) {
            EXPECT_NEAR(glm::length(m.local_m[i]), r, 1e-15);
            EXPECT_NEAR(glm::length(m.normal[i]), 1.0, 1e-15);
            expect_vec(m.local_m[i], r * m.normal[i], 0.0);
            sum_z += m.normal[i].z;
            for (int j = i + 1; j < n; ++j) min_gap = std::min(min_gap, glm::distance(m.normal[i], m.normal[j]));
        }
        EXPECT_NEAR(sum_z, 0.0, 1e-12);              // z_i = 1 - (2i+1)/n is symmetric
        EXPECT_GT(min_gap * std::sqrt(n), 3.0);      // Fibonacci spiral: about 3.09 / sqrt(n) on a unit sphere
    }
    EXPECT_THROW(ToolPoints::single(-1e-3), Error);
    EXPECT_THROW(ToolPoints::wand(0.0), Error);
    EXPECT_THROW(ToolPoints::sphere_mesh(5e-3, 0), Error);
    EXPECT_THROW(ToolPoints::sphere_mesh(5e-3, kMaxToolPoints + 1), Error);
    EXPECT_THROW(ToolPoints::sphere_mesh(NAN, 8), Error);
}

TEST(MultiPoint, RejectsBadToolPoints) {
    const ContactParams p{kKp, 0.0, 0.0};
    ToolPoints t = ToolPoints::wand(kL);
    t.count = 0;
    EXPECT_THROW(MultiPointRenderer(t, p), Error);
    t.count = kMaxToolPoints + 1;
    EXPECT_THROW(MultiPointRenderer(t, p), Error);
    t = ToolPoints::wand(kL);
    t.local_m[1].x = NAN;
    EXPECT_THROW(MultiPointRenderer(t, p), Error);
    t = ToolPoints::wand(kL);
    t.normal[0] = Vec3(0, 2, 0);
    EXPECT_THROW(MultiPointRenderer(t, p), Error);
    t = ToolPoints::wand(kL);
    t.radius_m = -1.0;
    EXPECT_THROW(MultiPointRenderer(t, p), Error);
    // The interaction mesh needs a unit normal on every point; the single centre point has none.
    EXPECT_THROW(MultiPointRenderer(ToolPoints::single(0.0), p, MultiPointMode::kInteractionMesh), Error);
    EXPECT_NO_THROW(MultiPointRenderer(ToolPoints::single(0.0), p, MultiPointMode::kIndependentProxies));
    EXPECT_THROW(MultiPointRenderer(ToolPoints::wand(kL), ContactParams{-1.0, 0.0, 0.0}), Error);
}

TEST(MultiPoint, SinglePointMatchesOneGodObjectWithSpringAndDamper) {
    // F = K*x + D*xdot per point (thesis ch. 3) is the god-object's force; one centre point = one HIP.
    const auto s = test::z_plane(1e-3, 10.25f);  // solid below z = 10.25 mm, normal +z
    const ContactParams p{kKp, 2.0, 0.0};
    const double r = 1.5e-3;
    MultiPointRenderer mp(ToolPoints::single(r), p);
    GodObject g(ContactParams{kKp, 2.0, r});  // ToolPoints::radius_m replaces params.tool_radius_m
    Pose tool;
    tool.orientation = rotation_from_axis_angle(Vec3(0.3, 1, 0), 0.4);  // orientation is irrelevant here
    const double zs[] = {14.0e-3, 11.0e-3, 10.5e-3, 10.5e-3, 12.0e-3};
    for (double z : zs) {
        tool.position = Vec3(9.7e-3, 12.1e-3, z);
        const MultiPointResult& m = mp.update(*s, tool, kDt);
        const ContactResult c = g.update(*s, tool.position, kDt);
        EXPECT_EQ(m.in_contact, c.contact ? 1 : 0);
        expect_vec(m.wrench.force_n, c.force_n, 0.0);
        expect_vec(m.wrench.torque_nm, Vec3(0.0), 0.0);
        expect_vec(m.point[0].proxy_m, c.proxy_m, 0.0);
    }
    // The analytic value at the third tick: depth 1.25 mm after 0.75 mm, F = 700*1.25e-3 + 2*0.5 = 1.875 N.
    MultiPointRenderer again(ToolPoints::single(r), p);
    for (double z : {14.0e-3, 11.0e-3}) {
        tool.position = Vec3(9.7e-3, 12.1e-3, z);
        again.update(*s, tool, kDt);
    }
    tool.position = Vec3(9.7e-3, 12.1e-3, 10.5e-3);
    expect_vec(again.update(*s, tool, kDt).wrench.force_n, Vec3(0, 0, 1.875), 1e-9);
}

TEST(MultiPoint, NonFinitePoseResetsEveryPoint) {
    const auto s = box_surface(Vec3(0.0), Vec3(4, 2, 15.25), Vec3(28, 30, 28));
    MultiPointRenderer mp(ToolPoints::wand(kL), ContactParams{kKp, 0.0, 0.0});
    Pose tool;
    tool.position = Vec3(64e-3, 64e-3, 55e-3);
    mp.update(*s, tool, kDt);
    tool.position.z = 63e-3;
    ASSERT_EQ(mp.update(*s, tool, kDt).in_contact, 2);
    Pose bad = tool;
    bad.orientation.x = NAN;
    const MultiPointResult& r = mp.update(*s, bad, kDt);
    EXPECT_EQ(r.points, 0);
    EXPECT_EQ(r.in_contact, 0);
    expect_vec(r.wrench.force_n, Vec3(0.0), 0.0);
    expect_vec(r.wrench.torque_nm, Vec3(0.0), 0.0);
    // History is gone: back at the same pose, both points start inside the cube and feel nothing.
    EXPECT_EQ(mp.update(*s, tool, kDt).in_contact, 0);
    bad = tool;
    bad.position.y = INFINITY;
    EXPECT_EQ(mp.update(*s, bad, kDt).points, 0);
}

}  // namespace
}  // namespace tridex::haptics
