// SculptHistory and the journal with the grab: a grab stroke through the sculpt thread's history is one undo step
// that restores the start exactly, its journal replays (and after an undo and a redo, too) to the same model bit for
// bit, its samples survive the journal's byte form, and the GPU path (the GPU clay kernel) gives the CPU path's model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include "clay_test_models.hpp"
#include "compute/journal/journal_format.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"

namespace tridex::compute {
namespace {

using clay_test::cube_lattice;
using clay_test::from_implicit;

/// A sphere of radius 10 cells with a small one (radius 3) above its top-left.
TriDexel two_spheres() {
    return from_implicit(cube_lattice(48), [](double x, double y, double z) {
        const double big = glm::length(Vec3(x, y, z) - Vec3(26.0, 24.0, 18.0)) - 10.0;
        const double small = glm::length(Vec3(x, y, z) - Vec3(12.3, 24.2, 34.4)) - 3.0;
        return std::min(big, small);
    });
}

/// Two grab strokes as the haptic loop makes them (a sample per tick, the first with the button still up): the small
/// sphere carried right and down, then a cap drawn out of the big one.
std::vector<std::vector<ToolSample>> strokes(const Lattice& L) {
    std::vector<std::vector<ToolSample>> out(2);
    const auto sample = [&](const Vec3& grid, double t) {
        ToolSample s;
        s.t_s = t;
        s.position = L.origin_m + L.cell_m * grid;
        s.tool.radius_m = 3.0 * L.cell_m;
        s.op = ToolOp::kGrab;
        return s;
    };
    for (int i = 0; i <= 40; ++i)
        out[0].push_back(sample(Vec3(12.3 + 0.15 * i, 24.2, 34.4 + 6.0 - 0.05 * i), 1e-3 * i));
    for (int i = 0; i <= 30; ++i) out[1].push_back(sample(Vec3(26.1, 23.9, 18.0 + 13.0 + 0.2 * i), 0.1 + 1e-3 * i));
    for (std::vector<ToolSample>& stroke : out) stroke.front().op = ToolOp::kNone;  // the button goes down after it
    return out;
}

std::vector<Sweep> sweeps_of(const std::vector<ToolSample>& samples) {
    std::vector<Sweep> out;
    for (std::size_t i = 1; i < samples.size(); ++i) {
        Sweep s;
        if (sample_sweep(samples[i - 1], samples[i], nullptr, s)) out.push_back(s);
    }
    return out;
}

TEST(SculptHistoryGrab, GrabSamplesSurviveTheJournalsByteForm) {
    ToolSample s, back;
    s.op = ToolOp::kGrab;
    unsigned char b[kJournalSampleBytes];
    encode_sample(s, b);
    ASSERT_TRUE(decode_sample(b, back));
    EXPECT_EQ(back.op, ToolOp::kGrab);
    EXPECT_STREQ(tool_op_name(back.op), "grab");
    b[113] = static_cast<unsigned char>(ToolOp::kGrab) + 1;  // no such operation
    EXPECT_FALSE(decode_sample(b, back));
}

TEST(SculptHistoryGrab, AGrabStrokeIsOneUndoStepAndItsJournalReplaysBitForBit) {
    TriDexel live = two_spheres();
    const TriDexel start = live;
    const std::vector<std::vector<ToolSample>> ss = strokes(live.lattice);
    std::vector<JournalRecord> records;
    const auto add = [&](JournalKind kind, std::uint64_t serial, const std::vector<ToolSample>* samples,
                         std::uint64_t rays = 0) {
        JournalRecord r;
        r.kind = kind;
        r.index = records.size();
        r.serial = serial;
        r.rays = rays;
        if (samples) r.samples = *samples;
        records.push_back(std::move(r));
    };
    std::uint64_t after_both = 0, after_first = 0;
    {
        const std::unique_ptr<app::BooleanBackend> cpu = app::make_cpu_backend(live);
        app::SculptHistory history(live, *cpu);
        std::uint64_t serial = 0;
        for (const std::vector<ToolSample>& stroke : ss) {
            const std::vector<Sweep> sweeps = sweeps_of(stroke);
            // Applied in batches of 7 sweeps (sweep j goes from sample j to j + 1), journalled as the batches'
            // samples, each sample once.
            ASSERT_EQ(sweeps.size() + 1, stroke.size());
            for (std::size_t i = 0; i < sweeps.size(); i += 7) {
                const std::size_t n = std::min<std::size_t>(7, sweeps.size() - i);
                history.apply(std::span<const Sweep>(sweeps).subspan(i, n));
                const std::vector<ToolSample> part(stroke.begin() + static_cast<std::ptrdiff_t>(i == 0 ? 0 : i + 1),
                                                   stroke.begin() + static_cast<std::ptrdiff_t>(i + n + 1));
                add(JournalKind::kBatch, 0, &part);
            }
            serial = history.end_stroke();
            ASSERT_NE(serial, 0u);
            add(JournalKind::kStrokeEnd, serial, nullptr);
            if (&stroke == &ss[0]) after_first = model_digest(live);
        }
        after_both = model_digest(live);
        EXPECT_NE(after_both, after_first);
        EXPECT_NE(after_first, model_digest(start));
        // One undo per stroke: the second stroke's undo gives the model after the first exactly, the first's the start.
        const auto undone = history.undo();
        EXPECT_EQ(undone.serial, serial);
        add(JournalKind::kUndo, undone.serial, nullptr, undone.rays);
        EXPECT_EQ(model_digest(live), after_first);
        const auto redone = history.redo();
        EXPECT_EQ(redone.serial, serial);
        add(JournalKind::kRedo, redone.serial, nullptr, redone.rays);
        EXPECT_EQ(model_digest(live), after_both);
    }
    // The journal replays to the live model, bit for bit.
    TriDexel again = two_spheres();
    journal_apply(again, records);
    EXPECT_EQ(model_digest(again), after_both);
    EXPECT_TRUE(clay_test::same_rays(again, live));
}

TEST(SculptHistoryGrab, AGrabStrokeGivesOneModelHoweverItsSweepsAreSplitIntoBatches) {
    // Short grab sweeps that join end to end go as one motion per group (apply_clay_batch); SculptHistory holds the
    // open group back, so batches of 1, 3, 7 and the whole stroke give the model of the whole stroke at once.
    const std::vector<std::vector<ToolSample>> ss = strokes(two_spheres().lattice);
    const std::vector<Sweep> stroke = sweeps_of(ss[0]);
    TriDexel whole = two_spheres();
    apply_clay_batch(whole, stroke);
    EXPECT_FALSE(clay_test::same_rays(whole, two_spheres()));
    for (const std::size_t size : {std::size_t{1}, std::size_t{3}, std::size_t{7}, stroke.size()}) {
        TriDexel m = two_spheres();
        const std::unique_ptr<app::BooleanBackend> cpu = app::make_cpu_backend(m);
        app::SculptHistory history(m, *cpu);
        std::size_t held_max = 0;
        for (std::size_t i = 0; i < stroke.size(); i += size) {
            history.apply(std::span<const Sweep>(stroke).subspan(i, std::min(size, stroke.size() - i)));
            held_max = std::max(held_max, history.held());
        }
        EXPECT_GT(held_max, 0u) << "batches of " << size;
        EXPECT_NE(history.end_stroke(), 0u);
        EXPECT_EQ(history.held(), 0u);
        EXPECT_TRUE(clay_test::same_rays(m, whole)) << "batches of " << size;
    }
    // Applied sweep by sweep (no groups) the same stroke gives another model, close to it.
    TriDexel one_by_one = two_spheres();
    for (const Sweep& s : stroke) apply_clay(one_by_one, s);
    EXPECT_FALSE(clay_test::same_rays(one_by_one, whole));
}

TEST(SculptHistoryGrab, TheGpuPathGivesTheCpuPathsModelAndUndoRestores) {
    TriDexel cpu_model = two_spheres();
    const TriDexel start = cpu_model;
    TriDexel gpu_model = cpu_model;
    const std::unique_ptr<app::BooleanBackend> cpu = app::make_cpu_backend(cpu_model);
    app::BackendChoice gpu;
    try {  // the GPU clay kernel forced, as on a discrete GPU
        gpu = app::make_boolean_backend(gpu_model, {app::BackendMode::kGpu, false, true}, false);
    } catch (const tridex::Error& e) {
        GTEST_SKIP() << "no Vulkan device: " << e.what();
    }
    app::SculptHistory hc(cpu_model, *cpu), hg(gpu_model, *gpu.backend);
    for (const std::vector<ToolSample>& stroke : strokes(cpu_model.lattice)) {
        const std::vector<Sweep> sweeps = sweeps_of(stroke);
        hc.apply(sweeps);
        hg.apply(sweeps);
        hc.end_stroke();
        hg.end_stroke();
        EXPECT_EQ(model_digest(cpu_model), model_digest(gpu_model));
    }
    EXPECT_NE(model_digest(cpu_model), model_digest(start));
    const compute::GpuClayStats* clay = gpu.backend->gpu_clay_stats();
    ASSERT_NE(clay, nullptr);
    EXPECT_GT(clay->fields, 5u);  // the short sweeps in groups, one field step each
    EXPECT_EQ(clay->host_fields, 0u);
    for (int k = 0; k < 2; ++k) {
        EXPECT_NE(hc.undo().serial, 0u);
        EXPECT_NE(hg.undo().serial, 0u);
    }
    EXPECT_TRUE(clay_test::same_rays(cpu_model, start));
    EXPECT_TRUE(clay_test::same_rays(gpu_model, start));
    EXPECT_EQ(gpu.backend->gpu_context()->validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::compute
