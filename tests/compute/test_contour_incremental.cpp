// Tests of compute/contour_dual's tile cache: update() redoes dirty tiles only and the result equals a
// from-scratch contour of the same model.
#include <gtest/gtest.h>

#include <random>

#include "compute/contour_dual.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

std::size_t dirty_count(const TriDexel& m) {
    std::size_t n = 0;
    for (std::uint8_t d : m.tiles.dirty) n += d;
    return n;
}

/// Contour of `model` by a fresh Contourer with every tile dirty (the model's flags are restored).
TriMesh from_scratch(TriDexel model) {
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});
    Contourer c(model);
    c.update(model);
    return c.mesh();
}

void expect_same_mesh(const TriMesh& a, const TriMesh& b) {
    ASSERT_EQ(a.positions.size(), b.positions.size());
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i) ASSERT_EQ(a.positions[i], b.positions[i]) << i;
    for (std::size_t i = 0; i < a.triangles.size(); ++i) ASSERT_EQ(a.triangles[i], b.triangles[i]) << i;
}

/// Chord of (sphere minus box) along ray (u, v) of set a, grid units.
std::vector<Interval> sphere_minus_box(const Vec3& c, double r, const Vec3& lo, const Vec3& hi, int a, int u, int v) {
    std::vector<Interval> s = sphere_chord(c, r, a, u, v);
    const std::vector<Interval> b = box_chord(lo, hi, a, u, v);
    if (s.empty() || b.empty()) return s;
    std::vector<Interval> out;
    if (s[0].enter < b[0].enter) out.push_back({s[0].enter, std::min(s[0].exit, b[0].enter)});
    if (s[0].exit > b[0].exit) out.push_back({std::max(s[0].enter, b[0].exit), s[0].exit});
    return out;
}

TEST(ContourIncremental, CarvedRegionRedoesOnlyItsTilesAndMatchesFromScratch) {
    const Lattice l = cube_lattice(80);  // 5 x 5 x 5 tiles
    TriDexel model = empty_model(l);
    const Vec3 c(40.3, 39.6, 40.2);
    const double r = 30.7;
    fill_rays(model, [&](int a, int u, int v) { return sphere_chord(c, r, a, u, v); });
    Contourer contourer(model);
    EXPECT_EQ(contourer.update(model), 125u);
    EXPECT_EQ(dirty_count(model), 0u);
    EXPECT_EQ(contourer.update(model), 0u);  // nothing dirty: nothing redone

    // Carve a box that pokes out of the sphere near its +x side.
    const Vec3 lo(58.4, 33.3, 36.6), hi(75.2, 44.8, 47.1);
    fill_rays(model, [&](int a, int u, int v) { return sphere_minus_box(c, r, lo, hi, a, u, v); });
    model.mark_dirty(Aabb{l.to_world(lo), l.to_world(hi)});
    const std::size_t marked = dirty_count(model);
    EXPECT_GT(marked, 0u);
    EXPECT_LT(marked, 125u / 4);
    EXPECT_EQ(contourer.update(model), marked);
    EXPECT_EQ(contourer.stats().tiles_recontoured, marked);
    const TriMesh inc = contourer.mesh();
    expect_closed_manifold(inc);
    expect_same_mesh(inc, from_scratch(model));
    // The carve removed material: volume dropped by about the carved box part inside the sphere.
    EXPECT_LT(signed_volume(inc), 4.0 / 3.0 * M_PI * std::pow(r * l.cell_m, 3));
}

TEST(ContourIncremental, SingleNodeEditsMatchFromScratch) {
    // Flip single nodes of a random voxel model (all three ray sets rebuilt consistently); mark_dirty on
    // the changed ends' box (node +- 1 cell) must be enough for an exact match with a fresh contour.
    const int cells = 36, n = cells + 1;
    std::vector<std::uint8_t> occ(static_cast<std::size_t>(n) * n * n, 0);
    std::mt19937 rng(11);
    std::bernoulli_distribution coin(0.45);
    const auto idx = [n](int i, int j, int k) { return i + n * (j + static_cast<std::size_t>(n) * k); };
    for (int k = 1; k < cells; ++k)
        for (int j = 1; j < cells; ++j)
            for (int i = 1; i < cells; ++i) occ[idx(i, j, k)] = coin(rng) ? 1 : 0;
    const auto inside = [&](int i, int j, int k) { return occ[idx(i, j, k)] != 0; };
    const Lattice l = cube_lattice(cells);
    TriDexel model = empty_model(l);
    fill_rays(model, [&](int a, int u, int v) { return voxel_ray(inside, n, a, u, v); });
    Contourer contourer(model);
    contourer.update(model);
    std::uniform_int_distribution<int> node(1, cells - 1);
    for (int edit = 0; edit < 24; ++edit) {
        // Nodes near tile borders (15, 16, 17, 31, 32, 33) half the time: the cross-tile cases.
        static constexpr int kNearBorder[6] = {15, 16, 17, 31, 32, 33};
        int p[3];
        for (int& x : p) x = (edit % 2 == 0) ? node(rng) : kNearBorder[std::uniform_int_distribution<int>(0, 5)(rng)];
        occ[idx(p[0], p[1], p[2])] ^= 1;
        for (int a = 0; a < 3; ++a) {
            const int u = p[(a + 1) % 3], v = p[(a + 2) % 3];
            model.sets[a].ray(u, v) = voxel_ray(inside, n, a, u, v);
        }
        const Vec3 g(p[0], p[1], p[2]);
        model.mark_dirty(Aabb{l.to_world(g - Vec3(1.0)), l.to_world(g + Vec3(1.0))});
        const std::size_t marked = dirty_count(model);
        ASSERT_EQ(contourer.update(model), marked);
        const TriMesh inc = contourer.mesh();
        SCOPED_TRACE(::testing::Message() << "edit " << edit << " node " << p[0] << "," << p[1] << "," << p[2]);
        expect_same_mesh(inc, from_scratch(model));
    }
    expect_closed_manifold(contourer.mesh());
}

}  // namespace
}  // namespace tridex::compute
