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

/// The workpiece whose step an undo takes back: the largest UndoTimes::undo_at (the later workpiece on a tie), -1
/// when no workpiece has anything to undo.
int undo_workpiece(std::span<const UndoTimes> times);
/// The workpiece whose step a redo re-applies: the largest UndoTimes::redo_at among the redo steps undone after
/// every workpiece's newest step (UndoTimes::newest_step_at; a newer action ends what can be redone), -1 when none.
int redo_workpiece(std::span<const UndoTimes> times);

/// One workpiece's sculpt thread as the router sees it.
struct UndoLane {
    std::function<UndoTimes()> times;             ///< SculptThread::live().undo_times
    std::function<std::uint64_t()> passes;        ///< SculptThread::passes()
    std::function<bool(SculptRequest)> request;   ///< SculptThread::request
};

/// Sends undo and redo requests of a session with several workpieces to the workpiece whose step is newest (undo) or
/// was undone last (redo), as Blender's and every editor's one undo order does. Each sculpt thread keeps its own
/// undo history (per-workpiece journals replay alone); this only chooses where a request goes. Requests go one at
/// a time: the next waits until the previous one's thread has taken it (two more passes), so two quick Ctrl+Z
/// read the state the first left. With nothing to undo (or redo) anywhere, the request goes to `fallback()` (the
/// workpiece the tool carves), which counts it as before. One thread (the window's) calls every member.
class UndoRouter {
public:
    /// Routes among `lanes` (index = workpiece, 0 the first); `fallback` names the workpiece the tool carves now.
    UndoRouter(std::vector<UndoLane> lanes, std::function<int()> fallback);
    /// Queues an undo or redo (other requests are not routed here: returns false) and sends what is due. False when
    /// 16 requests already wait or the chosen thread's queue is full.
    bool ask(SculptRequest r);
    /// Sends the queued requests whose turn came (each once the one before was taken, or after `wait` without the
    /// thread passing: a stopped thread does not hold the queue).
    bool pump(std::chrono::milliseconds wait = std::chrono::milliseconds(1000));
    /// Sends every queued request, waiting for each in turn, for at most `timeout` in all; false when some were
    /// left (then dropped).
    bool drain(std::chrono::milliseconds timeout);
    /// Requests waiting.
    std::size_t waiting() const { return queue_.size(); }
    /// Most requests that may wait.
    static constexpr std::size_t kMaxWaiting = 16;

private:
    bool send(SculptRequest r);
    std::vector<UndoLane> lanes_;
    std::function<int()> fallback_;
    std::deque<SculptRequest> queue_;
    int busy_ = -1;                 // the lane the last request went to, until it took it
    std::uint64_t busy_pass_ = 0;   // its passes() when sent
    std::chrono::steady_clock::time_point busy_since_{};
};

}  // namespace tridex::app
