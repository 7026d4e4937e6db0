// core/change_signal.hpp - a count of changes one thread announces and another may wait for, with a deadline.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace tridex {

/// Counts announcements (notify) and lets a waiting thread sleep until the count passes a value it has seen or a
/// deadline comes. Any number of threads may notify and wait. notify() takes a mutex briefly, so it is not for a
/// real-time loop; the sculpt thread announces a published change with it, and a paced frame loop wakes on it.
class ChangeSignal {
public:
    using Clock = std::chrono::steady_clock;

    /// Adds one to the count and wakes every waiting thread. Never throws.
    void notify() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            ++count_;
        }
        cv_.notify_all();
    }

    /// The number of notify() calls so far.
    std::uint64_t count() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return count_;
    }

    /// Waits until count() > seen (returns true, at once when it already is) or until `deadline` (returns false).
    bool wait_past(std::uint64_t seen, Clock::time_point deadline) const {
        std::unique_lock<std::mutex> lock(mutex_);
        return cv_.wait_until(lock, deadline, [&] { return count_ > seen; });
    }

private:
    mutable std::mutex mutex_;
    mutable std::condition_variable cv_;
    std::uint64_t count_ = 0;
};

}  // namespace tridex
