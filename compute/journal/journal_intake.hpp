// compute/journal/journal_intake.hpp - the session journal's intake thread: the samples the haptic loop hands the
// sculpt thread, journalled as they leave the loop, so a session killed while the sculpt thread is behind keeps them.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <thread>
#include <vector>

#include "compute/journal/journal_writer.hpp"
#include "core/sequenced_sample.hpp"
#include "core/spsc_ring.hpp"

namespace tridex::compute {

/// Takes every sample the haptic loop gives the sculpt thread from its own ring (HapticLoopConfig::sample_tap) and
/// writes those no batch record holds yet as intake records (JournalWriter::intake, journal_format.hpp
/// kJournalIntake). Its thread wakes every kPeriod; a sample waits kHold after it arrived (the sculpt thread, when it
/// keeps up, journals it first, and it is not written twice), then goes to the journal and on to the kernel at once.
/// So what a SIGKILL loses is bounded by kHold + kPeriod plus this small thread's own scheduling delay, however far
/// behind the sculpt thread is. Allocates only at construction; never blocks the haptic loop (a full ring drops
/// samples, counted by the loop as LoopStats::tap_dropped).
class JournalIntake {
public:
    static constexpr std::size_t kRingSamples = 8192;  ///< samples the ring holds: 8 s at 1 kHz
    static constexpr std::chrono::milliseconds kPeriod{5};  ///< how often the thread takes the ring
    static constexpr std::chrono::milliseconds kHold{20};   ///< how long a sample waits for its batch record

    /// Intake for `journal`, which must outlive this object (stop() before the journal closes).
    explicit JournalIntake(JournalWriter& journal);
    /// stop().
    ~JournalIntake();
    JournalIntake(const JournalIntake&) = delete;
    JournalIntake& operator=(const JournalIntake&) = delete;

    /// The ring the haptic loop pushes into (HapticLoopConfig::sample_tap); the loop is its only producer.
    SpscRing<SequencedSample>& ring() { return ring_; }
    /// Starts the thread. Once only.
    void start();
    /// Takes what is left in the ring, writes what no batch record holds (nothing, once the sculpt thread has
    /// drained and journalled everything) and ends the thread. Idempotent.
    void stop();

private:
    void run();
    void take(bool all);  // ring -> pending_, then the pending samples older than kHold (all: every one) -> journal

    JournalWriter& journal_;
    SpscRing<SequencedSample> ring_;
    std::vector<SequencedSample> pending_;                        // arrived, not yet written; reserved once
    std::vector<std::chrono::steady_clock::time_point> arrived_;  // when each pending sample was taken
    std::vector<ToolSample> run_;                                 // one run of consecutive numbers; reserved once
    std::thread thread_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;
};

}  // namespace tridex::compute
