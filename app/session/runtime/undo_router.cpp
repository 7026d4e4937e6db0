// app/session/runtime/undo_router.cpp - one undo order across several workpieces.
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

int redo_workpiece(std::span<const UndoTimes> times) {
    std::int64_t newest = -1;
    for (const UndoTimes& t : times) newest = std::max(newest, t.newest_step_at);
    int best = -1;
    for (std::size_t k = 0; k < times.size(); ++k) {
        const std::int64_t at = times[k].redo_at;
        if (at >= 0 && at >= newest && (best < 0 || at >= times[static_cast<std::size_t>(best)].redo_at))
            best = static_cast<int>(k);
    }
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

bool UndoRouter::pump(std::chrono::milliseconds wait) {
    bool ok = true;
    while (!queue_.empty()) {
        const SculptRequest r = queue_.front();
        if (busy_ >= 0) {
            const UndoLane& lane = lanes_[static_cast<std::size_t>(busy_)];
            const bool taken = lane.progress() >= busy_progress_ + lane.taken_after;
            if (!taken && std::chrono::steady_clock::now() - busy_since_ < wait) {
                if (!only_lane_for(r, busy_)) return ok;
                // Nothing elsewhere: it goes where the one before went, whose own queue keeps their order.
                queue_.pop_front();
                busy_progress_ = lane.progress();
                if (!lane.request(r)) return false;
                continue;
            }
            busy_ = -1;
        }
        queue_.pop_front();
        ok = send(r) && ok;
    }
    return ok;
}

bool UndoRouter::send(SculptRequest r) {
    std::vector<UndoTimes> times;
    times.reserve(lanes_.size());
    for (const UndoLane& l : lanes_) times.push_back(l.times());
    int k = r == SculptRequest::kUndo ? undo_workpiece(times) : redo_workpiece(times);
    if (k < 0) k = fallback_ ? fallback_() : 0;
    if (k < 0 || static_cast<std::size_t>(k) >= lanes_.size()) k = 0;
    const UndoLane& lane = lanes_[static_cast<std::size_t>(k)];
    busy_progress_ = lane.progress();
    if (!lane.request(r)) return false;
    busy_ = k;
    busy_since_ = std::chrono::steady_clock::now();
    return true;
}

bool UndoRouter::only_lane_for(SculptRequest r, int k) const {
    for (std::size_t j = 0; j < lanes_.size(); ++j) {
        if (static_cast<int>(j) == k) continue;
        const UndoTimes t = lanes_[j].times();
        if ((r == SculptRequest::kUndo ? t.undo_at : t.redo_at) >= 0) return false;
    }
    return true;
}

bool UndoRouter::drain(std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!queue_.empty() && std::chrono::steady_clock::now() < end) {
        pump();
        if (!queue_.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    const bool all = queue_.empty();
    queue_.clear();
    return all;
}

}  // namespace tridex::app
