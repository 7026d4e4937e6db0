// Tests of renderer/scene/primitive_meshes: closed, outward, analytic volumes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "core/tri_mesh.hpp"
#include "renderer/scene/primitive_meshes.hpp"

namespace tridex::renderer {
namespace {

TEST(PrimitiveMeshes, BoxIsClosedOutwardWithExactVolume) {
    Aabb box;
    box.add(Vec3(-0.5, 0.25, 1.0));
    box.add(Vec3(1.5, 1.25, 1.5));
    const TriMesh m = box_mesh(box);
    EXPECT_EQ(m.triangles.size(), 12u);
    const EdgeStats e = edge_stats(m);
    EXPECT_EQ(e.boundary_edges, 0u);
    EXPECT_EQ(e.nonmanifold_edges, 0u);
    EXPECT_EQ(e.misoriented_edges, 0u);
    EXPECT_NEAR(signed_volume(m), 2.0 * 1.0 * 0.5, 1e-15);
    EXPECT_THROW(box_mesh(Aabb{}), Error);
}

TEST(PrimitiveMeshes, SphereIsClosedOutwardOnTheUnitSphere) {
    const int rings = 12, segments = 20;
    const TriMesh m = unit_sphere(rings, segments);
    EXPECT_EQ(m.triangles.size(), static_cast<std::size_t>(2 * segments * (rings - 1)));
    const EdgeStats e = edge_stats(m);
    EXPECT_EQ(e.boundary_edges, 0u);
    EXPECT_EQ(e.nonmanifold_edges, 0u);
    EXPECT_EQ(e.misoriented_edges, 0u);
    EXPECT_EQ(e.degenerate_triangles, 0u);
    for (const Vec3& p : m.positions) EXPECT_NEAR(glm::length(p), 1.0, 1e-15);
    // Inscribed polyhedron: volume below 4/3 pi, and positive (outward) within 5 % for this resolution.
    const double v = signed_volume(m), ball = 4.0 / 3.0 * std::numbers::pi;
    EXPECT_LT(v, ball);
    EXPECT_GT(v, 0.95 * ball);
    EXPECT_THROW(unit_sphere(1, 8), Error);
    EXPECT_THROW(unit_sphere(4, 2), Error);
}

}  // namespace
}  // namespace tridex::renderer
