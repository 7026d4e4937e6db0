// SculptHistory with the clay tools: a push or smooth stroke's groups (apply_clay_batch) held back at the end of a batch so
// that the model does not depend on how the stroke's samples were split into batches, and undo with held sweeps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include "clay_test_models.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "compute/tools/clay_sweep.hpp"

namespace tridex::compute {
namespace {

using clay_test::clay_sweep;
using clay_test::cube_lattice;
using clay_test::from_implicit;

constexpr double kZ0 = 20.3;  // the slab's top face, grid units

TriDexel slab() { return from_implicit(cube_lattice(48), clay_test::slab(kZ0)); }

TEST(SculptHistoryClay, AStrokeGivesOneModelHoweverItsSweepsAreSplitIntoBatches) {
    // A wandering push stroke with a subtract in the middle that goes on as a smooth, through SculptHistory as the
    // sculpt thread and journal replay use it, split into batches of 1, 3, 7 and all at once.
    std::vector<Sweep> stroke;
    Vec3 p(14.0, 20.0, kZ0 + 2.0 - 0.8);
    for (int k = 0; k < 90; ++k) {
        const Vec3 q = p + Vec3(0.31 + 0.2 * std::sin(0.3 * k), 0.25 * std::cos(0.2 * k), 0.0);
        stroke.push_back(clay_sweep(k < 60 ? ToolOp::kPush : ToolOp::kSmooth, p, q, 2.0));
        p = q;
    }
    stroke[45].op = ToolOp::kSubtract;
    std::vector<TriDexel> models;
    for (const std::size_t size : {std::size_t{1}, std::size_t{3}, std::size_t{7}, stroke.size()}) {
        TriDexel m = slab();
        const std::unique_ptr<app::BooleanBackend> cpu = app::make_cpu_backend(m);
        app::SculptHistory history(m, *cpu);
        std::size_t held_max = 0;
        for (std::size_t i = 0; i < stroke.size(); i += size) {
            history.apply(std::span<const Sweep>(stroke).subspan(i, std::min(size, stroke.size() - i)));
            held_max = std::max(held_max, history.held());
        }
        EXPECT_GT(held_max, 0u) << "batches of " << size;
        EXPECT_LE(held_max, kClayGroupSweeps) << "batches of " << size;
        compute::BooleanStats flushed;
        EXPECT_NE(history.end_stroke(&flushed), 0u);
        EXPECT_EQ(history.held(), 0u);
        models.push_back(std::move(m));
    }
    TriDexel whole = slab();
    apply_clay_batch(whole, stroke);
    for (std::size_t k = 0; k < models.size(); ++k) EXPECT_TRUE(clay_test::same_rays(models[k], whole)) << "split " << k;
    // Undo restores the start exactly, held sweeps included.
    TriDexel m = slab();
    const TriDexel start = m;
    const std::unique_ptr<app::BooleanBackend> cpu = app::make_cpu_backend(m);
    app::SculptHistory history(m, *cpu);
    history.apply(std::span<const Sweep>(stroke).first(45));
    ASSERT_GT(history.held(), 0u);
    EXPECT_NE(history.undo().serial, 0u);
    EXPECT_TRUE(clay_test::same_rays(m, start));
}

}  // namespace
}  // namespace tridex::compute
