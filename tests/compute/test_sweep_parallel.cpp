// tests/compute/test_sweep_parallel.cpp - the multi-threaded CPU path (apply_sweeps_parallel) against the
// sequential reference (apply_sweep one by one): random batches of every tool and operation give identical
// intervals (bit for bit), stats and dirty tiles with 1, 2, 3 and 8 threads; bad input changes nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "compute/mesh/scan_convert.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/tools/sweep_parallel.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

TriDexel box_model(int cells) {
    Lattice L;
    L.origin_m = Vec3(0.3, -0.2, 0.7);
    L.cell_m = 0.001;
    L.cells = {cells, cells + 3, cells - 2};  // not cubic: the three sets differ in size
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    scan_convert(box_mesh(Aabb{L.to_world(Vec3(3.0)), L.to_world(Vec3(cells - 5.0))}), m);
    m.clear_dirty();
    return m;
}

/// Rays that differ bitwise (depths and materials) between a and b.
std::size_t differing_rays(const TriDexel& a, const TriDexel& b) {
    std::size_t n = 0;
    for (int s = 0; s < 3; ++s)
        for (std::size_t i = 0; i < a.sets[s].rays.size(); ++i) {
            const auto& x = a.sets[s].rays[i];
            const auto& y = b.sets[s].rays[i];
            bool same = x.size() == y.size();
            for (std::size_t k = 0; same && k < x.size(); ++k)
                same = std::memcmp(&x[k].enter, &y[k].enter, 4) == 0 && std::memcmp(&x[k].exit, &y[k].exit, 4) == 0 &&
                       x[k].enter_material == y[k].enter_material && x[k].exit_material == y[k].exit_material;
            if (!same) ++n;
        }
    return n;
}

/// A random batch: short strokes with every tool and operation, some sweeps of op kNone, positions on
/// lattice nodes now and then (grazing rays), sweeps overlapping each other heavily.
std::vector<Sweep> random_batch(const Lattice& L, int count, std::mt19937& rng) {
    std::uniform_real_distribution<double> pos(2.0, L.cells[2] - 2.0), unit(0.0, 1.0);
    std::vector<Sweep> out;
    Sweep s;
    Vec3 g(pos(rng), pos(rng), pos(rng));
    while (static_cast<int>(out.size()) < count) {
        if (out.empty() || unit(rng) < 0.15) {
            const double pick = unit(rng);
            s.op = pick < 0.45 ? ToolOp::kSubtract : pick < 0.75 ? ToolOp::kUnion : pick < 0.95 ? ToolOp::kPaint : ToolOp::kNone;
            s.material = static_cast<std::uint8_t>(rng() % 7);
            const bool flat = unit(rng) < 0.35;
            double r = 0.4 + 6.0 * unit(rng);
            if (unit(rng) < 0.3) r = std::max(1.0, std::round(r));
            s.tool = SweepTool{flat ? ToolKind::kFlatEnd : ToolKind::kBall, r * L.cell_m, (1.0 + 6.0 * unit(rng)) * L.cell_m};
            Vec3 axis(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
            if (unit(rng) < 0.4) axis = Vec3(0.0, 0.0, 1.0);
            s.axis = glm::length(axis) > 1e-3 ? axis : Vec3(1.0, 0.0, 0.0);
            g = Vec3(pos(rng), pos(rng), pos(rng));
        }
        Vec3 h = g + Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5) * 4.0;
        if (unit(rng) < 0.2) h = glm::round(h);
        s.path_m = Segment{L.to_world(g), L.to_world(h)};
        out.push_back(s);
        g = h;
    }
    return out;
}

TEST(SweepParallel, RandomBatchesEqualSequentialApplySweepForAnyThreadCount) {
    for (const int threads : {1, 2, 3, 8}) {
        TriDexel seq = box_model(36);
        TriDexel par = seq;
        std::size_t changed = 0;
        std::mt19937 rng(1234u + static_cast<unsigned>(threads));
        for (int b = 0; b < 12; ++b) {
            const std::vector<Sweep> batch = random_batch(seq.lattice, 1 + static_cast<int>(rng() % 64), rng);
            BooleanStats want;
            for (const Sweep& s : batch) {
                const BooleanStats one = apply_sweep(seq, s);
                want.rays_visited += one.rays_visited;
                want.rays_changed += one.rays_changed;
            }
            changed += want.rays_changed;
            const BooleanStats got = apply_sweeps_parallel(par, batch, threads);
            ASSERT_EQ(got.rays_visited, want.rays_visited) << "threads " << threads << " batch " << b;
            ASSERT_EQ(got.rays_changed, want.rays_changed) << "threads " << threads << " batch " << b;
            ASSERT_EQ(differing_rays(seq, par), 0u) << "threads " << threads << " batch " << b;
            ASSERT_EQ(seq.tiles.dirty, par.tiles.dirty) << "threads " << threads << " batch " << b;
        }
        EXPECT_GT(changed, 1000u);  // the batches really carved, added and painted
        EXPECT_GT(seq.interval_count(), 0u);
    }
}

TEST(SweepParallel, DefaultThreadCountAndEmptyBatches) {
    TriDexel seq = box_model(24);
    TriDexel par = seq;
    std::mt19937 rng(7u);
    const std::vector<Sweep> batch = random_batch(seq.lattice, 40, rng);
    for (const Sweep& s : batch) apply_sweep(seq, s);
    apply_sweeps_parallel(par, batch, 0);  // hardware_concurrency()
    EXPECT_EQ(differing_rays(seq, par), 0u);
    EXPECT_EQ(seq.tiles.dirty, par.tiles.dirty);
    const BooleanStats none = apply_sweeps_parallel(par, std::span<const Sweep>{}, 2);
    EXPECT_EQ(none.rays_visited, 0u);
    // A sweep entirely off the lattice visits nothing.
    Sweep far;
    far.tool = SweepTool{ToolKind::kBall, 0.002, 0.0};
    far.path_m = Segment{par.lattice.to_world(Vec3(-50.0)), par.lattice.to_world(Vec3(-40.0))};
    EXPECT_EQ(apply_sweeps_parallel(par, std::span<const Sweep>(&far, 1), 2).rays_visited, 0u);
}

TEST(SweepParallel, InvalidSweepThrowsBeforeChangingAnything) {
    TriDexel model = box_model(24);
    const TriDexel before = model;
    std::mt19937 rng(99u);
    std::vector<Sweep> batch = random_batch(model.lattice, 20, rng);
    for (Sweep& s : batch) s.op = ToolOp::kSubtract;
    batch[15].tool.radius_m = -1.0;
    EXPECT_THROW(apply_sweeps_parallel(model, batch, 2), Error);
    batch[15].tool.radius_m = 0.002;
    batch[17].path_m.b.x = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(apply_sweeps_parallel(model, batch, 3), Error);
    EXPECT_EQ(differing_rays(model, before), 0u);
    EXPECT_EQ(model.tiles.dirty, before.tiles.dirty);
}

}  // namespace
