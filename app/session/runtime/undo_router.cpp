// app/session/runtime/undo_router.cpp - one undo order across the workpieces and the placements.
#include "app/session/runtime/undo_router.hpp"

#include <algorithm>
#include <thread>
#include <utility>

namespace tridex::app {

int undo_workpiece(std::span<const UndoTimes> times) {
    int best = -1;
    for (std::size_t k = 0; k < times.size(); ++k)
        if (times[k].undo_at >= 0 && (best < 0 || times[k].undo_at >= times[static_cast<std::size_t>(best)].undo_at))
            best = static_cast<int>(k);
    return best;
}

UndoRouter::UndoRouter(std::vector<UndoLane> lanes, std::function<int()> fallback)
    : lanes_(std::move(lanes)), fallback_(std::move(fallback)) {}

bool UndoRouter::ask(SculptRequest r) {
    if (r != SculptRequest::kUndo && r != SculptRequest::kRedo) return false;
    if (queue_.size() >= kMaxWaiting) return false;
    queue_.push_back(r);
    return pump();
}

UndoRouter::Choice UndoRouter::choose(SculptRequest r) {
    std::vector<UndoTimes> times;
    times.reserve(lanes_.size());
    std::int64_t newest = -1;
    for (const UndoLane& l : lanes_) {
        times.push_back(l.times());
        newest = std::max(newest, times.back().newest_step_at);
    }
    if (newest > newest_) {  // a new step since: what was undone before it can no longer be redone
        newest_ = newest;
        undone_.clear();
    }
    Choice c;
    if (r == SculptRequest::kUndo) {
        c.lane = undo_workpiece(times);
        c.only = c.lane >= 0;
        for (std::size_t k = 0; k < times.size() && c.only; ++k)
            c.only = static_cast<int>(k) == c.lane || times[k].undo_at < 0;
    } else if (!undone_.empty()) {
        c.lane = undone_.back();
        c.only = true;  // the order is the router's own: no other lane's state can change it
    } else {
        bool any = false;  // an undone step a newer one ended: nothing to redo in the one order
        for (const UndoTimes& t : times) any = any || t.redo_at >= 0;
        if (any) c.drop = true;
    }
    if (c.lane < 0 && !c.drop) {  // nothing anywhere: the workpiece the tool carves counts the request
        c.lane = fallback_ ? fallback_() : 0;
        if (c.lane < 0 || static_cast<std::size_t>(c.lane) >= lanes_.size()) c.lane = 0;
        c.counted_only = true;
    }
    return c;
}

bool UndoRouter::send(SculptRequest r, const Choice& c) {
    if (c.drop) return true;
    const UndoLane& lane = lanes_[static_cast<std::size_t>(c.lane)];
    busy_progress_ = lane.progress();
    if (!lane.request(r)) return false;
    if (!c.counted_only) {
        if (r == SculptRequest::kUndo) undone_.push_back(c.lane);
        else undone_.pop_back();
    }
    busy_ = c.lane;
    seen_progress_ = busy_progress_;
    moved_at_ = std::chrono::steady_clock::now();
    return true;
}

bool UndoRouter::taken(std::chrono::milliseconds wait) {
    if (busy_ < 0) return true;
    const UndoLane& lane = lanes_[static_cast<std::size_t>(busy_)];
    if (lane.holding && lane.holding() > 0) return draining_;
    const std::uint64_t progress = lane.progress();
    if (progress >= busy_progress_ + lane.taken_after) return true;
    const auto now = std::chrono::steady_clock::now();
    if (progress != seen_progress_) {  // passing, not stopped: the wait starts again
        seen_progress_ = progress;
        moved_at_ = now;
    }
    return now - moved_at_ >= wait;
}

bool UndoRouter::pump(std::chrono::milliseconds wait) {
    bool ok = true;
    while (!queue_.empty()) {
        const SculptRequest r = queue_.front();
        if (!taken(wait)) {
            // The one before is not taken yet: this one goes now only where it would go whatever that one leaves
            // (the same lane, whose own queue keeps their order).
            const Choice c = choose(r);
            if (c.drop || c.lane != busy_ || !c.only) return ok;
            queue_.pop_front();
            ok = send(r, c) && ok;
            continue;
        }
        busy_ = -1;
        queue_.pop_front();
        ok = send(r, choose(r)) && ok;
    }
    return ok;
}

bool UndoRouter::drain(std::chrono::milliseconds timeout) {
    draining_ = true;
    const auto end = std::chrono::steady_clock::now() + timeout;
    while ((!queue_.empty() || !taken(timeout)) && std::chrono::steady_clock::now() < end) {
        pump();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    const bool all = queue_.empty() && taken(timeout);
    queue_.clear();
    return all;
}

}  // namespace tridex::app
