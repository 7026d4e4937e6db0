// tests/compute/test_workpiece.cpp - fit_to_stock and transformed: exact images of corners, winding
// and volume under mirroring, and refusals.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/primitives.hpp"
#include "compute/model/workpiece.hpp"
#include "core/error.hpp"

using namespace tridex;
using namespace tridex::compute;

TEST(FitToStock, MapsLongestSideAndCentre) {
    const Aabb box{Vec3(1, 2, 3), Vec3(3, 6, 4)};  // 2 x 4 x 1, centre (2, 4, 3.5)
    const Mat4 m = fit_to_stock(box, Vec3(0.5, -0.25, 1.0), 0.2);
    auto map = [&](const Vec3& p) { return Vec3(m * glm::dvec4(p, 1.0)); };
    const Vec3 lo = map(box.lo), hi = map(box.hi), c = map(box.centre());
    EXPECT_NEAR(c.x, 0.5, 1e-15);
    EXPECT_NEAR(c.y, -0.25, 1e-15);
    EXPECT_NEAR(c.z, 1.0, 1e-15);
    EXPECT_NEAR(hi.y - lo.y, 0.2, 1e-15);  // longest side -> stock size
    EXPECT_NEAR(hi.x - lo.x, 0.1, 1e-15);  // scale 0.05 for all axes
    EXPECT_NEAR(hi.z - lo.z, 0.05, 1e-15);
}

TEST(FitToStock, RefusesBadInput) {
    const Aabb box{Vec3(0), Vec3(1)};
    EXPECT_THROW(fit_to_stock(Aabb{}, Vec3(0), 0.1), Error);
    EXPECT_THROW(fit_to_stock(Aabb{Vec3(1), Vec3(1)}, Vec3(0), 0.1), Error);  // a point
    EXPECT_THROW(fit_to_stock(box, Vec3(0), 0.0), Error);
    EXPECT_THROW(fit_to_stock(box, Vec3(0), -1.0), Error);
    EXPECT_THROW(fit_to_stock(box, Vec3(0), NAN), Error);
    EXPECT_THROW(fit_to_stock(box, Vec3(NAN, 0, 0), 0.1), Error);
}

TEST(Transformed, KeepsOutwardWindingUnderMirror) {
    const TriMesh cube = box_mesh(Aabb{Vec3(0), Vec3(1, 2, 3)});
    ASSERT_DOUBLE_EQ(signed_volume(cube), 6.0);
    const Mat4 mirror = glm::scale(Mat4(1.0), Vec3(-2.0, 1.0, 1.0));  // det -2
    const TriMesh m = transformed(cube, mirror);
    EXPECT_DOUBLE_EQ(signed_volume(m), 12.0);
    EXPECT_EQ(edge_stats(m).misoriented_edges, 0u);
    EXPECT_DOUBLE_EQ(m.positions[1].x, -2.0);  // corner (1, 0, 0)
    const Mat4 move = glm::translate(Mat4(1.0), Vec3(5, 6, 7)) * glm::mat4_cast(glm::angleAxis(1.1, glm::normalize(Vec3(1, 1, 0))));
    EXPECT_NEAR(signed_volume(transformed(cube, move)), 6.0, 1e-12);
}

TEST(Transformed, RefusesSingularOrProjective) {
    const TriMesh cube = box_mesh(Aabb{Vec3(0), Vec3(1)});
    EXPECT_THROW(transformed(cube, glm::scale(Mat4(1.0), Vec3(1, 0, 1))), Error);
    Mat4 proj(1.0);
    proj[2][3] = -1.0;
    EXPECT_THROW(transformed(cube, proj), Error);
    Mat4 bad(1.0);
    bad[3][0] = INFINITY;
    EXPECT_THROW(transformed(cube, bad), Error);
}

TEST(Primitives, BoxAndIcosphereAreClosedAndOutward) {
    const TriMesh box = box_mesh(Aabb{Vec3(-1), Vec3(1, 2, 3)});
    EXPECT_EQ(edge_stats(box).boundary_edges + edge_stats(box).misoriented_edges, 0u);
    EXPECT_DOUBLE_EQ(signed_volume(box), 2.0 * 3.0 * 4.0);
    const TriMesh s = icosphere_mesh(Vec3(1, 2, 3), 2.0, 3);
    EXPECT_EQ(s.triangles.size(), 20u * 64u);
    EXPECT_EQ(s.positions.size(), 642u);  // 10 * 4^3 + 2
    const EdgeStats st = edge_stats(s);
    EXPECT_EQ(st.boundary_edges + st.nonmanifold_edges + st.misoriented_edges, 0u);
    for (const Vec3& p : s.positions) EXPECT_NEAR(glm::length(p - Vec3(1, 2, 3)), 2.0, 1e-12);
    const double v = signed_volume(s), ball = 4.0 / 3.0 * M_PI * 8.0;
    EXPECT_LT(v, ball);  // inscribed
    EXPECT_GT(v, 0.98 * ball);
    EXPECT_THROW(box_mesh(Aabb{Vec3(0), Vec3(1, 0, 1)}), Error);
    EXPECT_THROW(icosphere_mesh(Vec3(0), 0.0, 2), Error);
    EXPECT_THROW(icosphere_mesh(Vec3(0), 1.0, 8), Error);
}
