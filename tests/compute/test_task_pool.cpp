// tests/compute/test_task_pool.cpp - pool_for (the oneTBB task pool): every item exactly once in fixed chunks,
// slots within pool_slots, the same chunks for every thread count, exceptions rethrown to the caller.
#include <gtest/gtest.h>

#include <pthread.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "compute/parallel/task_pool.hpp"

using namespace tridex::compute;

TEST(TaskPool, EveryItemOnceInFixedChunks) {
    for (int threads : {1, 2, 3, 8, 0}) {
        const std::size_t count = 10007, grain = 64;
        std::vector<std::atomic<int>> hits(count);
        std::vector<std::atomic<std::size_t>> chunk_last((count + grain - 1) / grain);
        std::atomic<bool> bad_slot{false};
        const unsigned slots = pool_slots(threads);
        pool_for(count, grain, [&](const Chunk& c) {
            if (c.slot >= slots) bad_slot = true;
            chunk_last[c.first / grain] = c.last;
            for (std::size_t i = c.first; i < c.last; ++i) hits[i].fetch_add(1);
        }, threads);
        EXPECT_FALSE(bad_slot) << threads;
        for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(hits[i].load(), 1) << "item " << i << ", threads " << threads;
        for (std::size_t k = 0; k < chunk_last.size(); ++k)
            EXPECT_EQ(chunk_last[k].load(), std::min(count, (k + 1) * grain)) << "chunk " << k << ", threads " << threads;
    }
}

TEST(TaskPool, SlotsAreExclusiveWhileRunning) {
    // Two chunks running at once never share a slot: a per-slot flag is never found set on entry.
    const unsigned slots = pool_slots(4);
    std::vector<std::atomic<int>> busy(slots);
    std::atomic<int> clashes{0};
    pool_for(4000, 1, [&](const Chunk& c) {
        if (busy[c.slot].exchange(1) != 0) ++clashes;
        volatile double x = 0.0;
        for (int i = 0; i < 2000; ++i) x = x + 1.0;
        busy[c.slot].store(0);
    }, 4);
    EXPECT_EQ(clashes.load(), 0);
}

#if defined(__linux__)
TEST(TaskPool, WorkersAreNamedForProfilers) {
    // Chunks that ran on a thread other than the caller ran on a pool worker named "tridex-pool".
    const std::thread::id caller = std::this_thread::get_id();
    std::mutex lock;
    std::set<std::string> names;
    pool_for(
        64, 1,
        [&](const Chunk&) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));  // long enough for a worker to join in
            if (std::this_thread::get_id() == caller) return;
            char name[16] = {};
            pthread_getname_np(pthread_self(), name, sizeof name);
            const std::lock_guard<std::mutex> hold(lock);
            names.insert(name);
        },
        2);
    EXPECT_FALSE(names.empty()) << "no chunk ran on a worker";
    for (const std::string& n : names) EXPECT_EQ(n, "tridex-pool");
}
#endif

TEST(TaskPool, EmptyAndZeroGrain) {
    int calls = 0;
    pool_for(0, 8, [&](const Chunk&) { ++calls; });
    EXPECT_EQ(calls, 0);
    std::atomic<int> items{0};
    pool_for(5, 0, [&](const Chunk& c) { items += static_cast<int>(c.last - c.first); });  // grain 0 = 1
    EXPECT_EQ(items.load(), 5);
    EXPECT_GE(pool_slots(), 1u);
    EXPECT_EQ(pool_slots(3), 3u);
}

TEST(TaskPool, ExceptionReachesTheCaller) {
    for (int threads : {1, 2}) {
        EXPECT_THROW(pool_for(100, 1, [](const Chunk& c) {
            if (c.first == 37) throw std::runtime_error("chunk 37");
        }, threads), std::runtime_error) << threads;
    }
    // The pool still works afterwards.
    std::atomic<int> items{0};
    pool_for(100, 3, [&](const Chunk& c) { items += static_cast<int>(c.last - c.first); }, 2);
    EXPECT_EQ(items.load(), 100);
}

namespace {

/// Writes plain values over a stretch of the calling thread's stack, where an earlier pool_for's frames were.
__attribute__((noinline)) int scribble_stack(int seed) {
    volatile int area[512];
    for (int i = 0; i < 512; ++i) area[i] = seed + i;
    return area[seed & 511];
}

}  // namespace

TEST(TaskPool, TwoCallersAtOnceThenPlainWritesOverTheirStacks) {
    // Two threads share the pool, as two sculpt threads do, and each then reuses the stack where its pool_for
    // ran. The pool's own bookkeeping there (written by whichever worker finished last) is ordered before the
    // caller's return, so ThreadSanitizer reports nothing, and every item is still visited once.
    std::atomic<long> total{0};
    const auto caller = [&](int seed) {
        for (int round = 0; round < 300; ++round) {
            std::vector<int> items(257, 0);
            pool_for(items.size(), 1, [&](const Chunk& c) {
                for (std::size_t i = c.first; i < c.last; ++i) items[i] += 1;
            }, 2);
            long sum = 0;
            for (int v : items) sum += v;
            total += sum;
            total += scribble_stack(seed + round) * 0;
        }
    };
    std::thread a(caller, 1), b(caller, 2);
    a.join();
    b.join();
    EXPECT_EQ(total.load(), 2L * 300 * 257);
}
