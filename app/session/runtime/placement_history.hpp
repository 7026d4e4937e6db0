// app/session/runtime/placement_history.hpp - the placements of a session (the tool moving and turning a whole
// workpiece with ToolOp::kPlace) as undo steps, in the one undo order with the strokes (UndoRouter).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "compute/runtime/sculpt_thread.hpp"
#include "compute/runtime/undo_clock.hpp"
#include "core/pose.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// Each placement that ended (LoopView::placement) becomes an undo step: its undo sets the workpiece's pose back to
/// where the tool gripped it, its redo to where the tool let go (through `set_pose`: HapticLoop::set_workpiece_pose,
/// so the recording keeps the set and a replay repeats it). A new placement ends what can be redone. Steps are timed
/// in the sculpt threads' samples (UndoTimes) so that the router orders them among the strokes. The view carries only
/// the newest ended placement, so two that end between two views (a grip and release within one frame) count as
/// one. At most kMaxSteps undo steps are kept (the oldest dropped). One thread (the window's) calls every member.
class PlacementHistory {
public:
    /// `set_pose(workpiece, pose)` returns false when the loop refuses the set (the step then stays where it was).
    explicit PlacementHistory(std::function<bool(int, const Pose&)> set_pose);
    /// Takes the newest ended placement of a view (a serial not seen before becomes a step) and the view's sample
    /// count (LoopView::samples), the clock of the undos made next.
    void observe(const haptics::Placement& newest, std::uint64_t samples);
    /// Where its newest undo and redo steps stand (UndoLane::times).
    UndoTimes times() const;
    /// Undoes (kUndo) or redoes (kRedo) the newest step; true when there is none (nothing to do). False when the
    /// loop refused the pose or the request is neither.
    bool request(SculptRequest r);
    /// Undo and redo steps held.
    std::size_t undo_steps() const { return undo_.size(); }
    std::size_t redo_steps() const { return redo_.size(); }
    static constexpr std::size_t kMaxSteps = 256;

private:
    struct Step {
        int workpiece = 0;
        Pose before{}, after{};
        std::int64_t at = 0;         // samples at the release
        std::int64_t undone_at = 0;  // samples when last undone
    };
    std::function<bool(int, const Pose&)> set_pose_;
    std::vector<Step> undo_, redo_;
    std::uint64_t seen_ = 0;
    std::int64_t newest_ = -1;
    std::uint64_t samples_ = 0;
};

}  // namespace tridex::app
