// Per-stroke undo and redo (compute::UndoHistory through app::SculptHistory): sequences of strokes, undos, redos
// and new strokes on the CPU and GPU paths give, bit for bit, the model rebuilt from scratch with the strokes that
// remain; the memory budget drops the oldest steps; the sculpt thread's strokes, undos and redos replay from its
// journal to the same dexels.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <thread>

#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"
#include "sweep_programs.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
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
            backend = make_boolean_backend_on(model, false, *ctx).backend;
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

// ---- The sculpt thread: strokes from the samples, requests, and its journal ----------------------------------

// A pass along x over the box's +z face at height y, `n` samples from t0_s at 1 kHz.
std::vector<ToolSample> pass(double y, double t0_s, int n, ToolOp op) {
    std::vector<ToolSample> s(static_cast<std::size_t>(n));
    const TriDexel m = fresh();
    const Vec3 top = m.lattice.to_world(Vec3(24.0, 24.0, 41.5));
    for (int i = 0; i < n; ++i) {
        const double u = i / (n - 1.0);
        s[static_cast<std::size_t>(i)].t_s = t0_s + i * 1e-3;
        s[static_cast<std::size_t>(i)].position = top + Vec3(-0.015 + 0.03 * u, y, -0.002);
        s[static_cast<std::size_t>(i)].tool.radius_m = 0.004;
        s[static_cast<std::size_t>(i)].op = op;
        s[static_cast<std::size_t>(i)].material = 2;
    }
    return s;
}

void push_all(SpscRing<ToolSample>& ring, const std::vector<ToolSample>& s) {
    for (const ToolSample& x : s)
        while (!ring.try_push(x)) std::this_thread::yield();
}

void wait_drained(const SpscRing<ToolSample>& ring) {
    while (ring.size() > 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::this_thread::sleep_for(std::chrono::milliseconds(30));  // the step that took the last samples finishes
}

TEST(SculptThreadHistory, StrokesUndosAndRedosReplayFromTheJournalToTheSameDexels) {
    const std::string path = (fs::temp_directory_path() / ("tridex_history_" + std::to_string(::getpid()) + ".tdj")).string();
    TriDexel live = fresh();
    SculptStats stats;
    {
        compute::Contourer contourer(live);
        contourer.update(live);
        SpscRing<ToolSample> ring(4096);
        TripleBuffer<ActiveSurface> surface;
        compute::JournalWriter journal(path, "session", std::chrono::milliseconds(5));
        SculptThread t(live, contourer, ring, surface, Vec3(0.0));
        t.use_journal(journal);
        t.start();
        auto a = pass(-0.01, 0.0, 200, ToolOp::kSubtract);   // stroke 1
        auto lift = pass(-0.01, 0.2, 5, ToolOp::kNone);      // the tool lifted: stroke 1 closes
        auto b = pass(0.0, 0.205, 200, ToolOp::kSubtract);   // stroke 2
        auto c = pass(0.01, 0.405, 200, ToolOp::kUnion);     // an op change closes stroke 2; stroke 3
        push_all(ring, a);
        push_all(ring, lift);
        push_all(ring, b);
        push_all(ring, c);
        wait_drained(ring);
        const std::uint64_t seq = surface.latest().sequence;
        EXPECT_TRUE(t.request(SculptRequest::kUndo));  // stroke 3 (open) closes and is undone
        EXPECT_TRUE(t.request(SculptRequest::kUndo));  // stroke 2
        EXPECT_TRUE(t.request(SculptRequest::kRedo));  // stroke 2 again
        wait_drained(ring);
        EXPECT_GT(surface.latest().sequence, seq) << "the active surface follows an undo at once";
        auto d = pass(0.015, 0.7, 150, ToolOp::kSubtract);  // stroke 4: the redo of stroke 3 is gone
        push_all(ring, d);
        wait_drained(ring);
        EXPECT_TRUE(t.request(SculptRequest::kRedo));  // nothing to redo
        t.stop();
        stats = t.stats();
        EXPECT_EQ(journal.stats().error, "");
    }
    EXPECT_EQ(stats.undo_requests, 2u);
    EXPECT_EQ(stats.redo_requests, 2u);
    EXPECT_EQ(stats.undo_ms.size(), 3u);  // two undos and one redo changed the model
    EXPECT_EQ(stats.history.undos, 2u);
    EXPECT_EQ(stats.history.redos, 1u);
    EXPECT_EQ(stats.history.strokes, 4u);
    EXPECT_EQ(stats.history.undo_steps, 3u);
    EXPECT_EQ(stats.history.redo_steps, 0u);

    // The journal holds the closes, undos and redos between its batches; replaying it gives the same dexels.
    const compute::Journal j = compute::read_journal(path);
    EXPECT_FALSE(j.cut);
    std::size_t ends = 0, undos = 0, redos = 0;
    for (const auto& r : j.records) {
        ends += r.kind == compute::JournalKind::kStrokeEnd;
        undos += r.kind == compute::JournalKind::kUndo;
        redos += r.kind == compute::JournalKind::kRedo;
    }
    EXPECT_GE(ends, 3u);
    EXPECT_EQ(undos, 2u);
    EXPECT_EQ(redos, 1u);
    TriDexel again = fresh();
    const compute::JournalApplyStats st = compute::journal_apply(again, j.records);
    EXPECT_EQ(st.undos, 2u);
    EXPECT_EQ(st.redos, 1u);
    EXPECT_EQ(compare(live, again).rays, 0u);

    // And it is strokes 1, 2 and 4: stroke 3's union is gone (stroke 4 begins with the sweep from stroke 3's last
    // sample, which it carves).
    std::vector<compute::JournalRecord> runs(1);
    ToolSample c_last = pass(0.01, 0.405, 200, ToolOp::kNone).back();
    for (const auto& part : {pass(-0.01, 0.0, 200, ToolOp::kSubtract), pass(-0.01, 0.2, 5, ToolOp::kNone),
                             pass(0.0, 0.205, 200, ToolOp::kSubtract), std::vector<ToolSample>{c_last},
                             pass(0.015, 0.7, 150, ToolOp::kSubtract)})
        for (const ToolSample& x : part) runs[0].samples.push_back(x);
    TriDexel expect = fresh();
    compute::journal_apply(expect, runs);
    EXPECT_EQ(compare(live, expect).rays, 0u);

    // A replay that disagrees with a mark is refused, naming the record.
    std::vector<compute::JournalRecord> wrong = j.records;
    for (auto& r : wrong)
        if (r.kind == compute::JournalKind::kUndo) {
            r.serial += 7;
            break;
        }
    TriDexel w = fresh();
    try {
        compute::journal_apply(w, wrong);
        ADD_FAILURE() << "a wrong undo mark replayed";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("journal record "), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("undo of stroke"), std::string::npos) << e.what();
    }
    fs::remove(path);
}

// Checkpoints: written between strokes by the sculpt thread, named in the journal; replaying the records after the
// last one onto it gives the live model.
TEST(SculptThreadHistory, CheckpointsAreWrittenBetweenStrokesAndTheJournalContinuesFromThem) {
    const fs::path dir = fs::temp_directory_path() / ("tridex_ckpt_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string path = (dir / "s.tdj").string();
    TriDexel live = fresh();
    std::vector<TriDexel> written;
    SculptStats stats;
    {
        compute::Contourer contourer(live);
        contourer.update(live);
        SpscRing<ToolSample> ring(4096);
        TripleBuffer<ActiveSurface> surface;
        compute::JournalWriter journal(path, "session", std::chrono::milliseconds(5));
        SculptThread t(live, contourer, ring, surface, Vec3(0.0));
        t.use_journal(journal);
        t.use_checkpoints(
            [&](const TriDexel& m) {
                written.push_back(m);  // stands in for the .tdx file
                return CheckpointFile{"ck" + std::to_string(written.size()) + ".tdx", 100, 7};
            },
            0.01);
        t.start();
        push_all(ring, pass(-0.01, 0.0, 200, ToolOp::kSubtract));
        push_all(ring, pass(-0.01, 0.2, 3, ToolOp::kNone));
        wait_drained(ring);
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        push_all(ring, pass(0.01, 0.3, 200, ToolOp::kSubtract));
        wait_drained(ring);
        EXPECT_TRUE(t.request(SculptRequest::kUndo));  // undoes the stroke after the first checkpoint
        wait_drained(ring);
        t.stop();
        stats = t.stats();
    }
    EXPECT_EQ(stats.checkpoint_error, "");
    ASSERT_GE(stats.checkpoints, 1u);
    ASSERT_EQ(written.size(), stats.checkpoints);
    const compute::Journal j = compute::read_journal(path);
    std::size_t ck = j.records.size(), seen = 0;
    for (std::size_t k = 0; k < j.records.size(); ++k)
        if (j.records[k].kind == compute::JournalKind::kCheckpoint) {
            ck = k;
            ++seen;
            EXPECT_EQ(j.records[k].checkpoint, "ck" + std::to_string(seen) + ".tdx");
        }
    ASSERT_EQ(seen, written.size());
    TriDexel from = written.back();
    compute::journal_apply(from, j.records, {ck + 1, compute::journal_last_serial(j.records, ck), compute::UndoHistory::kDefaultBudgetBytes});
    EXPECT_EQ(compare(live, from).rays, 0u);
    // The first checkpoint holds the first stroke only.
    EXPECT_EQ(compare(written.front(), live).rays, 0u) << "the second stroke was undone";
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
