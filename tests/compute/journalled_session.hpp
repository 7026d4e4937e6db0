// tests/compute/journalled_session.hpp - a sculpt thread with a session journal, fed a tool stream as a haptic loop
// would: the sculpt-thread tests' live session, whose journal they replay.
#pragma once

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/runtime/sculpt_thread.hpp"

namespace tridex::test {

/// What a journalled session left: the sculpt thread's counters and the journal's.
struct JournalledRun {
    app::SculptStats sculpt;
    compute::JournalStats journal;
};

/// Sculpts `samples` into `live` on a SculptThread journalling to `path` (5 ms sync interval), trickled through a
/// 256-sample ring with a pause of `pause` every `every` samples, so that the thread's batches depend on timing; stops
/// the thread (rethrowing its failure) and returns the counters.
inline JournalledRun sculpt_journalled(compute::TriDexel& live, const std::vector<ToolSample>& samples,
                                       const std::string& path, std::size_t every = 13,
                                       std::chrono::microseconds pause = std::chrono::microseconds(300)) {
    compute::Contourer contourer(live);
    contourer.update(live);
    SpscRing<ToolSample> ring(256);
    TripleBuffer<ActiveSurface> surface;
    compute::JournalWriter journal(path, "session", std::chrono::milliseconds(5));
    app::SculptThread t(live, contourer, ring, surface, Vec3(0.0));
    t.use_journal(journal);
    t.start();
    for (std::size_t i = 0; i < samples.size(); ++i) {
        while (!ring.try_push(samples[i])) std::this_thread::yield();
        if (i % every == 0) std::this_thread::sleep_for(pause);
    }
    t.stop();
    return {t.stats(), journal.stats()};
}

}  // namespace tridex::test
