// Per-stroke undo and redo (compute::UndoHistory through app::SculptHistory): sequences of strokes, undos, redos
// and new strokes on the CPU and GPU paths give, bit for bit, the model rebuilt from scratch with the strokes that
// remain; the memory budget drops the oldest steps.
#include <gtest/gtest.h>

#include <optional>

#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"
#include "sweep_programs.hpp"

namespace tridex::app {
namespace {

using compute::Sweep;
using compute::TriDexel;
using compute::test::box_model;
using compute::test::compare;

constexpr int kCells = 48;
TriDexel fresh() { return box_model(kCells, 6.5, 41.5); }

// A random program cut into strokes of 20..90 sweeps.
std::vector<std::vector<Sweep>> strokes(std::uint32_t seed, int count) {
    const TriDexel m = fresh();
    const std::vector<Sweep> program = compute::test::random_program(m.lattice, 60 * count, seed);
    std::vector<std::vector<Sweep>> out;
    std::mt19937 rng(seed);
    std::size_t at = 0;
    while (static_cast<int>(out.size()) < count && at < program.size()) {
        const std::size_t n = std::min<std::size_t>(program.size() - at, 20 + rng() % 71);
        out.emplace_back(program.begin() + static_cast<std::ptrdiff_t>(at), program.begin() + static_cast<std::ptrdiff_t>(at + n));
        at += n;
    }
    return out;
}

// The model with `which` strokes applied in order, by the CPU reference from the untouched box.
TriDexel rebuilt(const std::vector<std::vector<Sweep>>& all, const std::vector<int>& which) {
    TriDexel m = fresh();
    for (const int k : which)
        for (const Sweep& s : all[static_cast<std::size_t>(k)]) compute::apply_sweep(m, s);
    return m;
}

struct Path {
    std::optional<gpu::Context> ctx;
    TriDexel model = fresh();
    std::unique_ptr<BooleanBackend> backend;
    explicit Path(bool gpu) {
        if (gpu) {
            ctx.emplace(gpu::Context::create({}));
            backend = make_boolean_backend_on(model, {BackendMode::kGpu}, *ctx).backend;
        } else {
            backend = make_cpu_backend(model);
        }
    }
    // The GPU slabs decoded, or the CPU model.
    TriDexel stored() const {
        if (!backend->gpu_slabs()) return model;
        TriDexel d = TriDexel::empty(model.lattice, std::size_t{1} << 30);
        backend->gpu_slabs()->download(d);
        return d;
    }
};

void expect_model(const Path& p, const TriDexel& want, const std::string& where) {
    EXPECT_EQ(compare(p.model, want).rays, 0u) << where << ": the CPU model";
    if (p.backend->gpu_slabs()) {
        EXPECT_EQ(compare(p.stored(), want).rays, 0u) << where << ": the GPU slabs";
    }
}

void stroke(SculptHistory& h, const std::vector<Sweep>& s) {
    // In a few batches, as the sculpt thread applies them.
    const std::size_t half = s.size() / 2;
    h.apply(std::span<const Sweep>(s).first(half));
    h.apply(std::span<const Sweep>(s).subspan(half));
    EXPECT_NE(h.end_stroke(), 0u);
}

void undo_redo_sequence(bool gpu) {
    const auto all = strokes(gpu ? 31u : 17u, 7);
    ASSERT_EQ(all.size(), 7u);
    Path p(gpu);
    SculptHistory h(p.model, *p.backend);
    for (int k = 0; k < 5; ++k) stroke(h, all[static_cast<std::size_t>(k)]);
    expect_model(p, rebuilt(all, {0, 1, 2, 3, 4}), "five strokes");

    p.model.clear_dirty();
    compute::UndoHistory::Change c = h.undo();
    EXPECT_EQ(c.serial, 5u);
    EXPECT_EQ(c.rays, compare(rebuilt(all, {0, 1, 2, 3}), rebuilt(all, {0, 1, 2, 3, 4})).rays)
        << "an undo writes back exactly the rays its stroke changed";
    EXPECT_NE(std::count(p.model.tiles.dirty.begin(), p.model.tiles.dirty.end(), std::uint8_t{1}), 0) << "the undone tiles are dirty";
    EXPECT_EQ(h.undo().serial, 4u);
    expect_model(p, rebuilt(all, {0, 1, 2}), "two undos");
    EXPECT_EQ(h.redo().serial, 4u);
    expect_model(p, rebuilt(all, {0, 1, 2, 3}), "a redo");
    for (int k = 0; k < 3; ++k) EXPECT_NE(h.undo().serial, 0u);
    expect_model(p, rebuilt(all, {0}), "three more undos");

    // A new stroke clears what could be redone.
    stroke(h, all[5]);
    EXPECT_EQ(h.redo().serial, 0u);
    expect_model(p, rebuilt(all, {0, 5}), "a new stroke after undos");
    EXPECT_EQ(h.undo().serial, 6u);
    EXPECT_EQ(h.undo().serial, 1u);
    EXPECT_EQ(h.undo().serial, 0u) << "nothing left to undo";
    expect_model(p, fresh(), "everything undone");
    EXPECT_EQ(h.redo().serial, 1u);
    EXPECT_EQ(h.redo().serial, 6u);
    expect_model(p, rebuilt(all, {0, 5}), "redone");

    // An open stroke is closed by undo, and undone with it.
    h.apply(all[6]);
    EXPECT_TRUE(h.stroke_open());
    EXPECT_EQ(h.undo().serial, 7u);
    EXPECT_FALSE(h.stroke_open());
    expect_model(p, rebuilt(all, {0, 5}), "an open stroke undone");

    const compute::HistoryStats st = h.stats();
    EXPECT_EQ(st.strokes, 7u);
    EXPECT_EQ(st.undo_steps, 2u);
    EXPECT_EQ(st.redo_steps, 1u);
    EXPECT_EQ(st.dropped_steps, 0u);
    EXPECT_GT(st.bytes, 0u);
    EXPECT_LE(st.bytes, st.budget_bytes);
    if (p.ctx) {
        EXPECT_EQ(p.ctx->validation_messages(), 0u);
    }
}

TEST(SculptHistory, UndoRedoAndNewStrokesMatchModelsRebuiltFromScratchOnTheCpu) { undo_redo_sequence(false); }

TEST(SculptHistory, UndoRedoAndNewStrokesMatchModelsRebuiltFromScratchOnTheGpu) { undo_redo_sequence(true); }

// Strokes whose rays hold more intervals than the GPU slabs keep inline (the spill pool) undo and redo exactly,
// and the pool holds as many intervals after redoing as before undoing.
TEST(SculptHistory, GpuUndoAndRedoOfRaysInTheSpillPoolStayExact) {
    const auto all = strokes(77u, 6);
    Path p(true);
    SculptHistory h(p.model, *p.backend);
    for (const auto& s : all) stroke(h, s);
    const std::uint64_t spilled = p.backend->spilled_intervals();
    EXPECT_GT(spilled, 0u);
    for (int k = 0; k < 6; ++k) EXPECT_NE(h.undo().serial, 0u);
    expect_model(p, fresh(), "six undos");
    for (int k = 0; k < 6; ++k) EXPECT_NE(h.redo().serial, 0u);
    expect_model(p, rebuilt(all, {0, 1, 2, 3, 4, 5}), "six redos");
    EXPECT_EQ(p.backend->spilled_intervals(), spilled);
    EXPECT_EQ(p.ctx->validation_messages(), 0u);
}

TEST(SculptHistory, TheBudgetDropsTheOldestStepsAndTheRestStillUndoExactly) {
    const auto all = strokes(5u, 7);
    // With room for everything: the largest open stroke's copies (C) and all steps kept (T).
    std::size_t largest_capture = 0, all_steps = 0;
    {
        Path p(false);
        SculptHistory h(p.model, *p.backend, std::size_t{1} << 30);
        for (const auto& s : all) {
            const std::size_t before = h.stats().bytes;
            h.apply(s);
            largest_capture = std::max(largest_capture, h.stats().bytes - before);
            h.end_stroke();
        }
        all_steps = h.stats().bytes;
        EXPECT_EQ(h.stats().undo_steps, 7u);
    }
    // Room for any one stroke but not for all of them.
    const std::size_t budget = std::max(largest_capture + largest_capture / 4, all_steps / 2);
    ASSERT_LT(budget, all_steps) << "captures " << largest_capture << " B, steps " << all_steps << " B";
    Path p(false);
    SculptHistory h(p.model, *p.backend, budget);
    for (const auto& s : all) stroke(h, s);
    const compute::HistoryStats st = h.stats();
    EXPECT_EQ(st.oversize_strokes, 0u);
    EXPECT_GT(st.dropped_steps, 0u);
    EXPECT_LE(st.bytes, st.budget_bytes);
    EXPECT_EQ(st.undo_steps + st.dropped_steps, 7u);
    std::size_t undone = 0;
    while (h.undo().serial != 0) ++undone;
    EXPECT_EQ(undone, st.undo_steps);
    std::vector<int> kept;
    for (std::size_t k = 0; k < 7 - undone; ++k) kept.push_back(static_cast<int>(k));
    expect_model(p, rebuilt(all, kept), "undone down to the oldest step kept");
}

TEST(SculptHistory, AStrokeLargerThanTheBudgetStaysAppliedAndEndsTheHistory) {
    const auto all = strokes(9u, 3);
    Path p(false);
    SculptHistory h(p.model, *p.backend, 4096);  // far less than any stroke's rays
    for (const auto& s : all) stroke(h, s);
    const compute::HistoryStats st = h.stats();
    EXPECT_EQ(st.oversize_strokes, 3u);
    EXPECT_EQ(st.undo_steps, 0u);
    EXPECT_EQ(st.bytes, 0u);
    EXPECT_EQ(h.undo().serial, 0u);
    expect_model(p, rebuilt(all, {0, 1, 2}), "nothing undone");
}

}  // namespace
}  // namespace tridex::app

namespace tridex::app {
namespace {

// A coarseness change on either path: the GPU slabs are made again for each lattice (the change, its undo, its redo),
// and strokes on the new lattice and their undos keep slabs and CPU model equal.
void coarseness_sequence(bool gpu) {
    const auto all = strokes(gpu ? 41u : 43u, 3);
    ASSERT_EQ(all.size(), 3u);
    Path p(gpu);
    SculptHistory h(p.model, *p.backend);
    stroke(h, all[0]);
    const TriDexel before = p.model;
    const compute::UndoHistory::Change c = h.resample(2 * kCells, std::size_t{1} << 30);
    EXPECT_TRUE(c.lattice);
    EXPECT_EQ(p.model.lattice.cells[0], 2 * kCells);
    const TriDexel fine = p.model;
    expect_model(p, fine, "after the change");
    stroke(h, all[1]);  // sweeps in world metres: the same strokes on the finer lattice
    expect_model(p, p.model, "a stroke on the finer lattice");
    EXPECT_EQ(h.undo().serial, 3u);
    expect_model(p, fine, "its undo");
    EXPECT_TRUE(h.undo().lattice);
    EXPECT_EQ(p.model.lattice.cells, before.lattice.cells);
    EXPECT_EQ(compare(p.model, before).rays, 0u) << "the old lattice's model, bit for bit";
    expect_model(p, before, "the change undone");
    stroke(h, all[2]);  // on the old lattice again: the change cannot be redone
    EXPECT_EQ(h.redo().serial, 0u);
    expect_model(p, rebuilt(all, {0, 2}), "a new stroke after the undo");
}

TEST(SculptHistory, ACoarsenessChangeAndItsUndoOnTheCpu) { coarseness_sequence(false); }

TEST(SculptHistory, ACoarsenessChangeAndItsUndoRemakeTheGpuSlabs) { coarseness_sequence(true); }

}  // namespace
}  // namespace tridex::app
