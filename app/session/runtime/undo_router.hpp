// app/session/runtime/undo_router.hpp - one undo order across several workpieces: Ctrl+Z takes back the newest
// step of all, whichever workpiece it was on, and redo brings back the step undone last.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <span>
#include <vector>

#include "compute/runtime/sculpt_thread.hpp"
#include "compute/runtime/undo_clock.hpp"

namespace tridex::app {

/// The lane whose step an undo takes back: the largest UndoTimes::undo_at (the later lane on a tie), -1 when no lane
/// has anything to undo.
int undo_workpiece(std::span<const UndoTimes> times);

/// One undo history as the router sees it: a workpiece's sculpt thread, or the session's placements
/// (PlacementHistory).
struct UndoLane {
    std::function<UndoTimes()> times;             ///< where its newest steps stand (SculptThread::live().undo_times)
    std::function<std::uint64_t()> progress;      ///< a counter that moves as it works (SculptThread::passes())
    std::function<bool(SculptRequest)> request;   ///< takes an undo or redo (SculptThread::request)
    /// How far `progress` moves once a request made before is surely taken (a sculpt thread: two passes).
    std::uint64_t taken_after = 2;
    /// Requests it holds untaken however far `progress` moves (SculptThread::requests_held: waiting for the tool's
    /// release); empty: none ever are.
    std::function<std::size_t()> holding = {};
};

/// Sends a session's undo and redo requests in one order: an undo to the history whose step is newest (a
/// workpiece's strokes and coarseness changes, or the placements), a redo to the history undone last, as the one undo
/// order of Blender and every editor. A new step anywhere (a larger UndoTimes::newest_step_at) ends what can be
/// redone; a redo then does nothing. Each sculpt thread keeps its own undo history (per-workpiece journals replay
/// alone); this only chooses where a request goes. Requests go one at a time: the next waits until the history the
/// previous one went to has taken it (its progress moved by taken_after), so two quick Ctrl+Z read the state the
/// first left, unless it goes to the same history whatever the first leaves (then at once: that history's own queue
/// keeps their order). With nothing to undo (or redo) anywhere, the request goes to workpiece `fallback()` (the one
/// the tool carves), whose sculpt thread counts it. One thread (the window's) calls every member.
class UndoRouter {
public:
    /// Routes among `lanes` (the workpieces' in order, then any others such as the placements'); `fallback` names the
    /// workpiece the tool carves now.
    UndoRouter(std::vector<UndoLane> lanes, std::function<int()> fallback);
    /// Queues an undo or redo (other requests are not routed here: returns false) and sends what is due. False when
    /// 16 requests already wait or the chosen thread's queue is full.
    bool ask(SculptRequest r);
    /// Sends the queued requests whose turn came (each once the one before was taken, or after `wait` without the
    /// thread passing at all: a stopped thread does not hold the queue, a slow one that still passes does).
    bool pump(std::chrono::milliseconds wait = std::chrono::milliseconds(1000));
    /// Sends every queued request, waiting for each in turn and for the last to be taken, for at most `timeout` in
    /// all; false when some were left (then dropped) or the last was not seen taken.
    bool drain(std::chrono::milliseconds timeout);
    /// Requests waiting.
    std::size_t waiting() const { return queue_.size(); }
    /// Most requests that may wait.
    static constexpr std::size_t kMaxWaiting = 16;

private:
    struct Choice {
        int lane = -1;              // where it goes
        bool only = false;          // it goes there whatever the request in flight leaves
        bool drop = false;          // a redo that a newer step ended: nothing is sent
        bool counted_only = false;  // nothing anywhere: sent to the fallback to be counted
    };
    Choice choose(SculptRequest r);
    bool send(SculptRequest r, const Choice& c);
    // Whether the request in flight was taken, or its lane's progress has not moved for `wait` (since it was sent or
    // since it last moved): a stopped thread holds nothing, a slow one that still passes holds the queue.
    // A lane that holds requests (UndoLane::holding) has not taken the one in flight, except while draining at the
    // end, when the thread takes what it holds as it stops.
    bool taken(std::chrono::milliseconds wait);
    std::vector<UndoLane> lanes_;
    std::function<int()> fallback_;
    std::deque<SculptRequest> queue_;
    std::vector<int> undone_;          // the lanes of the undos sent, newest last: where redo goes
    std::int64_t newest_ = -1;         // the newest step seen (UndoTimes::newest_step_at over the lanes)
    int busy_ = -1;                    // the lane the last request went to, until it took it
    std::uint64_t busy_progress_ = 0;  // its progress() when sent
    std::uint64_t seen_progress_ = 0;  // its progress() when last looked at
    std::chrono::steady_clock::time_point moved_at_{};  // when that was sent or last seen to move
    bool draining_ = false;                             // in drain()
};

}  // namespace tridex::app
