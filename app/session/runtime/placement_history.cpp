// app/session/runtime/placement_history.cpp - placements as undo steps.
#include "app/session/runtime/placement_history.hpp"

#include <algorithm>
#include <utility>

namespace tridex::app {

PlacementHistory::PlacementHistory(std::function<bool(int, const Pose&)> set_pose) : set_pose_(std::move(set_pose)) {}

void PlacementHistory::observe(const haptics::Placement& newest, std::uint64_t samples) {
    samples_ = samples;
    if (newest.serial == 0 || newest.serial == seen_) return;
    seen_ = newest.serial;
    const auto at = static_cast<std::int64_t>(newest.at_samples);
    undo_.push_back(Step{newest.workpiece, newest.before, newest.after, at, 0});
    if (undo_.size() > kMaxSteps) undo_.erase(undo_.begin());
    redo_.clear();
    newest_ = std::max(newest_, at);
}

UndoTimes PlacementHistory::times() const {
    UndoTimes t;
    if (!undo_.empty()) t.undo_at = undo_.back().at;
    if (!redo_.empty()) t.redo_at = redo_.back().undone_at;
    t.newest_step_at = newest_;
    return t;
}

bool PlacementHistory::request(SculptRequest r) {
    const bool undo = r == SculptRequest::kUndo;
    if (!undo && r != SculptRequest::kRedo) return false;
    std::vector<Step>& from = undo ? undo_ : redo_;
    if (from.empty()) return true;
    Step s = from.back();
    if (!set_pose_(s.workpiece, undo ? s.before : s.after)) return false;
    from.pop_back();
    if (undo) {
        s.undone_at = static_cast<std::int64_t>(samples_);
        redo_.push_back(s);
    } else {
        undo_.push_back(s);
    }
    return true;
}

}  // namespace tridex::app
