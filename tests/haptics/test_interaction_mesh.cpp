// Tests of haptics/interaction_mesh and MultiPointRenderer in kInteractionMesh mode (Popescu, Burdea,
// Bouzit 3.1-3.2): the unit step, the 1/cos(q) gain, and where the mesh differs from one HIP.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "haptics/forces/interaction_mesh.hpp"
#include "haptics/multipoint.hpp"
#include "haptics/tool_points.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

constexpr double kKp = 700.0;   // N/m
constexpr double kDt = 1e-3;    // s
constexpr double kH = 1e-3;     // cell, m
constexpr float kC = 10.25f;    // plane z = 10.25 mm (solid below, outward normal +z)
constexpr double kTolN = 1e-9;  // N

double deg(double d) { return d * std::numbers::pi / 180.0; }

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(InteractionMesh, PointForceHasAUnitStep) {
    const Vec3 n = glm::normalize(Vec3(0, -1, 2));
    expect_vec(mesh_point_force(kKp, 2e-3, n), 1.4 * n, 1e-15);
    expect_vec(mesh_point_force(kKp, 0.0, n), Vec3(0.0), 0.0);
    expect_vec(mesh_point_force(kKp, -1e-3, n), Vec3(0.0), 0.0);
    expect_vec(mesh_point_force(kKp, NAN, n), Vec3(0.0), 0.0);
    expect_vec(mesh_point_force(kKp, 1e-3, Vec3(NAN, 0, 1)), Vec3(0.0), 0.0);
}

TEST(InteractionMesh, DisplayedForceDividesByCosQ) {
    const Vec3 up(0, 0, 1);
    const Vec3 tilted(0, -std::sin(deg(30)), std::cos(deg(30)));
    MeshForce m = display_mesh_force(1.4 * tilted, 3.0 * up);  // contact normal length is irrelevant
    EXPECT_NEAR(m.cos_q, std::cos(deg(30)), 1e-15);
    EXPECT_NEAR(m.gain, 1.0 / std::cos(deg(30)), 1e-12);
    EXPECT_NEAR(glm::dot(m.displayed_n, up), 1.4, 1e-12);  // normal part restored to |sum|
    // Past the floor (q = 80 deg, cos 0.174 < 0.2) the gain stays at 5.
    const Vec3 steep(0, -std::sin(deg(80)), std::cos(deg(80)));
    m = display_mesh_force(1.4 * steep, up);
    EXPECT_NEAR(m.gain, 1.0 / kMinCosQ, 0.0);
    expect_vec(m.displayed_n, 7.0 * steep, 1e-12);
    // The sum pointing into the material (q = 120 deg): nothing displayed.
    m = display_mesh_force(Vec3(0, -std::sin(deg(120)), std::cos(deg(120))), up);
    EXPECT_NEAR(m.cos_q, -0.5, 1e-12);
    EXPECT_EQ(m.gain, 0.0);
    expect_vec(m.displayed_n, Vec3(0.0), 0.0);
    // No contact, non-finite input: zero, cos q = 1.
    m = display_mesh_force(Vec3(0.0), up);
    EXPECT_EQ(m.cos_q, 1.0);
    expect_vec(m.displayed_n, Vec3(0.0), 0.0);
    m = display_mesh_force(Vec3(NAN, 0, 1), up);
    EXPECT_EQ(m.gain, 0.0);
    expect_vec(m.displayed_n, Vec3(0.0), 0.0);
}

// One mesh point at the tool centre whose outward tool normal is -z in the tool frame (it faces the plane
// when the tool is upright) against one HIP at the same place: same depth 2 mm, tool tilted by q about x.
// One HIP: F = (0, 0, 1.4) N whatever the tilt (the point has no orientation).
// Mesh: F_m = k*d*N_m leans with the tool (|F_m| = 1.4 N, normal part 1.4*cos q); F_displayed = F_m/cos q
// keeps the normal part at k*d = 1.4 N and adds a tangential part -1.4*tan q along y:
//   q = 0: (0, 0, 1.4); q = 30: (0, -0.8083, 1.4); q = 60: (0, -2.4249, 1.4);
//   q = 80 (cos q < 0.2, gain held at 5): (0, -6.8937, 1.2155); q = 120 (N_m points into the solid): 0.
TEST(InteractionMesh, DiffersFromOneHipForATiltedContact) {
    const auto s = test::z_plane(kH, kC);
    ToolPoints one;
    one.count = 1;
    one.normal[0] = Vec3(0, 0, -1);
    const ContactParams p{kKp, 0.0, 0.0};
    struct Row {
        double q_deg;
        Vec3 mesh_n;
    };
    const double t30 = std::tan(deg(30)), t60 = std::tan(deg(60));
    const Row rows[] = {{0, Vec3(0, 0, 1.4)},
                        {30, Vec3(0, -1.4 * t30, 1.4)},
                        {60, Vec3(0, -1.4 * t60, 1.4)},
                        {80, 7.0 * Vec3(0, -std::sin(deg(80)), std::cos(deg(80)))},
                        {120, Vec3(0.0)}};
    for (const Row& row : rows) {
        MultiPointRenderer mesh(one, p, MultiPointMode::kInteractionMesh);
        MultiPointRenderer hip(ToolPoints::single(0.0), p);
        Pose tool;
        tool.orientation = rotation_from_axis_angle(Vec3(1, 0, 0), deg(row.q_deg));
        tool.position = Vec3(10.3e-3, 12.7e-3, 12e-3);
        mesh.update(*s, tool, kDt);
        hip.update(*s, tool, kDt);
        tool.position.z = 8.25e-3;  // 2 mm below the plane
        const MultiPointResult& m = mesh.update(*s, tool, kDt);
        const MultiPointResult& h = hip.update(*s, tool, kDt);
        SCOPED_TRACE(row.q_deg);
        ASSERT_EQ(m.in_contact, 1);
        EXPECT_NEAR(m.point[0].depth_m, 2e-3, 1e-12);
        expect_vec(h.wrench.force_n, Vec3(0, 0, 1.4), kTolN);
        expect_vec(m.wrench.force_n, row.mesh_n, kTolN);
        EXPECT_NEAR(m.cos_q, std::cos(deg(row.q_deg)), 1e-12);
        std::printf("q = %5.1f deg: one HIP F = (%.4f, %.4f, %.4f) N, mesh F_displayed = (%.4f, %.4f, %.4f) N\n",
                    row.q_deg, h.wrench.force_n.x, h.wrench.force_n.y, h.wrench.force_n.z, m.wrench.force_n.x,
                    m.wrench.force_n.y, m.wrench.force_n.z);
    }
}

TEST(InteractionMesh, TorqueGetsTheSameGain) {
    // A mesh point 10 mm along tool x, tilted 30 deg about x (which leaves r = (0.01, 0, 0)):
    // tau = r x F_m / cos q with F_m = 1.4*N, N = (0, -sin 30, cos 30).
    const auto s = test::z_plane(kH, kC);
    ToolPoints off;
    off.count = 1;
    off.local_m[0] = Vec3(10e-3, 0, 0);
    off.normal[0] = Vec3(0, 0, -1);
    MultiPointRenderer mesh(off, ContactParams{kKp, 0.0, 0.0}, MultiPointMode::kInteractionMesh);
    Pose tool;
    tool.orientation = rotation_from_axis_angle(Vec3(1, 0, 0), deg(30));
    tool.position = Vec3(5e-3, 12.7e-3, 12e-3);
    mesh.update(*s, tool, kDt);
    tool.position.z = 8.25e-3;
    const MultiPointResult& m = mesh.update(*s, tool, kDt);
    ASSERT_EQ(m.in_contact, 1);
    const Vec3 n(0, -std::sin(deg(30)), std::cos(deg(30)));
    expect_vec(m.wrench.torque_nm, glm::cross(Vec3(10e-3, 0, 0), 1.4 * n) / std::cos(deg(30)), 1e-12);
    expect_vec(m.point[0].force_n, 1.4 * n, kTolN);  // the point's own F_m, before the gain
}

// A ball mesh (radius 5 mm) with its centre 3 mm above the plane, i.e. the ball 2 mm deep, in two
// orientations. One ball HIP (ToolPoints::single(5 mm)) gives 1.4 N along +z in both. The mesh samples the
// ball at its points only: the expected sum is computed here point by point from the geometry
// (d_m = plane - p_m.z, F_m = k*d_m*(-R*n_m)), so it changes with the orientation; radial normals make the
// torque zero.
TEST(InteractionMesh, BallMeshDependsOnOrientationOneHipDoesNot) {
    const auto s = test::z_plane(kH, kC);
    const double r = 5e-3;
    const ToolPoints ball = ToolPoints::sphere_mesh(r, 64);
    const ContactParams p{kKp, 0.0, 0.0};
    const double plane = kC * kH;
    Vec3 forces[2];
    const Quat orientations[2] = {Quat(1, 0, 0, 0), rotation_from_axis_angle(Vec3(1, 2, 3), 0.9)};
    for (int k = 0; k < 2; ++k) {
        MultiPointRenderer mesh(ball, p, MultiPointMode::kInteractionMesh);
        MultiPointRenderer hip(ToolPoints::single(r), p);
        Pose tool;
        tool.orientation = orientations[k];
        // Lowered from 8 mm to 3 mm above the plane in 0.25 mm steps (0.25 m/s at 1 kHz).
        for (int step = 0; step < 20; ++step) {
            tool.position = Vec3(15.3e-3, 14.6e-3, plane + 8e-3 - 0.25e-3 * step);
            mesh.update(*s, tool, kDt);
            hip.update(*s, tool, kDt);
        }
        tool.position.z = plane + 3e-3;
        const MultiPointResult& m = mesh.update(*s, tool, kDt);
        const MultiPointResult& h = hip.update(*s, tool, kDt);
        expect_vec(h.wrench.force_n, Vec3(0, 0, 1.4), kTolN);
        Vec3 sum(0.0);
        int touching = 0;
        for (int i = 0; i < ball.count; ++i) {
            const Vec3 pw = tool.orientation * ball.local_m[i] + tool.position;
            const double d = plane - pw.z;
            if (d > 0) {
                sum += kKp * d * -(tool.orientation * ball.normal[i]);
                ++touching;
            }
        }
        ASSERT_GT(touching, 0);
        EXPECT_EQ(m.in_contact, touching);
        const double cos_q = sum.z / glm::length(sum);
        expect_vec(m.wrench.force_n, sum / std::max(cos_q, kMinCosQ), kTolN);
        expect_vec(m.wrench.torque_nm, Vec3(0.0), 1e-12);
        forces[k] = m.wrench.force_n;
        std::printf("ball mesh, orientation %d: %d of 64 points touch, F_displayed = (%.4f, %.4f, %.4f) N, "
                    "cos q = %.4f; one ball HIP: (0, 0, 1.4) N\n",
                    k, touching, forces[k].x, forces[k].y, forces[k].z, m.cos_q);
    }
    EXPECT_GT(glm::distance(forces[0], forces[1]), 0.01);
}

}  // namespace
}  // namespace tridex::haptics
