// Tests of apply_clay_batch: runs of short push sweeps of one tool go as one grouped push (clay_push_group) split
// where their motion outgrows clay_group_cells; the grouped groove's floor follows the ball within half a cell and
// keeps the volume; Booleans and other clay sweeps in the batch apply as on their own; a bad sweep changes nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "clay_test_models.hpp"
#include "compute/tools/clay_push.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

using clay_test::clay_sweep;
using clay_test::cube_lattice;
using clay_test::from_implicit;
using clay_test::volume_cells;

constexpr double kZ0 = 20.3;  // the slab's top face, grid units

TriDexel slab() { return from_implicit(cube_lattice(48), clay_test::slab(kZ0)); }

/// `n` push sweeps of a ball of radius R cells, `step` cells each along +x from x0, pressed `depth` cells into the top.
std::vector<Sweep> groove(int n, double x0, double R, double depth, double step = 0.6) {
    std::vector<Sweep> out;
    for (int k = 0; k < n; ++k) {
        const Vec3 a(x0 + step * k, 24.2, kZ0 + R - depth), b(x0 + step * (k + 1), 24.2, kZ0 + R - depth);
        out.push_back(clay_sweep(ToolOp::kPush, a, b, R));
    }
    return out;
}

/// Lowest top crossing (cells) of the Z rays along the groove's centre line, x in [x0, x1].
float floor_of(const TriDexel& m, int x0, int x1) {
    float lo = 1e9f;
    for (int i = x0; i <= x1; ++i) {
        const auto& ray = m.sets[2].ray(i, 24);
        if (!ray.empty()) lo = std::min(lo, ray.back().exit);
    }
    return lo;
}

TEST(ClayBatch, ShortPushesOfOneToolGoAsGroupsSplitAtTheGroupLength) {
    const double R = 2.0;
    const std::vector<Sweep> batch = groove(16, 8.0, R, 1.0, 1.5);  // 24 cells of motion in 16 sweeps
    const float limit = clay_group_cells(static_cast<float>(R));
    ASSERT_LT(limit, 24.0f) << "the groove must need more than one group";
    TriDexel grouped = slab();
    apply_clay_batch(grouped, batch);
    // The same groups by hand: consecutive sweeps while their motion's box diagonal stays within the limit.
    TriDexel by_hand = slab();
    std::size_t i = 0, groups = 0;
    while (i < batch.size()) {
        std::size_t j = i + 1;
        while (j < batch.size() && j - i < kClayGroupSweeps &&
               glm::length(batch[j].path_m.b - batch[i].path_m.a) / 1e-3 <= limit)
            ++j;
        std::vector<GridSweep> g;
        for (std::size_t k = i; k < j; ++k) g.push_back(to_clay_grid_sweep(by_hand.lattice, batch[k]));
        clay_push_group(by_hand, g);
        ++groups;
        i = j;
    }
    EXPECT_GE(groups, 2u);
    EXPECT_TRUE(clay_test::same_rays(grouped, by_hand)) << "apply_clay_batch must group exactly so";
    // Applying the batch again from the start gives the same model bit for bit.
    TriDexel again = slab();
    apply_clay_batch(again, batch);
    EXPECT_TRUE(clay_test::same_rays(grouped, again));
}

TEST(ClayBatch, AGroupedGrooveFollowsTheBallAndKeepsTheVolume) {
    for (const double R : {2.0, 4.0}) {
        const std::vector<Sweep> batch = groove(16, 14.0, R, 1.0);
        TriDexel one = slab(), grouped = slab();
        const double v0 = volume_cells(one);
        for (const Sweep& s : batch) apply_clay(one, s);
        apply_clay_batch(grouped, batch);
        const float f1 = floor_of(one, 17, 22), fg = floor_of(grouped, 17, 22);
        const double dv1 = volume_cells(one) - v0, dvg = volume_cells(grouped) - v0;
        std::printf("R = %.0f cells: groove floor %.3f (one by one) and %.3f (grouped) cells, the face at %.2f; volume "
                    "change %.4f and %.4f cells^3 of %.0f\n",
                    R, f1, fg, kZ0, dv1, dvg, v0);
        // The ball's lowest point runs 1 cell under the face: the grouped push's floor follows it (one by one, each
        // sweep's contacts see the dents before it and the floor ends lower still).
        EXPECT_NEAR(fg, kZ0 - 1.0, 0.5);
        EXPECT_LE(f1, fg + 0.05);
        EXPECT_LT(std::fabs(dvg), 1e-4 * v0);
        EXPECT_EQ(clay_set_disagreement(grouped, clay_whole_box(grouped.lattice)), 0u);
    }
}

TEST(ClayBatch, DeepPressesIntoAFaceOnTheNodesKeepTheVolumeGroupByGroup) {
    // A face through the lattice's nodes and a ball pressed well past the push's step: the edges at the face carry
    // both ends near the surface, whose crossings race across their edges as the rim's weight changes. Every
    // group's rim must still be solved to keep the volume.
    const double z0 = 20.0, depth = 3.37;
    const TriDexel start = from_implicit(cube_lattice(48), clay_test::slab(z0));
    for (const double R : {2.0, 4.0}) {
        TriDexel m = start;
        const double v0 = volume_cells(m);
        double worst = 0.0;
        std::size_t changed = 0;
        for (int b = 0; b < 4; ++b) {
            std::vector<Sweep> batch;
            for (int k = 0; k < 16; ++k) {
                const double x = 14.0 + 0.45 * (16 * b + k), y = 24.3 + 2.0 * std::sin(0.1 * (16 * b + k));
                const double x1 = x + 0.45, y1 = 24.3 + 2.0 * std::sin(0.1 * (16 * b + k + 1));
                batch.push_back(clay_sweep(ToolOp::kPush, Vec3(x, y, z0 + R - depth), Vec3(x1, y1, z0 + R - depth), R));
            }
            const double before = volume_cells(m);
            changed += apply_clay_batch(m, batch).rays_changed;
            const double dv = volume_cells(m) - before;
            worst = std::max(worst, std::fabs(dv));
        }
        std::printf("R = %.0f cells, face on the nodes, pressed %.2f cells: largest volume change of a batch %.4f "
                    "cells^3, over the stroke %.4f of %.0f\n", R, depth, worst, volume_cells(m) - v0, v0);
        EXPECT_GT(changed, 0u) << "the stroke must push";
        EXPECT_LT(worst, 0.5) << "a batch's rim left volume unaccounted";
    }
}

TEST(ClayBatch, BooleansAndOtherClayOpsInTheBatchApplyAsOnTheirOwn) {
    std::vector<Sweep> batch = groove(4, 12.0, 2.0, 1.0);
    Sweep cut;
    cut.op = ToolOp::kSubtract;
    cut.tool.kind = ToolKind::kBall;
    cut.tool.radius_m = 2.0e-3;
    cut.path_m = Segment{Vec3(30.0, 30.0, kZ0) * 1e-3, Vec3(34.0, 30.0, kZ0) * 1e-3};
    batch.push_back(cut);
    batch.push_back(clay_sweep(ToolOp::kSmooth, Vec3(30.0, 14.0, kZ0 + 2.4), Vec3(30.6, 14.0, kZ0 + 2.4), 3.0));
    const std::vector<Sweep> tail = groove(3, 20.0, 2.0, 1.0);
    batch.insert(batch.end(), tail.begin(), tail.end());
    TriDexel a = slab(), b = slab();
    apply_clay_batch(a, batch);
    // By hand: the first four pushes as one group, the cut, the smooth, the last three pushes as one group.
    auto group = [&](std::size_t i0, std::size_t n) {
        std::vector<GridSweep> g;
        for (std::size_t k = i0; k < i0 + n; ++k) g.push_back(to_clay_grid_sweep(b.lattice, batch[k]));
        clay_push_group(b, g);
    };
    group(0, 4);
    apply_sweep(b, batch[4]);
    apply_clay(b, batch[5]);
    group(6, 3);
    EXPECT_TRUE(clay_test::same_rays(a, b));
}

TEST(ClayBatch, ManySlowPushesGoInGroupsOfAtMostTheGroupsSweeps) {
    // Two and a half groups of sweeps of 0.05 cell (a slow hand at the haptic rate): the motion stays short, the count
    // closes the groups; for the default size and others a session may record.
    std::vector<TriDexel> models;
    for (const std::size_t n : {kClayGroupSweeps, std::size_t{16}, std::size_t{5}}) {
        std::vector<Sweep> batch;
        for (std::size_t k = 0; k < 80; ++k) {
            const double x = 20.0 + 0.05 * static_cast<double>(k);
            batch.push_back(clay_sweep(ToolOp::kPush, Vec3(x, 24.2, kZ0 + 1.0), Vec3(x + 0.05, 24.2, kZ0 + 1.0), 2.0));
        }
        batch.resize(n * 5 / 2);
        TriDexel a = slab(), b = slab();
        apply_clay_batch(a, batch, nullptr, clay_cpu_kernel(), n);
        for (std::size_t i = 0; i < batch.size(); i += n) {
            std::vector<GridSweep> g;
            for (std::size_t k = i; k < std::min(batch.size(), i + n); ++k)
                g.push_back(to_clay_grid_sweep(b.lattice, batch[k]));
            clay_push_group(b, g);
        }
        EXPECT_TRUE(clay_test::same_rays(a, b)) << "groups of " << n;
        EXPECT_EQ(clay_open_group(a.lattice, batch, n), 2 * n) << "the last half group is open, groups of " << n;
        if (n == 16) {
            // The same 40 sweeps grouped by the default size: another grouping, another model.
            TriDexel c = slab();
            apply_clay_batch(c, batch);
            EXPECT_FALSE(clay_test::same_rays(a, c)) << "the group size must decide the model";
        }
    }
}

TEST(ClayBatch, AGroupSizeOutsideItsRangeIsRefusedAndChangesNothing) {
    const std::vector<Sweep> batch = groove(4, 12.0, 2.0, 1.0);
    TriDexel m = slab();
    const TriDexel before = m;
    for (const std::size_t n : {std::size_t{0}, kClayGroupSweepsMax + 1}) {
        try {
            apply_clay_batch(m, batch, nullptr, clay_cpu_kernel(), n);
            ADD_FAILURE() << "group size " << n << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("clay group size"), std::string::npos) << e.what();
        }
        EXPECT_THROW(clay_open_group(m.lattice, batch, n), Error);
    }
    EXPECT_TRUE(clay_test::same_rays(m, before));
}

TEST(ClayBatch, ABadSweepChangesNothing) {
    std::vector<Sweep> batch = groove(4, 12.0, 2.0, 1.0);
    Sweep bad = batch[1];
    bad.tool.radius_m = -1.0;
    batch.push_back(bad);
    TriDexel m = slab();
    const TriDexel before = m;
    EXPECT_THROW(apply_clay_batch(m, batch), Error);
    EXPECT_TRUE(clay_test::same_rays(m, before));
}

}  // namespace
}  // namespace tridex::compute
