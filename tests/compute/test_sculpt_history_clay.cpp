// SculptHistory with the clay tools: a push or smooth stroke's groups (apply_clay_batch) held back at the end of a batch so
// that the model does not depend on how the stroke's samples were split into batches, and undo with held sweeps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include "clay_test_models.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "core/error.hpp"

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
    // The same for each group size a session may record (SessionSpec::clay_group_sweeps), set on the backend.
    for (const std::size_t group : {kClayGroupSweeps, std::size_t{16}}) {
        std::vector<TriDexel> models;
        for (const std::size_t size : {std::size_t{1}, std::size_t{3}, std::size_t{7}, stroke.size()}) {
            TriDexel m = slab();
            const std::unique_ptr<app::BooleanBackend> cpu = app::make_cpu_backend(m);
            cpu->set_clay_group_sweeps(group);
            app::SculptHistory history(m, *cpu);
            std::size_t held_max = 0;
            for (std::size_t i = 0; i < stroke.size(); i += size) {
                history.apply(std::span<const Sweep>(stroke).subspan(i, std::min(size, stroke.size() - i)));
                held_max = std::max(held_max, history.held());
            }
            EXPECT_GT(held_max, 0u) << "batches of " << size << ", groups of " << group;
            EXPECT_LE(held_max, group) << "batches of " << size << ", groups of " << group;
            compute::BooleanStats flushed;
            EXPECT_NE(history.end_stroke(&flushed), 0u);
            EXPECT_EQ(history.held(), 0u);
            models.push_back(std::move(m));
        }
        TriDexel whole = slab();
        apply_clay_batch(whole, stroke, nullptr, clay_cpu_kernel(), group);
        for (std::size_t k = 0; k < models.size(); ++k)
            EXPECT_TRUE(clay_test::same_rays(models[k], whole)) << "split " << k << ", groups of " << group;
    }
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

// A journal's replay groups clay sweeps by the size its session recorded (JournalApplyFrom::clay_group_sweeps): a slow
// push stroke journalled by a session that grouped 16 replays to that session's model, not to the default's.
TEST(SculptHistoryClay, AJournalReplaysWithTheGroupSizeItsSessionUsed) {
    const Lattice L = slab().lattice;
    std::vector<ToolSample> samples(120);
    for (std::size_t i = 0; i < samples.size(); ++i) {
        samples[i].t_s = 1e-3 * static_cast<double>(i);
        const double x = 14.0 + 0.04 * static_cast<double>(i);  // grid units: a slow hand
        samples[i].position = L.origin_m + L.cell_m * Vec3(x, 24.2, kZ0 + 1.0);
        samples[i].tool.radius_m = 2.0 * L.cell_m;
        samples[i].op = ToolOp::kPush;
    }
    std::vector<JournalRecord> records;
    for (std::size_t i = 0; i < samples.size(); i += 37) {
        JournalRecord r;
        r.index = records.size();
        r.samples.assign(samples.begin() + static_cast<std::ptrdiff_t>(i),
                         samples.begin() + static_cast<std::ptrdiff_t>(std::min(samples.size(), i + 37)));
        records.push_back(std::move(r));
    }
    JournalRecord end;
    end.kind = JournalKind::kStrokeEnd;
    end.index = records.size();
    end.serial = 1;
    records.push_back(end);
    // The session: its sweeps through SculptHistory on a backend grouping 16.
    TriDexel live = slab();
    {
        const std::unique_ptr<app::BooleanBackend> cpu = app::make_cpu_backend(live);
        cpu->set_clay_group_sweeps(16);
        app::SculptHistory history(live, *cpu);
        for (std::size_t i = 1; i < samples.size(); ++i) {
            Sweep s;
            ASSERT_TRUE(sample_sweep(samples[i - 1], samples[i], nullptr, s));
            history.apply(std::span<const Sweep>(&s, 1));
        }
        EXPECT_EQ(history.end_stroke(), 1u);
    }
    JournalApplyFrom from;
    from.clay_group_sweeps = 16;
    TriDexel again = slab(), by_default = slab();
    journal_apply(again, records, from);
    journal_apply(by_default, records);
    EXPECT_EQ(model_digest(again), model_digest(live)) << "the replay must group as the session did";
    EXPECT_NE(model_digest(by_default), model_digest(live)) << "the group size must decide the model";
    from.clay_group_sweeps = 0;
    TriDexel refused = slab();
    EXPECT_THROW(journal_apply(refused, records, from), Error);
}

}  // namespace
}  // namespace tridex::compute
