// Late starts in a sculpt thread's stream: a shared session's joiner that starts from the host's snapshot, and the
// snapshots asked for a wall's render rank joining late (on a session of its own and on a follower), each replayed
// from its record on to the session's model bit for bit, undos of strokes made before it included.
#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <optional>
#include <thread>

#include "compute/journal/journal_format.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/journal/stream_buffer.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"
#include "journal_stream.hpp"
#include "site_grooves.hpp"

namespace tridex::app {
namespace {

// Moves the host's stream from record `first` on into a follower's intake (a late joiner gets only those).
void relay_from(compute::ToolStreamBuffer& stream, SiteIntake& follower, std::uint64_t first) {
    for (const compute::JournalRecord& r : stream.take().records)
        if (r.index >= first) follower.push_host_record(r);
}

TEST(SculptSites, ALateJoinerStartsFromTheHostsSnapshotAndFollowsUndosOfStrokesMadeBeforeIt) {
    compute::TriDexel host_model = box_model();
    compute::ToolStreamBuffer stream;
    SiteIntake host_in, join_in;
    compute::Contourer hc(host_model);
    hc.update(host_model);
    SpscRing<ToolSample> host_ring(4096);
    TripleBuffer<ActiveSurface> hs;
    SculptThread host(host_model, hc, host_ring, hs, Vec3(0.0));
    host.use_stream(stream);
    host.use_site_intake(host_in);
    std::mutex snap_mutex;
    std::optional<SculptSnapshot> snap;
    std::uint64_t first = 0;
    host.use_snapshots([&](SculptSnapshot&& s) {
        std::lock_guard lock(snap_mutex);
        first = stream.records();
        snap = std::move(s);
    });
    host.start();
    const auto settle_host = [&] {
        for (int k = 0; k < 40 && (host_ring.size() > 0 || host_in.pending() > 0); ++k)
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    };
    for (const ToolSample& x : groove(0, 0.02, -0.03, 0.03, 60, 0.0)) host_ring.try_push(x);  // A, the host's
    settle_host();
    host_in.push_samples(groove(2, -0.02, 0.03, -0.03, 60, 0.0));  // B, site 2's
    settle_host();
    const std::vector<ToolSample> c = groove(0, 0.0, -0.03, 0.03, 80, 1.0);  // C, the host's, split by the join
    for (const ToolSample& x : slice(c, 0, 40)) host_ring.try_push(x);
    settle_host();
    host_in.push_snapshot(1);  // site 1 joins late, mid-gesture
    settle_host();
    for (const ToolSample& x : slice(c, 40, c.size())) host_ring.try_push(x);
    settle_host();
    {
        std::lock_guard lock(snap_mutex);
        ASSERT_TRUE(snap.has_value());
        EXPECT_GT(first, 0u);
    }
    // The joiner: the snapshot's model, its history and sweeps, and the stream from the snapshot on.
    compute::TriDexel join_model = snap->model;
    compute::Contourer jc(join_model);
    jc.update(join_model);
    SpscRing<ToolSample> join_ring(16);
    TripleBuffer<ActiveSurface> js;
    SculptThread join(join_model, jc, join_ring, js, Vec3(0.0));
    join.follow_host(join_in, 1, {[](std::span<const ToolSample>) {}, [](SculptRequest) {}, {}},
                     FollowStart{snap->history, snap->prevs, snap->last_closed_serial});
    join.start();
    const auto settle = [&] {
        settle_host();
        for (int k = 0; k < 20; ++k) {
            relay_from(stream, join_in, first);
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    };
    settle();
    ASSERT_TRUE(host.request(SculptRequest::kUndo));  // the host's gesture C, both its parts: one before the join
    settle();
    ASSERT_TRUE(host.request(SculptRequest::kUndo));  // B is site 2's: refused
    settle();
    host_in.push_request(2, SculptRequest::kUndo);  // site 2 takes back B, carved before the join
    settle();
    host_in.push_request(2, SculptRequest::kRedo);
    settle();
    host.stop();
    relay_from(stream, join_in, first);
    settle();
    join.stop();
    EXPECT_EQ(host.stats().history.undos, 3u);  // C's two strokes and B
    EXPECT_EQ(host.stats().history.redos, 1u);
    EXPECT_EQ(host.stats().refusals.size(), 1u);
    EXPECT_EQ(join.stats().undo_ms.size(), 4u);  // the host's undos and redo, followed from the joiner's history
    EXPECT_EQ(compute::model_digest(join_model), compute::model_digest(host_model));

    // Bad history bytes are refused when the follower starts.
    compute::TriDexel other = box_model();
    compute::Contourer oc(other);
    oc.update(other);
    SculptThread bad(other, oc, join_ring, js, Vec3(0.0));
    std::vector<unsigned char> torn = snap->history;
    torn.resize(torn.size() / 2);
    bad.follow_host(join_in, 1, {[](std::span<const ToolSample>) {}, [](SculptRequest) {}, {}},
                    FollowStart{torn, {}, 0});
    EXPECT_THROW(bad.start(), Error);
}

TEST(SculptSites, AnAskedSnapshotWaitsForTheOpenStrokeAndTheStreamAppliesToItAsToTheSession) {
    // A session of its own (a wall's rank 0): a snapshot asked mid-stroke is taken once the stroke closed, and a
    // replica that starts from it (a render rank joining late: JournalApplier with its history) and applies the
    // stream from its record on ends with the session's model, through undos of strokes made before it.
    compute::TriDexel model = box_model();
    compute::ToolStreamBuffer stream;
    compute::Contourer contourer(model);
    contourer.update(model);
    SpscRing<ToolSample> ring(4096);
    TripleBuffer<ActiveSurface> surface;
    SculptThread t(model, contourer, ring, surface, Vec3(0.0));
    t.use_stream(stream);
    std::mutex m;
    std::optional<SculptSnapshot> snap;
    std::uint64_t first = 0;
    int snapshots = 0;
    t.use_snapshot_asks([&](SculptSnapshot&& s) {
        std::lock_guard lock(m);
        first = stream.records();
        snap = std::move(s);
        ++snapshots;
    });
    t.start();
    const auto settle = [&] {
        for (int k = 0; k < 40 && ring.size() > 0; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(5));
        std::this_thread::sleep_for(std::chrono::milliseconds(60));
    };
    for (const ToolSample& x : groove(0, 0.02, -0.03, 0.03, 60, 0.0)) ring.try_push(x);  // A
    settle();
    const std::vector<ToolSample> b = groove(0, -0.02, 0.03, -0.03, 60, 1.0);  // B: open when the snapshot is asked
    for (const ToolSample& x : slice(b, 0, 30)) ring.try_push(x);
    settle();
    EXPECT_EQ(t.ask_snapshot(), 1u);
    EXPECT_EQ(t.ask_snapshot(), 2u);
    settle();
    {
        std::lock_guard lock(m);
        EXPECT_EQ(snapshots, 0) << "a snapshot was taken while a stroke was open";
    }
    for (const ToolSample& x : slice(b, 30, b.size())) ring.try_push(x);  // B ends: the tool lifts
    settle();
    for (int k = 0; k < 500; ++k) {  // a loaded machine (TSan, two cores) may take longer than settle()
        {
            std::lock_guard lock(m);
            if (snapshots > 0) break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    int taken = 0;
    {
        std::lock_guard lock(m);
        taken = snapshots;
    }
    if (taken != 1) t.stop();  // before the assertion returns: the thread writes into this frame's `snap`
    {
        std::lock_guard lock(m);
        ASSERT_EQ(snapshots, 1) << "one snapshot serves both asks";
        EXPECT_EQ(snap->asks, 2u);
        EXPECT_EQ(snap->site, 0u);
        EXPECT_EQ(snap->last_closed_serial, 2u);
    }
    for (const ToolSample& x : groove(0, 0.0, -0.03, 0.03, 60, 2.0)) ring.try_push(x);  // C, after the snapshot
    settle();
    for (int k = 0; k < 3; ++k) {  // C, then B and A: made before the snapshot
        ASSERT_TRUE(t.request(SculptRequest::kUndo));
        settle();
    }
    ASSERT_TRUE(t.request(SculptRequest::kRedo));  // A again
    settle();
    t.stop();
    EXPECT_EQ(t.stats().history.undos, 3u);
    EXPECT_EQ(snapshots, 1);

    const std::vector<compute::JournalRecord> all = stream.take().records;
    ASSERT_GT(first, 0u);
    ASSERT_LT(first, all.size());
    compute::TriDexel replica = snap->model;
    compute::JournalApplyFrom from;
    from.last_serial = snap->last_closed_serial;
    compute::JournalApplier applier(replica, from);
    applier.load_history(snap->history);
    applier.resume_after(first - 1, snap->prevs, first);
    applier.apply(std::span<const compute::JournalRecord>(all).subspan(first));
    applier.flush();
    EXPECT_EQ(applier.stats().undos, 3u);
    EXPECT_EQ(applier.stats().redos, 1u);
    EXPECT_EQ(compute::model_digest(replica), compute::model_digest(model));

    // Without the history, the undos of strokes made before the snapshot find nothing to undo.
    compute::TriDexel bare = snap->model;
    compute::JournalApplier lost(bare, from);
    lost.resume_after(first - 1, snap->prevs, first);
    EXPECT_THROW(lost.apply(std::span<const compute::JournalRecord>(all).subspan(first)), Error);
}

TEST(SculptSites, AFollowerServesAnAskedSnapshotOnceTheHostClosedTheStroke) {
    // A wall that joined a shared session: its rank 0 follows the host, and a render rank joining the wall late gets
    // a snapshot of that replica, taken between the host's strokes (a follower cannot close one itself).
    compute::TriDexel model = box_model();
    compute::Contourer contourer(model);
    contourer.update(model);
    SpscRing<ToolSample> ring(16);
    TripleBuffer<ActiveSurface> surface;
    SiteIntake in;
    SculptThread t(model, contourer, ring, surface, Vec3(0.0));
    t.follow_host(in, 1, {[](std::span<const ToolSample>) {}, [](SculptRequest) {}, {}});
    std::mutex m;
    int taken = 0;
    std::uint64_t serial = 0;
    t.use_snapshot_asks([&](SculptSnapshot&& s) {
        std::lock_guard lock(m);
        ++taken;
        serial = s.last_closed_serial;
    });
    t.start();
    const auto settle = [&] {
        for (int k = 0; k < 40 && in.pending() > 0; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(5));
        std::this_thread::sleep_for(std::chrono::milliseconds(60));
    };
    const std::vector<ToolSample> a = groove(2, 0.0, -0.03, 0.03, 30, 0.0);
    in.push_host_samples(slice(a, 0, 15));  // the host's stroke, open here too
    settle();
    EXPECT_EQ(t.ask_snapshot(), 1u);
    settle();
    {
        std::lock_guard lock(m);
        EXPECT_EQ(taken, 0) << "a snapshot was taken inside the host's stroke";
    }
    in.push_host_samples(slice(a, 15, a.size()));
    in.push_host_mark(compute::kJournalStrokeEnd, 1, 0);
    settle();
    t.stop();
    EXPECT_EQ(taken, 1);
    EXPECT_EQ(serial, 1u);
}

}  // namespace
}  // namespace tridex::app
