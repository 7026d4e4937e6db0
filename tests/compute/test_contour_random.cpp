// Tests of compute/contour/contour_dual on random occupancy: the mesh must be a closed 2-manifold for any input.
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <random>

#include "compute/contour/contour_dual.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

TEST(ContourRandom, VoxelSetsGiveClosedManifoldsAtEveryDensity) {
    std::size_t split_total = 0;
    for (const double density : {0.05, 0.2, 0.35, 0.5, 0.65, 0.8, 0.95}) {
        for (unsigned seed = 1; seed <= 3; ++seed) {
            SCOPED_TRACE(::testing::Message() << "density " << density << " seed " << seed);
            TriDexel model = random_voxels(40, density, seed);  // 3 x 3 x 3 tiles, the last ones partial
            Contourer contourer(model);
            contourer.update(model);
            const TriMesh m = contourer.mesh();
            expect_closed_manifold(m);
            const ContourStats s = contourer.stats();
            EXPECT_EQ(s.fallbacks, 0u);  // consistent rays: every crossing is on its edge
            EXPECT_GT(signed_volume(m), 0.0);
            split_total += s.split_faces;
            if (seed == 1)
                std::printf("density %.2f: %zu triangles, %zu split faces, %zu cells visited\n", density,
                            s.triangles, s.split_faces, s.cells_visited);
        }
    }
    // The repair of faces merged on both sides must have been exercised (it is common at mid density).
    EXPECT_GT(split_total, 0u);
}

TEST(ContourRandom, InconsistentRaySetsStillGiveClosedManifolds) {
    // Every ray of every set gets its own random intervals: the Y and Z rays disagree with the X-ray
    // occupancy, so many crossings fall back; topology comes from the X rays alone and stays manifold.
    const int cells = 34;
    TriDexel model = empty_model(cube_lattice(cells));
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> pos(1.0, cells - 1.0);
    fill_rays(model, [&](int, int u, int v) {
        std::vector<Interval> ray;
        if (u == 0 || v == 0 || u == cells || v == cells) return ray;
        std::vector<double> ends;
        for (int e = 0; e < 6; ++e) ends.push_back(pos(rng));
        std::sort(ends.begin(), ends.end());
        for (int e = 0; e + 1 < 6; e += 2)
            if (ends[e + 1] - ends[e] > 1e-3 && (ray.empty() || ends[e] > ray.back().exit + 1e-3))
                ray.push_back({static_cast<float>(ends[e]), static_cast<float>(ends[e + 1])});
        return ray;
    });
    Contourer contourer(model);
    contourer.update(model);
    const TriMesh m = contourer.mesh();
    expect_closed_manifold(m);
    const ContourStats s = contourer.stats();
    std::printf("inconsistent rays: %zu triangles, %zu fallbacks, %zu split faces\n", s.triangles, s.fallbacks,
                s.split_faces);
    EXPECT_GT(s.fallbacks, 0u);
    // Every vertex still lies in the lattice's interior cells (crossings and fallbacks clamp into edges).
    const Aabb inner{model.lattice.origin_m, model.lattice.to_world(Vec3(cells))};
    for (const Vec3& p : m.positions) ASSERT_TRUE(inner.contains(p));
}

TEST(ContourRandom, MaterialTouchingTheLatticeBorderIsStillClosed) {
    // Border nodes count as outside, so even a completely full lattice gives a closed box-like mesh.
    const int cells = 20;
    TriDexel model = empty_model(cube_lattice(cells));
    fill_rays(model, [&](int, int, int) { return std::vector<Interval>{{-1.0f, cells + 1.0f}}; });
    Contourer contourer(model);
    contourer.update(model);
    const TriMesh m = contourer.mesh();
    expect_closed_manifold(m);
    EXPECT_GT(contourer.stats().fallbacks, 0u);  // the rays do not end on the border edges
}

TEST(ContourRandom, NonFiniteEndsDoNotBreakTheMesh) {
    // A sphere whose rays near the middle carry NaN / infinite garbage after their chord.
    TriDexel model = empty_model(cube_lattice(24));
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    fill_rays(model, [&](int a, int u, int v) {
        std::vector<Interval> ray = sphere_chord(Vec3(11.6, 12.3, 12.2), 8.4, a, u, v);
        if (u == 12 && !ray.empty()) ray.push_back({nan, nan});
        if (v == 12 && !ray.empty()) ray.push_back({20.5f, inf});
        return ray;
    });
    Contourer contourer(model);
    contourer.update(model);
    const TriMesh m = contourer.mesh();
    expect_closed_manifold(m);
    for (const Vec3& p : m.positions) ASSERT_TRUE(is_finite(p));
}

}  // namespace
}  // namespace tridex::compute
