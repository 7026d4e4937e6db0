// The sculpt thread's strokes (closed at a lift, an op change, a request), its undo and redo requests, and its
// checkpoints, replayed from its journal to the same dexels. CPU only (run under ThreadSanitizer).
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"
#include "island_models.hpp"
#include "sculpt_passes.hpp"
#include "sweep_programs.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using compute::TriDexel;
using compute::test::box_model;
using compute::test::compare;

constexpr int kCells = 48;
TriDexel fresh() { return box_model(kCells, 6.5, 41.5); }

using test::pass;
using test::push_all;
using test::wait_drained;

// A sculpt thread on `model` with its contourer (contoured once), a ring of 4096 samples and a surface hand-off.
struct Rig {
    explicit Rig(TriDexel& model) : contourer(model), contoured((contourer.update(model), true)),
                                    thread(model, contourer, ring, surface, Vec3(0.0)) {}
    compute::Contourer contourer;
    bool contoured;
    SpscRing<ToolSample> ring{4096};
    TripleBuffer<ActiveSurface> surface;
    SculptThread thread;
};

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
        wait_drained(ring, t);
        const std::uint64_t seq = surface.latest().sequence;
        EXPECT_TRUE(t.request(SculptRequest::kUndo));  // stroke 3 (open) closes and is undone
        EXPECT_TRUE(t.request(SculptRequest::kUndo));  // stroke 2
        EXPECT_TRUE(t.request(SculptRequest::kRedo));  // stroke 2 again
        wait_drained(ring, t);
        EXPECT_GT(surface.latest().sequence, seq) << "the active surface follows an undo at once";
        auto d = pass(0.015, 0.7, 150, ToolOp::kSubtract);  // stroke 4: the redo of stroke 3 is gone
        push_all(ring, d);
        wait_drained(ring, t);
        EXPECT_TRUE(t.request(SculptRequest::kRedo));  // nothing to redo
        t.stop();
        stats = t.stats();
        EXPECT_EQ(journal.stats().error, "");
    }
    EXPECT_EQ(stats.undo_requests, 2u);
    EXPECT_EQ(stats.redo_requests, 2u);
    EXPECT_EQ(stats.undo_ms.size(), 3u);  // two undos and one redo changed the model
    ASSERT_EQ(stats.undo_restore_ms.size(), 3u);
    ASSERT_EQ(stats.undo_contour_ms.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i)
        EXPECT_LE(stats.undo_restore_ms[i] + stats.undo_contour_ms[i], stats.undo_ms[i]);
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

// With idle closing off (the mouse stylus: a stroke is the held button), holding still mid-stroke for 0.7 s of device
// time keeps the stroke one undo step.
TEST(SculptThreadHistory, IdleClosingCanBeTurnedOffForHeldButtonStrokes) {
    for (const bool idle_close : {false}) {
        TriDexel live = fresh();
        SculptStats stats;
        {
            Rig rig(live);
            SpscRing<ToolSample>& ring = rig.ring;
            SculptThread& t = rig.thread;
            t.strokes_end_on_release(!idle_close);
            t.start();
            auto a = pass(-0.01, 0.0, 200, ToolOp::kSubtract);
            std::vector<ToolSample> hold(700, a.back());  // the tool held still where the pass ended
            for (std::size_t i = 0; i < hold.size(); ++i) hold[i].t_s = a.back().t_s + 1e-3 * static_cast<double>(i + 1);
            auto b = pass(0.0, hold.back().t_s + 1e-3, 200, ToolOp::kSubtract);
            push_all(ring, a);
            wait_drained(ring, t);
            for (std::size_t k = 0; k < hold.size(); k += 100) {  // in batches, as samples arrive at 1 kHz
                push_all(ring, std::vector<ToolSample>(hold.begin() + static_cast<std::ptrdiff_t>(k),
                                                       hold.begin() + static_cast<std::ptrdiff_t>(k + 100)));
                wait_drained(ring, t);
            }
            push_all(ring, b);
            wait_drained(ring, t);
            t.stop();
            stats = t.stats();
        }
        EXPECT_EQ(stats.history.strokes, 1u) << "idle closing off";
    }
}

// With strokes that end on release (the mouse's left button), an undo asked while the tool still cuts (the request
// reached the thread before the release did) waits for the release and takes back the whole drag: the model is the
// fresh box again, one stroke, its mark after the release sample. With idle closing (a force device) the same order
// undoes only the part before the request, and the rest of the drag stays carved.
TEST(SculptThreadHistory, AnUndoAskedDuringAHeldStrokeWaitsForTheRelease) {
    for (const bool held : {true, false}) {
        TriDexel live = fresh();
        SculptStats stats;
        {
            Rig rig(live);
            SculptThread& t = rig.thread;
            t.strokes_end_on_release(held);
            t.start();
            push_all(rig.ring, pass(-0.01, 0.0, 200, ToolOp::kSubtract));
            wait_drained(rig.ring, t);
            EXPECT_TRUE(t.request(SculptRequest::kUndo));
            wait_drained(rig.ring, t);
            push_all(rig.ring, pass(0.0, 0.2, 200, ToolOp::kSubtract));  // the drag goes on: the button still held
            wait_drained(rig.ring, t);
            push_all(rig.ring, pass(0.0, 0.4, 5, ToolOp::kNone));  // released
            wait_drained(rig.ring, t);
            t.stop();
            stats = t.stats();
        }
        const std::size_t diff = compare(live, fresh()).rays;
        ASSERT_EQ(stats.marks.size(), 1u) << held;
        EXPECT_EQ(stats.marks[0].request, SculptRequest::kUndo);
        EXPECT_EQ(stats.history.undos, 1u) << held;
        if (held) {
            EXPECT_EQ(diff, 0u) << "the whole drag is taken back";
            EXPECT_EQ(stats.history.strokes, 1u);
            EXPECT_EQ(stats.marks[0].after_samples, 401u) << "taken at the release sample";
            EXPECT_EQ(stats.held_requests, 1u);
        } else {
            EXPECT_GT(diff, 0u) << "idle closing undoes at once: the drag's rest stays";
            EXPECT_EQ(stats.history.strokes, 2u);
            EXPECT_EQ(stats.marks[0].after_samples, 200u);
            EXPECT_EQ(stats.held_requests, 0u);
        }
    }
}

// With strokes that end on release, undo requests asked during a drag the session ends in are taken when the thread
// stops, after the drag's stroke closes; redo waits behind an undo in order.
TEST(SculptThreadHistory, RequestsHeldWhenTheSessionEndsMidDragAreTakenAtStop) {
    TriDexel live = fresh();
    SculptStats stats;
    {
        Rig rig(live);
        SculptThread& t = rig.thread;
        t.strokes_end_on_release(true);
        t.start();
        push_all(rig.ring, pass(-0.01, 0.0, 200, ToolOp::kSubtract));
        push_all(rig.ring, pass(-0.01, 0.2, 5, ToolOp::kNone));
        push_all(rig.ring, pass(0.01, 0.4, 200, ToolOp::kSubtract));  // the second drag, never released
        wait_drained(rig.ring, t);
        EXPECT_TRUE(t.request(SculptRequest::kUndo));
        EXPECT_TRUE(t.request(SculptRequest::kUndo));
        EXPECT_TRUE(t.request(SculptRequest::kRedo));
        wait_drained(rig.ring, t);
        EXPECT_EQ(t.requests_held(), 3u);
        push_all(rig.ring, pass(0.01, 0.6, 200, ToolOp::kSubtract));  // the drag goes on, back across
        wait_drained(rig.ring, t);
        t.stop();
        stats = t.stats();
    }
    ASSERT_EQ(stats.marks.size(), 3u);
    EXPECT_EQ(stats.marks[0].request, SculptRequest::kUndo);
    EXPECT_EQ(stats.marks[1].request, SculptRequest::kUndo);
    EXPECT_EQ(stats.marks[2].request, SculptRequest::kRedo);
    EXPECT_EQ(stats.history.strokes, 2u);
    EXPECT_EQ(stats.history.undos, 2u);
    EXPECT_EQ(stats.history.redos, 1u);
    EXPECT_EQ(stats.held_requests, 3u);
    EXPECT_EQ(stats.marks[0].after_samples, 605u) << "taken at stop, after the whole drag";
    // The second drag (both passes) undone, the first undone and redone: the first drag's groove alone.
    TriDexel expect = fresh();
    {
        Rig rig(expect);
        rig.thread.start();
        push_all(rig.ring, pass(-0.01, 0.0, 200, ToolOp::kSubtract));
        push_all(rig.ring, pass(-0.01, 0.2, 5, ToolOp::kNone));
        wait_drained(rig.ring, rig.thread);
        rig.thread.stop();
    }
    EXPECT_EQ(compare(live, expect).rays, 0u);
}

// A replay of the same samples that follows the live thread's marks (SculptStats::marks) repeats its undos, redos and
// stroke closes where the live thread took them, however differently its samples are batched: the same dexels bit for
// bit. Without the marks the same samples give another model (the check can fail).
TEST(SculptThreadHistory, ReplayFollowingTheMarksRepeatsUndosRedosAndIdleClosesExactly) {
    auto a = pass(-0.01, 0.0, 200, ToolOp::kSubtract);  // stroke 1, undone mid-drag
    auto b = pass(0.0, 0.2, 200, ToolOp::kSubtract);    // stroke 2 (the drag goes on), closed by a request
    auto c = pass(0.01, 0.4, 200, ToolOp::kUnion);      // stroke 3, closed for idling in the air
    std::vector<ToolSample> air = pass(0.01, 0.6, 700, ToolOp::kUnion);
    for (ToolSample& x : air) x.position.z += 0.03;     // well above the box: changes nothing
    auto e = pass(0.015, 1.3, 200, ToolOp::kUnion);     // stroke 4, undone and redone
    std::vector<ToolSample> all;
    for (const auto* part : {&a, &b, &c, &air, &e}) all.insert(all.end(), part->begin(), part->end());
    TriDexel live = fresh();
    SculptStats stats;
    {
        Rig rig(live);
        SpscRing<ToolSample>& ring = rig.ring;
        SculptThread& t = rig.thread;
        t.start();
        push_all(ring, a);
        wait_drained(ring, t);
        EXPECT_TRUE(t.request(SculptRequest::kUndo));
        push_all(ring, b);
        wait_drained(ring, t);
        EXPECT_TRUE(t.request(SculptRequest::kEndStroke));
        push_all(ring, c);
        wait_drained(ring, t);
        for (std::size_t k = 0; k < air.size(); k += 100) {  // as samples arrive at 1 kHz: the idle close falls between
            push_all(ring, std::vector<ToolSample>(air.begin() + static_cast<std::ptrdiff_t>(k),
                                                   air.begin() + static_cast<std::ptrdiff_t>(std::min(k + 100, air.size()))));
            wait_drained(ring, t);
        }
        push_all(ring, e);
        wait_drained(ring, t);
        EXPECT_TRUE(t.request(SculptRequest::kUndo));
        EXPECT_TRUE(t.request(SculptRequest::kRedo));
        wait_drained(ring, t);
        t.stop();
        stats = t.stats();
    }
    // The requests lie where the samples stood when they were taken; the idle close inside the air pass.
    ASSERT_EQ(stats.marks.size(), 5u);
    EXPECT_EQ(stats.marks[0].request, SculptRequest::kUndo);
    EXPECT_EQ(stats.marks[0].after_samples, 200u);
    EXPECT_EQ(stats.marks[1].request, SculptRequest::kEndStroke);
    EXPECT_EQ(stats.marks[1].after_samples, 400u);
    EXPECT_EQ(stats.marks[2].request, SculptRequest::kEndStroke);
    EXPECT_GT(stats.marks[2].after_samples, 600u + 500u);
    EXPECT_LE(stats.marks[2].after_samples, 600u + 700u);
    EXPECT_EQ(stats.marks[3].request, SculptRequest::kUndo);
    EXPECT_EQ(stats.marks[4].request, SculptRequest::kRedo);
    EXPECT_EQ(stats.marks[3].after_samples, all.size());
    EXPECT_EQ(stats.marks[4].after_samples, all.size());
    EXPECT_EQ(stats.history.undos, 2u);
    EXPECT_EQ(stats.history.redos, 1u);

    // All samples in one go (one batch): following the marks gives the live dexels; without them, not.
    for (const bool follow : {true, false}) {
        TriDexel again = fresh();
        SculptStats st;
        {
            Rig rig(again);
            if (follow) rig.thread.follow_marks(stats.marks);
            push_all(rig.ring, all);
            rig.thread.start();
            wait_drained(rig.ring, rig.thread);
            rig.thread.stop();
            st = rig.thread.stats();
        }
        if (follow) {
            EXPECT_EQ(compare(live, again).rays, 0u) << "the replay that follows the marks differs";
            EXPECT_EQ(st.history.undos, 2u);
            EXPECT_EQ(st.history.redos, 1u);
            ASSERT_EQ(st.marks.size(), stats.marks.size());  // a replay keeps them too (a recording of it repeats them)
            for (std::size_t k = 0; k < st.marks.size(); ++k) {
                EXPECT_EQ(st.marks[k].after_samples, stats.marks[k].after_samples) << k;
                EXPECT_EQ(st.marks[k].request, stats.marks[k].request) << k;
            }
        } else {
            EXPECT_GT(compare(live, again).rays, 0u) << "without the marks the same samples gave the same model";
        }
    }

    // Marks out of order, or a save among them, are refused before the thread starts.
    TriDexel m = fresh();
    Rig rig(m);
    EXPECT_THROW(rig.thread.follow_marks({{10, SculptRequest::kUndo}, {9, SculptRequest::kRedo}}), Error);
    EXPECT_THROW(rig.thread.follow_marks({{10, SculptRequest::kSave}}), Error);
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
        wait_drained(ring, t);
        std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the checkpoint interval passes
        wait_drained(ring, t);                                        // and a pass has written the checkpoint
        push_all(ring, pass(0.01, 0.3, 200, ToolOp::kSubtract));
        wait_drained(ring, t);
        EXPECT_TRUE(t.request(SculptRequest::kUndo));  // undoes the stroke after the first checkpoint
        wait_drained(ring, t);
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

// Specks: a stroke that cuts a knob loose closes (the tool lifted) and its floating top is removed on the sculpt thread,
// the active surface and the contour follow at once; the journal's replay with the same setting removes the same
// speck (the same dexels), a replay with removal off keeps it.
TEST(SculptThreadHistory, SpecksRemovedLiveAreRemovedAgainByTheJournalsReplay) {
    const std::string path = (fs::temp_directory_path() / ("tridex_specks_" + std::to_string(::getpid()) + ".tdj")).string();
    TriDexel live = compute::test::knob_model();
    const TriDexel start = live;
    SculptStats stats;
    const std::vector<ToolSample> cut = compute::test::knob_cut_samples(live.lattice, 0.0);
    {
        Rig rig(live);
        compute::JournalWriter journal(path, "session", std::chrono::milliseconds(5));
        rig.thread.use_journal(journal);
        rig.thread.remove_islands(true);
        rig.thread.start();
        push_all(rig.ring, cut);
        wait_drained(rig.ring, rig.thread);
        const std::uint64_t seq = rig.surface.latest().sequence;
        ToolSample lift = cut.back();
        lift.t_s += 1e-3;
        lift.op = ToolOp::kNone;
        push_all(rig.ring, {lift});  // the stroke closes: the speck goes
        wait_drained(rig.ring, rig.thread);
        EXPECT_GT(rig.surface.latest().sequence, seq) << "the active surface follows the removal at once";
        rig.thread.stop();
        stats = rig.thread.stats();
        EXPECT_EQ(journal.stats().error, "");
    }
    EXPECT_EQ(stats.islands.searches, 1u);
    EXPECT_EQ(stats.islands.specks, 1u);
    EXPECT_EQ(stats.island_search_ms.size(), 1u);
    EXPECT_EQ(stats.history.strokes, 1u);
    const compute::Journal j = compute::read_journal(path);
    TriDexel again = start;
    compute::JournalApplyFrom from;
    from.remove_islands = true;
    const compute::JournalApplyStats st = compute::journal_apply(again, j.records, from);
    EXPECT_EQ(st.islands_removed, 1u);
    EXPECT_EQ(st.island_volume_m3, stats.islands.volume_m3);
    EXPECT_EQ(compare(live, again).rays, 0u);
    TriDexel kept = start;
    EXPECT_EQ(compute::journal_apply(kept, j.records).islands_removed, 0u);
    EXPECT_GT(compare(live, kept).rays, 0u) << "without removal the replay keeps the speck";
    fs::remove(path);
}

}  // namespace
}  // namespace tridex::app
