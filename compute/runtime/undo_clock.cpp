// compute/runtime/undo_clock.cpp - when a sculpt thread's undo steps were made and undone.
#include "compute/runtime/undo_clock.hpp"

#include <algorithm>

namespace tridex::app {

void UndoClock::changed(std::uint64_t samples) { last_change_ = static_cast<std::int64_t>(samples); }

void UndoClock::closed(std::uint64_t serial) {
    if (serial == 0 || last_change_ < 0) return;
    made_at_[serial] = last_change_;
    newest_ = std::max(newest_, last_change_);
}

void UndoClock::made(std::uint64_t serial, std::uint64_t samples) {
    if (serial == 0) return;
    const auto at = static_cast<std::int64_t>(samples);
    made_at_[serial] = at;
    newest_ = std::max(newest_, at);
}

void UndoClock::undone(std::uint64_t serial, std::uint64_t samples) {
    if (serial != 0) undone_at_[serial] = static_cast<std::int64_t>(samples);
}

UndoTimes UndoClock::times(std::uint64_t next_undo, std::uint64_t next_redo, bool open_changed) const {
    UndoTimes t;
    const auto at = [](const std::unordered_map<std::uint64_t, std::int64_t>& m, std::uint64_t serial) {
        const auto it = m.find(serial);
        return it == m.end() ? std::int64_t{0} : it->second;  // a step from before this thread: older than all
    };
    if (open_changed)
        t.undo_at = std::max<std::int64_t>(last_change_, 0);
    else if (next_undo != 0)
        t.undo_at = at(made_at_, next_undo);
    if (next_redo != 0) t.redo_at = at(undone_at_, next_redo);
    t.newest_step_at = open_changed ? std::max(newest_, last_change_) : newest_;
    return t;
}

}  // namespace tridex::app
