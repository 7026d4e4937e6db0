// The undo order across workpieces (UndoRouter): which workpiece an undo and a redo go to, from each sculpt
// thread's UndoTimes, and one request at a time, each after the one before was taken. Fake lanes, no threads.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

#include "app/session/runtime/placement_history.hpp"
#include "app/session/runtime/undo_router.hpp"

namespace tridex::app {
namespace {

TEST(UndoOrder, UndoGoesToTheNewestStepOfAll) {
    std::vector<UndoTimes> t(3);
    EXPECT_EQ(undo_workpiece(t), -1);  // nothing to undo anywhere
    t[0].undo_at = 100;
    t[2].undo_at = 40;
    EXPECT_EQ(undo_workpiece(t), 0);
    t[1].undo_at = 250;  // e.g. an open stroke that changed the model
    EXPECT_EQ(undo_workpiece(t), 1);
    t[2].undo_at = 250;  // a tie: the later workpiece
    EXPECT_EQ(undo_workpiece(t), 2);
}

TEST(UndoOrder, EveryStepOfOneThreadIsTimedByItsClock) {
    UndoClock c;
    EXPECT_EQ(c.times(0, 0, false).undo_at, -1);
    c.changed(10);
    c.changed(20);
    EXPECT_EQ(c.times(0, 0, true).undo_at, 20);  // the open stroke, undone by closing it first
    c.closed(1);
    c.made(2, 50);  // a coarseness change
    EXPECT_EQ(c.times(2, 0, false).undo_at, 50);
    EXPECT_EQ(c.times(1, 0, false).undo_at, 20);
    c.undone(2, 70);
    const UndoTimes after = c.times(1, 2, false);
    EXPECT_EQ(after.redo_at, 70);
    EXPECT_EQ(after.newest_step_at, 50);
    EXPECT_EQ(c.times(9, 0, false).undo_at, 0);  // a step from a loaded history: older than all
}

struct FakeLane {
    UndoTimes times;
    std::uint64_t passes = 0;
    std::size_t held = 0;  // requests it holds for a release (SculptThread::requests_held)
    std::vector<SculptRequest> got;
    UndoLane lane() {
        return {[this] { return times; }, [this] { return passes; },
                [this](SculptRequest r) {
                    got.push_back(r);
                    return true;
                },
                2, [this] { return held; }};
    }
    // A step to undo, made at `at` (undo-clock units), the lane's newest.
    void step_at(std::int64_t at) {
        times.undo_at = at;
        times.newest_step_at = at;
    }
};

// Two workpieces, a's step at 100 and b's newer at 200, and two undos asked at once: the first went to b.
struct TwoUndos {
    FakeLane a, b;
    UndoRouter r{{a.lane(), b.lane()}, [] { return 0; }};
    TwoUndos() {
        a.step_at(100);
        b.step_at(200);
        EXPECT_TRUE(r.ask(SculptRequest::kUndo));
        EXPECT_TRUE(r.ask(SculptRequest::kUndo));
    }
};

TEST(UndoRouter, RequestsGoOneAtATimeEachAfterTheOneBeforeWasTaken) {
    TwoUndos two;
    auto& [a, b, r] = two;
    EXPECT_EQ(b.got.size(), 1u);  // the newest first
    EXPECT_EQ(r.waiting(), 1u);   // the second waits until b took the first
    // b takes it: two passes, its step undone.
    b.passes += 2;
    b.times.undo_at = -1;
    b.times.redo_at = 300;
    r.pump();
    EXPECT_EQ(a.got.size(), 1u);
    EXPECT_EQ(r.waiting(), 0u);
    a.passes += 2;
    a.times.undo_at = -1;
    a.times.redo_at = 310;
    ASSERT_TRUE(r.ask(SculptRequest::kRedo));
    EXPECT_EQ(a.got.size(), 2u);  // the one undone last
    EXPECT_EQ(a.got.back(), SculptRequest::kRedo);
    EXPECT_FALSE(r.ask(SculptRequest::kEndStroke));  // not routed here
}

TEST(UndoRouter, NothingAnywhereGoesToTheFallbackAndAStoppedThreadDoesNotHoldTheQueue) {
    FakeLane a, b;
    UndoRouter r({a.lane(), b.lane()}, [] { return 1; });
    ASSERT_TRUE(r.ask(SculptRequest::kUndo));
    EXPECT_EQ(b.got.size(), 1u);  // counted where the tool carves
    b.passes += 2;
    ASSERT_TRUE(r.ask(SculptRequest::kRedo));
    EXPECT_EQ(b.got.size(), 2u);
    b.passes += 2;
    a.times.undo_at = 10;
    b.times.undo_at = 20;
    ASSERT_TRUE(r.ask(SculptRequest::kUndo));
    EXPECT_EQ(b.got.size(), 3u);
    ASSERT_TRUE(r.ask(SculptRequest::kUndo));  // a has a step too: waits for b, which never passes again
    EXPECT_EQ(r.waiting(), 1u);
    EXPECT_FALSE(r.drain(std::chrono::milliseconds(2500)));  // sent after the wait, but never seen taken
    EXPECT_EQ(r.waiting(), 0u);
    EXPECT_EQ(a.got.size() + b.got.size(), 4u);
}

// A lane that passes slowly (a long pass under load) has not stopped: the next request waits until it took the one
// before, and so reads the undo times that one left, however long that takes.
TEST(UndoRouter, ASlowThreadThatStillPassesHoldsTheQueueUntilItTookTheRequest) {
    constexpr auto kWait = std::chrono::milliseconds(1000);
    TwoUndos two;
    auto& [a, b, r] = two;
    ASSERT_EQ(b.got.size(), 1u);
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    ++b.passes;  // one pass: not taken yet
    EXPECT_TRUE(r.pump(kWait));
    std::this_thread::sleep_for(std::chrono::milliseconds(600));  // over the wait since sent, under it since the pass
    EXPECT_TRUE(r.pump(kWait));
    EXPECT_EQ(r.waiting(), 1u);
    EXPECT_EQ(b.got.size(), 1u) << "sent on b's old undo times";
    ++b.passes;  // taken: b's step undone
    b.times.undo_at = -1;
    b.times.redo_at = 300;
    EXPECT_TRUE(r.pump(kWait));
    EXPECT_EQ(r.waiting(), 0u);
    EXPECT_EQ(a.got.size(), 1u);
}

// A lane whose thread holds the request for the tool's release (a mouse drag on b) has not taken it, however often it
// passes: the second undo waits for the release and then reads the times the first left. Draining at the end counts
// a held request as taken (the thread takes it as it stops), so the second is sent rather than dropped.
TEST(UndoRouter, ARequestHeldForTheReleaseHoldsTheQueueUntilItIsTaken) {
    TwoUndos two;
    auto& [a, b, r] = two;
    ASSERT_EQ(b.got.size(), 1u);
    b.held = 1;
    b.passes += 10;
    EXPECT_TRUE(r.pump());
    EXPECT_EQ(r.waiting(), 1u) << "sent while b still held the first";
    EXPECT_EQ(a.got.size(), 0u);
    b.held = 0;  // released: b's drag undone
    b.times.undo_at = -1;
    b.times.redo_at = 300;
    EXPECT_TRUE(r.pump());
    EXPECT_EQ(r.waiting(), 0u);
    EXPECT_EQ(a.got.size(), 1u);

    TwoUndos at_end;
    at_end.b.held = 1;
    (void)at_end.r.drain(std::chrono::milliseconds(50));  // a never passes: the second is not seen taken
    EXPECT_EQ(at_end.r.waiting(), 0u);
    EXPECT_EQ(at_end.a.got.size() + at_end.b.got.size(), 2u) << "drained: the held one counts as taken";
}

TEST(UndoRouter, RedoFollowsTheUndosInReverseUntilANewStepEndsIt) {
    FakeLane a, b;
    a.times = UndoTimes{100, -1, 100};
    b.times = UndoTimes{200, -1, 200};
    UndoRouter r({a.lane(), b.lane()}, [] { return 0; });
    ASSERT_TRUE(r.ask(SculptRequest::kUndo));  // b's
    b.passes += 2;
    b.times = UndoTimes{-1, 300, 200};
    ASSERT_TRUE(r.ask(SculptRequest::kUndo));  // a's
    a.passes += 2;
    a.times = UndoTimes{-1, 310, 100};
    ASSERT_TRUE(r.ask(SculptRequest::kRedo));  // a's: undone last
    ASSERT_EQ(a.got.size(), 2u);
    EXPECT_EQ(a.got.back(), SculptRequest::kRedo);
    a.passes += 2;
    a.times = UndoTimes{100, -1, 100};
    // A new stroke on a: b's undone step can no longer be redone, though b's own history still holds it.
    a.times = UndoTimes{400, -1, 400};
    ASSERT_TRUE(r.ask(SculptRequest::kRedo));
    EXPECT_EQ(b.got.size(), 1u);  // nothing sent
    EXPECT_EQ(a.got.size(), 2u);
}

TEST(PlacementHistory, AnEndedPlacementIsAStepWhoseUndoAndRedoSetThePose) {
    std::vector<std::pair<int, Pose>> sets;
    bool refuse = false;
    PlacementHistory h([&](int k, const Pose& p) {
        if (refuse) return false;
        sets.emplace_back(k, p);
        return true;
    });
    EXPECT_EQ(h.times().undo_at, -1);
    EXPECT_TRUE(h.request(SculptRequest::kUndo));  // nothing: nothing done
    EXPECT_TRUE(sets.empty());
    const Pose a{Vec3(0.0), Quat(1.0, 0.0, 0.0, 0.0)}, b{Vec3(0.1, 0.0, 0.0), Quat(1.0, 0.0, 0.0, 0.0)};
    h.observe(haptics::Placement{1, 1, a, b, 500}, 520);
    h.observe(haptics::Placement{1, 1, a, b, 500}, 530);  // the same one in a later view: still one step
    EXPECT_EQ(h.undo_steps(), 1u);
    EXPECT_EQ(h.times().undo_at, 500);
    EXPECT_EQ(h.times().newest_step_at, 500);
    refuse = true;
    EXPECT_FALSE(h.request(SculptRequest::kUndo));  // the loop refused: the step stays
    EXPECT_EQ(h.undo_steps(), 1u);
    refuse = false;
    ASSERT_TRUE(h.request(SculptRequest::kUndo));
    ASSERT_EQ(sets.size(), 1u);
    EXPECT_EQ(sets[0].first, 1);
    EXPECT_EQ(sets[0].second.position, a.position);  // back where it was gripped
    EXPECT_EQ(h.times().undo_at, -1);
    EXPECT_EQ(h.times().redo_at, 530);  // undone at the view's clock
    ASSERT_TRUE(h.request(SculptRequest::kRedo));
    EXPECT_EQ(sets[1].second.position, b.position);
    ASSERT_TRUE(h.request(SculptRequest::kUndo));
    h.observe(haptics::Placement{2, 0, a, b, 700}, 710);  // a new placement ends what could be redone
    EXPECT_EQ(h.redo_steps(), 0u);
    EXPECT_EQ(h.times().undo_at, 700);
    EXPECT_FALSE(h.request(SculptRequest::kEndStroke));
}

}  // namespace
}  // namespace tridex::app
