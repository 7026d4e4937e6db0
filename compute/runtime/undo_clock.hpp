// compute/runtime/undo_clock.hpp - when a sculpt thread's undo steps were made and undone, counted in samples
// drained: what orders undo and redo across several workpieces, whose sculpt threads drain the same tick stream.
#pragma once

#include <cstdint>
#include <unordered_map>

namespace tridex::app {

/// Where a sculpt thread's newest undo and redo steps stand in its sample stream (SculptLive::undo_times). Every
/// workpiece of one haptic loop gets every tick (ToolOp::kNone for the ones not carved), so the sample counts of
/// several workpieces' sculpt threads are one clock, and the newest step of all is the one with the largest count.
struct UndoTimes {
    /// Samples drained at the newest change of what an undo takes back: the open stroke when it changed the model
    /// (an undo closes it first), else the newest undo step. 0 for a step made before this thread started (a
    /// loaded history); -1 when there is nothing to undo.
    std::int64_t undo_at = -1;
    /// Samples drained when the step a redo re-applies was undone; -1 when there is nothing to redo.
    std::int64_t redo_at = -1;
    /// Samples drained at the newest change that became an undo step (a stroke or a coarseness change), or at the
    /// open stroke's newest change; -1 when none. A redo older than another workpiece's newer step is not offered
    /// (a new action ends what can be redone, as in every editor).
    std::int64_t newest_step_at = -1;
};

/// Keeps, per undo-step serial (UndoHistory's numbering), the sample count of the step's newest change and of its
/// latest undo; SculptThread feeds it from its one thread. Memory: a map entry per step made and per step undone,
/// kept for the session.
class UndoClock {
public:
    /// The open stroke changed the model after `samples` samples drained.
    void changed(std::uint64_t samples);
    /// The open stroke closed as undo step `serial` (> 0; 0 is ignored): its time is its newest change's.
    void closed(std::uint64_t serial);
    /// A step that is not a stroke (a coarseness change) was made as `serial` after `samples` samples.
    void made(std::uint64_t serial, std::uint64_t samples);
    /// Step `serial` was undone after `samples` samples.
    void undone(std::uint64_t serial, std::uint64_t samples);
    /// The times for a history whose next undo and redo steps are `next_undo` and `next_redo` (0 = none), with an
    /// open stroke that changed the model when `open_changed`.
    UndoTimes times(std::uint64_t next_undo, std::uint64_t next_redo, bool open_changed) const;

private:
    std::int64_t last_change_ = -1;  // samples at the open (or last closed) stroke's newest change
    std::int64_t newest_ = -1;       // newest change that made a step
    std::unordered_map<std::uint64_t, std::int64_t> made_at_, undone_at_;
};

}  // namespace tridex::app
