// compute/parallel/task_pool.hpp - the persistent task scheduler (oneTBB) that sculpting work runs on.
#pragma once

#include <cstddef>
#include <functional>

#include "core/progress.hpp"

namespace tridex::compute {

/// A range of work items [first, last) handed to one call of a parallel body, and the slot of the thread
/// running it: 0 <= slot < pool_slots(threads) (distinct for calls running at the same time), so a body can
/// keep per-slot scratch memory.
struct Chunk {
    std::size_t first = 0, last = 0;
    unsigned slot = 0;
};

/// Threads a pool_for call with `threads` uses: threads > 0 as given, else the machine's cores
/// (oneTBB's default concurrency, which follows the process's CPU affinity mask). At least 1.
unsigned pool_slots(int threads = 0);

/// Runs body(chunk) over [0, count) in chunks of `grain` items (the last one may be shorter; grain 0 is
/// taken as 1) on a persistent oneTBB task arena of pool_slots(threads) threads; the calling thread joins
/// in. The split into chunks depends only on count and grain, never on the number of threads, so a body
/// whose chunks write disjoint data gives the same result for every thread count. Worker threads live for
/// the whole process (no thread is started per call; arenas are made once per distinct thread count).
/// The haptic thread is never one of them: it is a std::thread of its own (haptics/haptic_loop.hpp) with
/// SCHED_FIFO when granted, so it preempts these workers on any core.
/// Returns when every chunk is done. An exception thrown by the body cancels the chunks not yet started and
/// is rethrown here (the first one thrown); chunks already run keep their effects.
void pool_for(std::size_t count, std::size_t grain, const std::function<void(const Chunk&)>& body, int threads = 0);

/// Slices of a pool_for_progress call (its progress is reported this many times at most).
inline constexpr std::size_t kProgressSlices = 64;

/// As pool_for, run as up to kProgressSlices consecutive pool_for calls over whole multiples of `grain` (so the
/// chunks, and with them the results, are those of one pool_for call; Chunk::first and last are in [0, count)),
/// calling report_progress(progress, items done, count) on the calling thread after each slice. With an empty
/// `progress`: one pool_for call. Exceptions as pool_for (the slices after a throwing one do not run).
void pool_for_progress(std::size_t count, std::size_t grain, const std::function<void(const Chunk&)>& body,
                       const ProgressFn& progress, int threads = 0);

}  // namespace tridex::compute
