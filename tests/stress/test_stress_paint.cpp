// tests/stress/test_stress_paint.cpp - the material checks of the stress run (stress_paint.hpp) on a small
// model: a paint-only batch of overlapping ball and flat-end sweeps with distinct materials passes
// check_paint_batch, and the check fails when the model is wrong (batch applied in reverse order, one
// sweep painted with another id, a depth moved by one ulp, an end given an unused id). The exact double
// cylinder chord is checked against closed-form cases.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "compute/tools/sweep.hpp"
#include "stress_common.hpp"
#include "stress_paint.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

constexpr double kMargin = 1e-3;  // cells (3D): ends nearer than this to a sweep's exact surface are not judged

/// A paint-only batch on the lattice of `m`: overlapping strokes through the box, materials 11, 22, ...
std::vector<Sweep> paint_batch(const Lattice& L, std::uint64_t seed, std::size_t count) {
    std::mt19937_64 rng(seed);
    auto uni = [&rng](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    std::vector<Sweep> batch;
    for (std::size_t k = 0; k < count; ++k) {
        Sweep s;
        s.op = ToolOp::kPaint;
        s.material = static_cast<std::uint8_t>(11 * (k % 20 + 1));
        const bool flat = k % 3 == 2;
        s.tool = SweepTool{flat ? ToolKind::kFlatEnd : ToolKind::kBall, uni(1.5, 7.0) * L.cell_m, uni(2.0, 9.0) * L.cell_m};
        s.axis = k % 2 ? Vec3(0.0, 0.0, 1.0) : Vec3(uni(-1, 1), uni(-1, 1), 0.7);
        const Vec3 a(uni(2.0, 30.0), uni(2.0, 30.0), uni(2.0, 30.0));
        const Vec3 b = a + Vec3(uni(-8, 8), uni(-8, 8), uni(-8, 8));
        s.path_m = Segment{L.to_world(a), L.to_world(b)};
        batch.push_back(s);
    }
    return batch;
}

struct Painted {
    TriDexel model;
    std::vector<std::pair<int, std::size_t>> rays;
    std::vector<std::vector<Interval>> before;
};

Painted paint(const std::vector<Sweep>& batch, bool reverse = false) {
    Painted r{test::stress_box(32, 3.5, 28.5), {}, {}};
    r.rays = test::footprint_rays(r.model, batch);
    for (const auto& [a, i] : r.rays) r.before.push_back(r.model.sets[a].rays[i]);
    if (reverse)
        for (auto s = batch.rbegin(); s != batch.rend(); ++s) apply_sweep(r.model, *s);
    else
        for (const Sweep& s : batch) apply_sweep(r.model, s);
    return r;
}

TEST(StressPaint, ExactCylinderChordClosedForms) {
    double t0 = 0, t1 = 0;
    // Axis z from (0,0,2) to (0,0,7), radius 2: a z ray through (1,0) runs from 2 to 7; an x ray at z=3 through
    // y=1 runs from -sqrt(3) to sqrt(3); an x ray at z=8 misses; a z ray at distance 2 only touches.
    ASSERT_TRUE(test::exact_cylinder_chord(Vec3(1, 0, 0), 2, Vec3(0, 0, 2), Vec3(0, 0, 5), 2.0, t0, t1));
    EXPECT_DOUBLE_EQ(t0, 2.0);
    EXPECT_DOUBLE_EQ(t1, 7.0);
    ASSERT_TRUE(test::exact_cylinder_chord(Vec3(0, 1, 3), 0, Vec3(0, 0, 2), Vec3(0, 0, 5), 2.0, t0, t1));
    EXPECT_NEAR(t0, -std::sqrt(3.0), 1e-15);
    EXPECT_NEAR(t1, std::sqrt(3.0), 1e-15);
    EXPECT_FALSE(test::exact_cylinder_chord(Vec3(0, 1, 8), 0, Vec3(0, 0, 2), Vec3(0, 0, 5), 2.0, t0, t1));
    EXPECT_FALSE(test::exact_cylinder_chord(Vec3(2, 0, 0), 2, Vec3(0, 0, 2), Vec3(0, 0, 5), 2.0, t0, t1));
    // Axis along (1,0,1)/sqrt2 from the origin, length 4 sqrt2, radius 1: the z ray through (2, 0) enters
    // the side at z = 2 - sqrt2 and leaves it at z = 2 + sqrt2 (the caps are farther).
    ASSERT_TRUE(test::exact_cylinder_chord(Vec3(2, 0, 0), 2, Vec3(0.0), Vec3(4, 0, 4), 1.0, t0, t1));
    EXPECT_NEAR(t0, 2.0 - std::sqrt(2.0), 1e-14);
    EXPECT_NEAR(t1, 2.0 + std::sqrt(2.0), 1e-14);
}

TEST(StressPaint, PaintBatchPassesAndWrongModelsFail) {
    const std::vector<Sweep> batch = paint_batch(test::stress_box(32, 0, 0).lattice, 5u, 60);
    const Painted good = paint(batch);
    const test::PaintReport ok = test::check_paint_batch(good.model, batch, good.rays, good.before, kMargin);
    std::printf("paint batch of %zu: %zu ends checked, %zu painted, %zu kept, %zu undecided, bad %zu%s\n", batch.size(),
                ok.ends, ok.painted, ok.kept, ok.undecided, ok.bad, ok.first.c_str());
    EXPECT_EQ(ok.bad, 0u) << ok.first;
    EXPECT_GT(ok.painted, 1000u);
    EXPECT_GT(ok.kept, 500u);
    EXPECT_LT(ok.undecided, ok.ends / 100 + 1);

    // Reverse order: where strokes overlap, the earlier stroke's material wins -> mismatches.
    const Painted rev = paint(batch, true);
    const test::PaintReport r1 = test::check_paint_batch(rev.model, batch, rev.rays, rev.before, kMargin);
    EXPECT_GT(r1.bad, 0u);
    // One sweep painted with another id: each of the last 10 sweeps in turn (a sweep entirely inside the box
    // or painted over later paints no end that the check sees); most of them must be caught.
    std::size_t caught = 0;
    for (std::size_t k = batch.size() - 10; k < batch.size(); ++k) {
        std::vector<Sweep> other = batch;
        other[k].material = 3;
        const Painted wrong = paint(other);
        caught += test::check_paint_batch(wrong.model, batch, wrong.rays, wrong.before, kMargin).bad > 0;
    }
    std::printf("one sweep with another id: caught in %zu of 10 cases\n", caught);
    EXPECT_GE(caught, 5u);
    // A depth one ulp off, and a single material flipped on a painted end.
    Painted moved = paint(batch);
    Painted flipped = paint(batch);
    bool done_move = false, done_flip = false;
    for (std::size_t k = 0; k < moved.rays.size() && !(done_move && done_flip); ++k) {
        auto& ray = moved.model.sets[moved.rays[k].first].rays[moved.rays[k].second];
        auto& ray2 = flipped.model.sets[flipped.rays[k].first].rays[flipped.rays[k].second];
        if (ray.empty()) continue;
        if (!done_move) ray[0].enter = std::nextafter(ray[0].enter, 1e9f), done_move = true;
        if (!done_flip && ray2[0].enter_material != moved.before[k][0].enter_material)
            ray2[0].enter_material = moved.before[k][0].enter_material, done_flip = true;
    }
    ASSERT_TRUE(done_move && done_flip);
    EXPECT_EQ(test::check_paint_batch(moved.model, batch, moved.rays, moved.before, kMargin).bad, 1u);
    EXPECT_EQ(test::check_paint_batch(flipped.model, batch, flipped.rays, flipped.before, kMargin).bad, 1u);
}

TEST(StressPaint, UnusedMaterialIdsAreCounted) {
    std::array<bool, 256> used{};
    used[0] = used[11] = true;
    std::vector<Interval> ray = {{1.0f, 2.0f, 0, 11}, {3.0f, 4.0f, 11, 0}};
    EXPECT_EQ(test::unused_materials(ray, used), 0u);
    ray[1].exit_material = 12;
    EXPECT_EQ(test::unused_materials(ray, used), 1u);
}

}  // namespace
