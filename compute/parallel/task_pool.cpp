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

// ThreadSanitizer cannot see oneTBB's hand-offs and joins (libtbb.so is not instrumented). Under TSan:
// - the fork (caller -> tasks) and the join (tasks -> caller) are announced to it, each on its own address, so tasks
//   stay unordered among themselves and real races between them are still reported;
// - oneTBB's own bookkeeping, inlined from its headers into this file, is not checked: a worker writes the caller's
//   wait node after the last task and wakes the caller inside libtbb, an order TSan cannot see, and an arena full of
//   callers runs a caller's functor on another thread. Workers are ignored while in an arena and callers while in
//   `execute`, except while a body runs (IgnoreBookkeeping / CheckBody), so every body's accesses are still checked.
#if defined(__SANITIZE_THREAD__)
#include <sanitizer/tsan_interface.h>
#define TRIDEX_TSAN_RELEASE(p) __tsan_release(p)
#define TRIDEX_TSAN_ACQUIRE(p) __tsan_acquire(p)
extern "C" {  // exported by libtsan, not declared in GCC 12's sanitizer/tsan_interface.h
void __tsan_ignore_thread_begin();
void __tsan_ignore_thread_end();
}
#endif

namespace tridex::compute {
namespace {

#if defined(__SANITIZE_THREAD__)
/// This thread's open __tsan_ignore_thread_begin calls, closed when the thread ends (a worker still in an arena
/// at the process's exit is not told that it left).
struct IgnoreCount {
    int open = 0;
    IgnoreCount() = default;
    IgnoreCount(const IgnoreCount&) = delete;
    IgnoreCount& operator=(const IgnoreCount&) = delete;
    ~IgnoreCount() {
        for (; open > 0; --open) __tsan_ignore_thread_end();
    }
};
thread_local IgnoreCount tsan_ignores;
void ignore_begin() {
    __tsan_ignore_thread_begin();
    ++tsan_ignores.open;
}
void ignore_end() {
    if (tsan_ignores.open == 0) return;
    --tsan_ignores.open;
    __tsan_ignore_thread_end();
}
bool ignoring() { return tsan_ignores.open > 0; }
#else
#define TRIDEX_TSAN_RELEASE(p) static_cast<void>(p)
#define TRIDEX_TSAN_ACQUIRE(p) static_cast<void>(p)
void ignore_begin() {}
void ignore_end() {}
bool ignoring() { return false; }
#endif

/// Under ThreadSanitizer, leaves oneTBB's bookkeeping unchecked for the scope's lifetime (nothing otherwise).
struct IgnoreBookkeeping {
    IgnoreBookkeeping() { ignore_begin(); }
    ~IgnoreBookkeeping() { ignore_end(); }
    IgnoreBookkeeping(const IgnoreBookkeeping&) = delete;
    IgnoreBookkeeping& operator=(const IgnoreBookkeeping&) = delete;
};

/// One task's run of the body. Under ThreadSanitizer: its accesses are checked, it starts after the caller's fork
/// and it ends before the caller's join, also when the body throws (nothing otherwise).
class TaskScope {
public:
    TaskScope(int* fork, int* join) : join_(join), was_(ignoring()) {
        if (was_) ignore_end();
        TRIDEX_TSAN_ACQUIRE(fork);
    }
    ~TaskScope() {
        TRIDEX_TSAN_RELEASE(join_);
        if (was_) ignore_begin();
    }
    TaskScope(const TaskScope&) = delete;
    TaskScope& operator=(const TaskScope&) = delete;

private:
    int* join_;
    bool was_;
};

/// Names each worker thread that joins an arena "tridex-pool" (core/thread_name.hpp), so that profilers and
/// gpu::Context's search for a Vulkan driver's workers tell them apart from unnamed threads; under ThreadSanitizer,
/// also leaves a worker's oneTBB bookkeeping unchecked while it is in the arena.
class NamePoolWorkers : public oneapi::tbb::task_scheduler_observer {
public:
    explicit NamePoolWorkers(oneapi::tbb::task_arena& a) : oneapi::tbb::task_scheduler_observer(a) { observe(true); }
    ~NamePoolWorkers() override { observe(false); }
    void on_scheduler_entry(bool is_worker) override {
        if (!is_worker) return;
        name_this_thread("tridex-pool");
        ignore_begin();
    }
    void on_scheduler_exit(bool is_worker) override {
        if (is_worker) ignore_end();
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
    oneapi::tbb::task_arena& a = arena(slots);
    const IgnoreBookkeeping unchecked;
    // A body's exception reaches this thread through oneTBB's own hand-off, which ThreadSanitizer does not see: the
    // tasks' release of `join` is acquired on that path too, or the exception's allocation on a worker looks racy.
    const auto joined = [&] { TRIDEX_TSAN_ACQUIRE(&join); };
    try {
        a.execute([&] {
            oneapi::tbb::parallel_for(
                oneapi::tbb::blocked_range<std::size_t>(0, chunks, 1),
                [&](const oneapi::tbb::blocked_range<std::size_t>& r) {
                    const TaskScope task(&fork, &join);
                    const int index = oneapi::tbb::this_task_arena::current_thread_index();
                    const unsigned slot = index >= 0 && static_cast<unsigned>(index) < slots ? static_cast<unsigned>(index) : 0u;
                    for (std::size_t c = r.begin(); c != r.end(); ++c)
                        body(Chunk{c * grain, std::min(count, (c + 1) * grain), slot});
                },
                oneapi::tbb::simple_partitioner());
        });
    } catch (...) {
        joined();
        throw;
    }
    joined();
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
