// tests/compute/test_sweep.cpp - the CPU reference of swept Booleans: union and paint per ray, flat-end
// mill sweeps against analytic volumes, union/subtract of the same sweep cancelling, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "compute/model/interval_ops.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

TriDexel model_with_box(double lo_cells, double hi_cells, int cells = 48) {
    Lattice L;
    L.origin_m = Vec3(0.3, -0.2, 0.1);
    L.cell_m = 0.001;
    L.cells = {cells, cells, cells};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    if (hi_cells > lo_cells) scan_convert(box_mesh(Aabb{L.to_world(Vec3(lo_cells)), L.to_world(Vec3(hi_cells))}), m);
    return m;
}

bool valid_ray(const std::vector<Interval>& r) {
    for (std::size_t i = 0; i < r.size(); ++i) {
        if (!(r[i].enter < r[i].exit) || !std::isfinite(r[i].enter) || !std::isfinite(r[i].exit)) return false;
        if (i > 0 && !(r[i - 1].exit < r[i].enter)) return false;
    }
    return true;
}

}  // namespace

TEST(IntervalOps, UnionMergesOverlappingAndTouchingIntervalsAndMarksNewEnds) {
    std::vector<Interval> r{{0.f, 1.f, 1, 2}, {2.f, 3.f, 3, 4}, {5.f, 6.f, 5, 6}};
    EXPECT_TRUE(union_interval_changed(r, 1.f, 2.5f, 9));  // touches the first, overlaps the second
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(r[0].enter, 0.f);
    EXPECT_EQ(r[0].exit, 3.f);
    EXPECT_EQ(r[0].enter_material, 1);
    EXPECT_EQ(r[0].exit_material, 4);  // the old exit survives, so does its material
    EXPECT_TRUE(union_interval_changed(r, 5.5f, 7.f, 9));
    EXPECT_EQ(r[1].exit, 7.f);
    EXPECT_EQ(r[1].exit_material, 9);  // extended by the tool: the tool's material
    EXPECT_EQ(r[1].enter_material, 5);
    EXPECT_FALSE(union_interval_changed(r, 0.5f, 2.0f, 9));  // already solid
    EXPECT_TRUE(union_interval_changed(r, 10.f, 11.f, 7));   // a new interval at the end
    ASSERT_EQ(r.size(), 3u);
    EXPECT_EQ(r[2].enter_material, 7);
    EXPECT_TRUE(union_interval_changed(r, -2.f, 12.f, 8));   // swallows everything
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].enter, -2.f);
    EXPECT_EQ(r[0].exit, 12.f);
    EXPECT_FALSE(union_interval_changed(r, 3.f, 3.f, 1));
    EXPECT_FALSE(union_interval_changed(r, NAN, 3.f, 1));
    EXPECT_TRUE(valid_ray(r));
}

TEST(IntervalOps, SubtractGivesCutEndsTheCutMaterial) {
    std::vector<Interval> r{{0.f, 10.f, 1, 2}};
    EXPECT_TRUE(subtract_interval_changed(r, 4.f, 6.f, 5));
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(r[0].enter_material, 1);
    EXPECT_EQ(r[0].exit_material, 5);
    EXPECT_EQ(r[1].enter_material, 5);
    EXPECT_EQ(r[1].exit_material, 2);
}

TEST(IntervalOps, PaintSetsOnlyTheEndsInsideTheSpan) {
    std::vector<Interval> r{{0.f, 2.f}, {3.f, 5.f}, {6.f, 9.f}};
    EXPECT_TRUE(paint_interval_changed(r, 1.f, 6.f, 4));
    EXPECT_EQ(r[0].enter_material, 0);
    EXPECT_EQ(r[0].exit_material, 4);
    EXPECT_EQ(r[1].enter_material, 4);
    EXPECT_EQ(r[1].exit_material, 4);
    EXPECT_EQ(r[2].enter_material, 4);  // 6 is inside the closed span
    EXPECT_EQ(r[2].exit_material, 0);
    EXPECT_FALSE(paint_interval_changed(r, 1.f, 6.f, 4));  // nothing left to change
    EXPECT_EQ(r[1].enter, 3.f);
    EXPECT_EQ(r[1].exit, 5.f);
}

TEST(Sweep, FlatEndMillPlungeAndSideMoveRemoveTheAnalyticVolume) {
    TriDexel m = model_with_box(4.5, 43.5);
    const double v0 = dexel_volume_m3(m);
    const Lattice& L = m.lattice;
    // Flat walls and the floor fall midway between lattice nodes, where the dexel volume (a midpoint
    // rule) is exact; only the curved wall carries sampling error.
    const double r = 0.006, h = 0.012, D = 0.0157;  // radius, plunge depth, side move (m)
    Sweep s;
    s.op = ToolOp::kSubtract;
    s.tool = SweepTool{ToolKind::kFlatEnd, r, 0.03};
    s.axis = Vec3(0.0, 0.0, 1.0);
    const Vec3 top = L.to_world(Vec3(17.5, 20.5, 43.5));
    s.path_m = Segment{top, top - Vec3(0.0, 0.0, h)};  // plunge
    apply_sweep(m, s);
    const double v1 = dexel_volume_m3(m);
    const double plunge = M_PI * r * r * h;
    EXPECT_NEAR((v0 - v1) / plunge, 1.0, 0.01) << "plunge removed " << v0 - v1 << " m^3, exact " << plunge;
    s.path_m = Segment{top - Vec3(0.0, 0.0, h), top - Vec3(-D, 0.0, h)};  // slot along +x at full depth
    const GridSweep g = to_grid_sweep(L, s);
    EXPECT_EQ(g.stamps, 1u);  // the whole slot in closed form
    apply_sweep(m, s);
    const double v2 = dexel_volume_m3(m);
    const double slot = (2.0 * r * D) * h;  // (disc swept by D) minus the disc already removed
    EXPECT_NEAR((v1 - v2) / slot, 1.0, 0.01) << "slot removed " << v1 - v2 << " m^3, exact " << slot;
    for (const RaySet& set : m.sets)
        for (const auto& ray : set.rays) ASSERT_TRUE(valid_ray(ray));
}

TEST(Sweep, UnionOfABallIntoEmptySpaceHasTheBallsVolumeAndSubtractingItAgainLeavesNothing) {
    TriDexel m = model_with_box(0.0, 0.0, 40);
    const Lattice& L = m.lattice;
    Sweep s;
    s.op = ToolOp::kUnion;
    s.material = 3;
    s.tool = SweepTool{ToolKind::kBall, 0.0083, 0.0};
    const Vec3 a = L.to_world(Vec3(14.2, 15.7, 16.1)), b = L.to_world(Vec3(25.9, 22.3, 20.4));
    s.path_m = Segment{a, b};
    const BooleanStats st = apply_sweep(m, s);
    EXPECT_GT(st.rays_changed, 0u);
    const double r = s.tool.radius_m, len = glm::length(b - a);
    const double exact = M_PI * r * r * len + 4.0 / 3.0 * M_PI * r * r * r;
    EXPECT_NEAR(dexel_volume_m3(m) / exact, 1.0, 0.01);
    for (const RaySet& set : m.sets)
        for (const auto& ray : set.rays)
            for (const Interval& iv : ray) {
                ASSERT_EQ(iv.enter_material, 3);
                ASSERT_EQ(iv.exit_material, 3);
            }
    s.op = ToolOp::kSubtract;
    apply_sweep(m, s);
    EXPECT_EQ(m.interval_count(), 0u);
}

TEST(Sweep, PaintingTheTopFaceColoursOnlyTheSurfacePointsUnderTheBall) {
    TriDexel m = model_with_box(4.0, 36.0, 40);
    const Lattice& L = m.lattice;
    Sweep s;
    s.op = ToolOp::kPaint;
    s.material = 2;
    s.tool = SweepTool{ToolKind::kBall, 0.004, 0.0};
    const Vec3 c = L.to_world(Vec3(20.0, 20.0, 36.0));
    s.path_m = Segment{c, c};
    const double v0 = dexel_volume_m3(m);
    apply_sweep(m, s);
    EXPECT_EQ(dexel_volume_m3(m), v0);
    int painted_top = 0;
    for (int v = 0; v < m.sets[2].nv; ++v)
        for (int u = 0; u < m.sets[2].nu; ++u)
            for (const Interval& iv : m.sets[2].ray(u, v)) {
                EXPECT_EQ(iv.enter_material, 0);  // the bottom face is far from the ball
                const double dist2 = (u - 20.0) * (u - 20.0) + (v - 20.0) * (v - 20.0);
                if (iv.exit_material == 2) {
                    ++painted_top;
                    EXPECT_LE(dist2, 16.0 + 1e-6);
                } else {
                    EXPECT_GT(dist2, 16.0 - 1e-6);
                }
            }
    EXPECT_GT(painted_top, 40);  // about pi * 4^2 = 50 rays
}

TEST(Sweep, BadInputIsRefusedNamingTheFieldAndLeavesTheModelUnchanged) {
    TriDexel m = model_with_box(4.0, 36.0, 40);
    const std::size_t n = m.interval_count();
    Sweep s;
    s.tool = SweepTool{ToolKind::kFlatEnd, 0.004, 0.0};
    s.path_m = Segment{Vec3(0.32, -0.18, 0.12), Vec3(0.32, -0.18, 0.12)};
    EXPECT_THROW(apply_sweep(m, s), Error);  // zero length
    s.tool.length_m = 0.01;
    s.axis = Vec3(0.0);
    EXPECT_THROW(apply_sweep(m, s), Error);
    s.axis = Vec3(0.0, 0.0, 1.0);
    s.path_m.b = Vec3(NAN, 0.0, 0.0);
    EXPECT_THROW(apply_sweep(m, s), Error);
    s.path_m.b = Vec3(1e9, 0.0, 0.0);
    EXPECT_THROW(apply_sweep(m, s), Error);  // 2^24 cells away
    s.path_m.b = s.path_m.a;
    s.tool.radius_m = -1.0;
    try {
        apply_sweep(m, s);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("radius_m"), std::string::npos) << e.what();
    }
    EXPECT_EQ(m.interval_count(), n);
}
