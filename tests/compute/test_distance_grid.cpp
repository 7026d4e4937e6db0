// A closed mesh's signed distance grid against analytic shapes: a sphere's |p| - R and a box's distance, in metres
// and in grid cells; the sign agrees with the scan conversion; the trilinear sample and its gradient; bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "compute/contour/surface_distance.hpp"
#include "compute/contour/distance_grid_build.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

namespace tridex::compute {
namespace {

Vec3 node_of(const DistanceGrid& g, int i, int j, int k) { return g.origin_m + g.cell_m * Vec3(i, j, k); }

TEST(DistanceGrid, ASpheresFieldIsItsDistanceWithinTheChordSagAndPropagationIsExactToTheMesh) {
    const double radius = 0.03, cell = 0.001;
    const TriMesh sphere = icosphere_mesh(Vec3(0.0), radius, 5);  // 20480 triangles
    const DistanceGrid g = build_distance_grid(sphere, cell, 0.01, std::size_t{64} << 20);
    ASSERT_TRUE(g.valid());
    EXPECT_EQ(g.nodes[0], 81);  // 60 mm + 2 x 10 mm margin at 1 mm: 80 cells
    // The mesh is inscribed: it lies at most R (1 - cos(edge angle / 2)) inside the sphere.
    const double edge = 0.03 * 1.1071 / 32.0;  // icosahedron edge angle / 2^5, times R
    const double sag = radius * (1.0 - std::cos(edge / radius));
    TriangleGrid exact(sphere, 0.004);
    double worst_analytic = 0.0, worst_mesh = 0.0;
    int wrong_sign = 0;
    for (int k = 0; k < g.nodes[2]; ++k)
        for (int j = 0; j < g.nodes[1]; ++j)
            for (int i = 0; i < g.nodes[0]; ++i) {
                const Vec3 p = node_of(g, i, j, k);
                const double d = g.distance_m[g.index(i, j, k)];
                worst_analytic = std::max(worst_analytic, std::abs(d - (glm::length(p) - radius)));
                if ((i + j + k) % 7 == 0)  // the exact search is slow far from the surface: a seventh of the nodes
                    worst_mesh = std::max(worst_mesh, std::abs(std::abs(d) - exact.distance(p)));
                const double analytic = glm::length(p) - radius;
                if (std::abs(analytic) > 2.0 * sag && (d < 0.0) != (analytic < 0.0)) ++wrong_sign;
            }
    std::printf("sphere R = 30 mm, cell 1 mm: largest error against |p| - R %.3g m (%.3f cells; chord sag %.3g m), "
                "against the mesh's own distance %.3g m (%.4f cells)\n",
                worst_analytic, worst_analytic / cell, sag, worst_mesh, worst_mesh / cell);
    EXPECT_EQ(wrong_sign, 0);
    EXPECT_LT(worst_analytic, sag + 1e-6);
    EXPECT_LT(worst_mesh, 1e-3 * cell);  // the propagated nearest triangle is the nearest, to float rounding
}

TEST(DistanceGrid, ABoxsFieldIsExactAndItsSampleAndGradientFollowTheFaces) {
    const Aabb box{Vec3(-0.02, -0.01, -0.015), Vec3(0.02, 0.01, 0.015)};
    const DistanceGrid g = build_distance_grid(box_mesh(box), 0.0025, 0.01, std::size_t{16} << 20);
    auto box_distance = [&](const Vec3& p) {
        const Vec3 q = glm::abs(p - box.centre()) - 0.5 * box.size();
        const double outside = glm::length(glm::max(q, Vec3(0.0)));
        return outside + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
    };
    double worst = 0.0;
    for (int k = 0; k < g.nodes[2]; ++k)
        for (int j = 0; j < g.nodes[1]; ++j)
            for (int i = 0; i < g.nodes[0]; ++i)
                worst = std::max(worst, std::abs(g.distance_m[g.index(i, j, k)] - box_distance(node_of(g, i, j, k))));
    EXPECT_LT(worst, 1e-7) << "metres";
    // Above the top face the field is linear in y: the sample is exact, its gradient +y.
    double d = 0.0;
    Vec3 grad(0.0);
    ASSERT_TRUE(g.sample(Vec3(0.0013, 0.0137, -0.0021), d, grad));
    EXPECT_NEAR(d, 0.0037, 1e-7);
    EXPECT_NEAR(grad.y, 1.0, 1e-5);
    EXPECT_NEAR(grad.x, 0.0, 1e-5);
    EXPECT_NEAR(grad.z, 0.0, 1e-5);
    // Inside, under the top face: negative, the gradient still points out through it.
    ASSERT_TRUE(g.sample(Vec3(0.0011, 0.0081, 0.0009), d, grad));
    EXPECT_NEAR(d, -0.0019, 1e-7);
    EXPECT_NEAR(grad.y, 1.0, 1e-5);
    // Outside the grid's box, or not finite: no sample, the outputs untouched.
    d = 42.0;
    EXPECT_FALSE(g.sample(Vec3(0.0, 0.05, 0.0), d, grad));
    EXPECT_FALSE(g.sample(Vec3(std::nan(""), 0.0, 0.0), d, grad));
    EXPECT_EQ(d, 42.0);
}

TEST(DistanceGrid, BadInputIsRefusedWithTheReason) {
    const TriMesh box = box_mesh(Aabb{Vec3(0.0), Vec3(0.1)});
    auto message = [&](auto f) {
        try {
            f();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message([&] { build_distance_grid(box, 0.0, 0.01, 1 << 20); }).find("cell_m must be finite and > 0"),
              std::string::npos);
    EXPECT_NE(message([&] { build_distance_grid(box, 0.001, -1.0, 1 << 20); }).find("margin_m"), std::string::npos);
    EXPECT_NE(message([&] { build_distance_grid(TriMesh{}, 0.001, 0.0, 1 << 20); }).find("no triangles"),
              std::string::npos);
    const std::string big = message([&] { build_distance_grid(box, 0.0001, 0.0, 1 << 20); });
    EXPECT_NE(big.find("1001 x 1001 x 1001 nodes"), std::string::npos) << big;
    EXPECT_NE(big.find("use a coarser grid"), std::string::npos) << big;
}

}  // namespace
}  // namespace tridex::compute
