// tests/haptics/test_mesh_tool_points.cpp - contact points over a mesh tool's own surface (Popescu et al. 3.1):
// on the surface with its outward normals, spread evenly, the tip first, deterministic; tool_points_for's
// mesh rules.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "core/primitives.hpp"
#include "haptics/mesh_tool_points.hpp"
#include "haptics/tool_points.hpp"

using namespace tridex;
using namespace tridex::haptics;

TEST(MeshToolPoints, PointsLieOnTheBoxFacesWithTheirOutwardNormals) {
    const Aabb box{Vec3(-0.004, 0.0, -0.002), Vec3(0.004, 0.01, 0.002)};
    const ToolPoints p = mesh_surface_points(box_mesh(box), 32);
    ASSERT_EQ(p.count, 32);
    validate(p, true);
    EXPECT_EQ(p.radius_m, 0.0);
    for (int i = 0; i < p.count; ++i) {
        const Vec3& x = p.local_m[i];
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(x[a], box.lo[a] - 1e-12);
            EXPECT_LE(x[a], box.hi[a] + 1e-12);
        }
        if (i == 0) continue;  // the tip: a corner with its vertex normal
        // On a face: the normal's axis coordinate is on that face's plane.
        int on = 0;
        for (int a = 0; a < 3; ++a) {
            if (std::abs(p.normal[i][a] - 1.0) < 1e-12) on += std::abs(x[a] - box.hi[a]) < 1e-12;
            if (std::abs(p.normal[i][a] + 1.0) < 1e-12) on += std::abs(x[a] - box.lo[a]) < 1e-12;
        }
        EXPECT_EQ(on, 1) << "point " << i;
    }
    // The tip first: a vertex of the lowest face, its normal pointing down.
    EXPECT_NEAR(p.local_m[0].y, 0.0, 1e-15);
    EXPECT_LT(p.normal[0].y, 0.0);
}

TEST(MeshToolPoints, PointsSpreadOverTheWholeSurfaceAndAreDeterministic) {
    const TriMesh ball = icosphere_mesh(Vec3(0.0, 0.005, 0.0), 0.005, 3);
    const ToolPoints a = mesh_surface_points(ball, 64);
    const ToolPoints b = mesh_surface_points(ball, 64);
    double min_d = 1.0;
    Vec3 mean(0.0);
    for (int i = 0; i < a.count; ++i) {
        EXPECT_EQ(a.local_m[i], b.local_m[i]);
        EXPECT_NEAR(glm::length(a.local_m[i] - Vec3(0.0, 0.005, 0.0)), 0.005, 1e-4);  // on the (faceted) sphere
        mean += a.local_m[i] / 64.0;
        for (int j = 0; j < i; ++j) min_d = std::min(min_d, glm::length(a.local_m[i] - a.local_m[j]));
    }
    // 64 points evenly over a sphere of radius 5 mm are about 2.2 mm apart; farthest-point sampling keeps over half.
    EXPECT_GT(min_d, 0.0012);
    EXPECT_LT(glm::length(mean - Vec3(0.0, 0.005, 0.0)), 0.001);
    EXPECT_NEAR(a.local_m[0].y, 0.0, 1e-12);  // the tip
}

TEST(MeshToolPoints, ToolPointsForAMeshToolNeedItsMeshAndAllowedCounts) {
    const TriMesh m = icosphere_mesh(Vec3(0.0), 0.004, 2);
    const ToolShape tool{ToolKind::kMesh, 0.004, 0.0, 0};
    EXPECT_EQ(tool_points_for(tool, 1, "tool", &m).count, 32);
    EXPECT_EQ(tool_points_for(tool, 8, "tool", &m).count, 8);
    EXPECT_EQ(tool_points_for(tool, 64, "tool", &m).count, 64);
    EXPECT_THROW(tool_points_for(tool, 2, "tool", &m), Error);
    EXPECT_THROW(tool_points_for(tool, 7, "tool", &m), Error);
    EXPECT_THROW(tool_points_for(tool, 65, "tool", &m), Error);
    EXPECT_THROW(tool_points_for(tool, 1, "tool"), Error);
    EXPECT_THROW(mesh_surface_points(TriMesh{}, 8), Error);
}
