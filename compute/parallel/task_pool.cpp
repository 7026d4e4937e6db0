// compute/parallel/task_pool.cpp - pool_for on oneTBB task arenas (one per distinct thread count).
#include "compute/parallel/task_pool.hpp"

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_scheduler_observer.h>

#include "core/thread_name.hpp"

// ThreadSanitizer cannot see oneTBB's hand-off and join (libtbb.so is not instrumented): under TSan the fork
// (caller -> tasks) and the join (tasks -> caller) are announced to it, each on its own address, so tasks stay
// unordered among themselves and real races between them are still reported.
#if defined(__SANITIZE_THREAD__)
#include <sanitizer/tsan_interface.h>
#define TRIDEX_TSAN_RELEASE(p) __tsan_release(p)
#define TRIDEX_TSAN_ACQUIRE(p) __tsan_acquire(p)
#else
#define TRIDEX_TSAN_RELEASE(p) static_cast<void>(p)
#define TRIDEX_TSAN_ACQUIRE(p) static_cast<void>(p)
#endif

namespace tridex::compute {
namespace {

/// Names each worker thread that joins an arena "tridex-pool" (core/thread_name.hpp), so that profilers and
/// gpu::Context's search for a Vulkan driver's workers tell them apart from unnamed threads.
class NamePoolWorkers : public oneapi::tbb::task_scheduler_observer {
public:
    explicit NamePoolWorkers(oneapi::tbb::task_arena& a) : oneapi::tbb::task_scheduler_observer(a) { observe(true); }
    ~NamePoolWorkers() override { observe(false); }
    void on_scheduler_entry(bool is_worker) override {
        if (is_worker) name_this_thread("tridex-pool");
    }
};

/// One task arena and the observer that names its workers.
struct Arena {
    explicit Arena(unsigned slots) : arena(static_cast<int>(slots)), names(arena) { arena.initialize(); }
    oneapi::tbb::task_arena arena;
    NamePoolWorkers names;
};

/// The arena with `slots` threads, made on first use and kept for the process's lifetime.
oneapi::tbb::task_arena& arena(unsigned slots) {
    static std::mutex lock;
    static std::map<unsigned, std::unique_ptr<Arena>> arenas;
    const std::lock_guard<std::mutex> hold(lock);
    std::unique_ptr<Arena>& a = arenas[slots];
    if (!a) a = std::make_unique<Arena>(slots);
    return a->arena;
}

}  // namespace

unsigned pool_slots(int threads) {
    if (threads > 0) return static_cast<unsigned>(threads);
    const int n = oneapi::tbb::info::default_concurrency();
    return n > 0 ? static_cast<unsigned>(n) : 1u;
}

void pool_for(std::size_t count, std::size_t grain, const std::function<void(const Chunk&)>& body, int threads) {
    if (count == 0) return;
    if (grain == 0) grain = 1;
    const std::size_t chunks = (count + grain - 1) / grain;
    const unsigned slots = pool_slots(threads);
    if (chunks == 1 || slots == 1) {  // nothing to share: no hand-off
        for (std::size_t c = 0; c < chunks; ++c) body(Chunk{c * grain, std::min(count, (c + 1) * grain), 0});
        return;
    }
    int fork = 0, join = 0;  // addresses for the TSan announcements only
    TRIDEX_TSAN_RELEASE(&fork);
    arena(slots).execute([&] {
        oneapi::tbb::parallel_for(
            oneapi::tbb::blocked_range<std::size_t>(0, chunks, 1),
            [&](const oneapi::tbb::blocked_range<std::size_t>& r) {
                TRIDEX_TSAN_ACQUIRE(&fork);
                const int index = oneapi::tbb::this_task_arena::current_thread_index();
                const unsigned slot = index >= 0 && static_cast<unsigned>(index) < slots ? static_cast<unsigned>(index) : 0u;
                for (std::size_t c = r.begin(); c != r.end(); ++c)
                    body(Chunk{c * grain, std::min(count, (c + 1) * grain), slot});
                TRIDEX_TSAN_RELEASE(&join);
            },
            oneapi::tbb::simple_partitioner());
    });
    TRIDEX_TSAN_ACQUIRE(&join);
}

void pool_for_progress(std::size_t count, std::size_t grain, const std::function<void(const Chunk&)>& body,
                       const ProgressFn& progress, int threads) {
    if (!progress) {
        pool_for(count, grain, body, threads);
        return;
    }
    if (grain == 0) grain = 1;
    const std::size_t chunks = (count + grain - 1) / grain;
    const std::size_t per_slice = std::max<std::size_t>(1, (chunks + kProgressSlices - 1) / kProgressSlices) * grain;
    for (std::size_t first = 0; first < count; first += per_slice) {
        const std::size_t n = std::min(per_slice, count - first);
        pool_for(
            n, grain,
            [&](const Chunk& c) {
                body(Chunk{first + c.first, first + c.last, c.slot});
            },
            threads);
        report_progress(progress, static_cast<double>(first + n), static_cast<double>(count));
    }
}

}  // namespace tridex::compute
