// compute/journal/journal_intake.cpp - the journal's intake thread.
#include "compute/journal/journal_intake.hpp"

#include "core/thread_name.hpp"

namespace tridex::compute {

JournalIntake::JournalIntake(JournalWriter& journal) : journal_(journal), ring_(kRingSamples) {
    // A round takes at most the ring's capacity, and keeps at most kHold's worth of it pending besides.
    pending_.reserve(2 * ring_.capacity());
    arrived_.reserve(2 * ring_.capacity());
    run_.reserve(2 * ring_.capacity());
}

JournalIntake::~JournalIntake() { stop(); }

void JournalIntake::start() {
    if (thread_.joinable()) return;
    thread_ = std::thread([this] { run(); });
}

void JournalIntake::stop() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
}

void JournalIntake::run() {
    name_this_thread("tridex-intake");
    std::unique_lock lock(mutex_);
    while (!stop_) {
        wake_.wait_for(lock, kPeriod, [this] { return stop_; });
        if (stop_) break;
        lock.unlock();
        take(false);
        lock.lock();
    }
    lock.unlock();
    take(true);
}

void JournalIntake::take(bool all) {
    const auto now = std::chrono::steady_clock::now();
    SequencedSample s;
    // Never more than the pending buffer holds: the rest waits in the ring for the next round.
    while (pending_.size() < pending_.capacity() && ring_.try_pop(s)) {
        pending_.push_back(s);
        arrived_.push_back(now);
    }
    std::size_t ready = 0;
    while (ready < pending_.size() && (all || now - arrived_[ready] >= kHold || pending_.size() >= ring_.capacity()))
        ++ready;
    // Runs of consecutive numbers (the loop drops a sample the tap had no room for) go out as one record each.
    for (std::size_t i = 0; i < ready;) {
        std::size_t j = i + 1;
        while (j < ready && pending_[j].seq == pending_[j - 1].seq + 1) ++j;
        run_.clear();
        for (std::size_t k = i; k < j; ++k) run_.push_back(pending_[k].sample);
        journal_.intake(pending_[i].seq, run_);
        i = j;
    }
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(ready));
    arrived_.erase(arrived_.begin(), arrived_.begin() + static_cast<std::ptrdiff_t>(ready));
}

}  // namespace tridex::compute
