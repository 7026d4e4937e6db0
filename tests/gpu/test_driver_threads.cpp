// Tests of gpu/driver_threads and of the Context's pinning of lavapipe's worker threads one per core.
#include <gtest/gtest.h>

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <set>
#include <thread>
#include <vector>

#include "gpu/context.hpp"
#include "gpu/driver_threads.hpp"

namespace tridex::gpu {
namespace {

int allowed_cpus() {
    cpu_set_t s;
    CPU_ZERO(&s);
    if (sched_getaffinity(0, sizeof s, &s) != 0) return 0;
    return CPU_COUNT(&s);
}

// The CPUs thread `tid` may run on (empty when it has ended).
std::vector<int> affinity_of(int tid) {
    cpu_set_t s;
    CPU_ZERO(&s);
    std::vector<int> out;
    if (sched_getaffinity(tid, sizeof s, &s) != 0) return out;
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (CPU_ISSET(c, &s)) out.push_back(c);
    return out;
}

// Threads that wait until released; each reports its thread id.
struct Sleepers {
    std::atomic<bool> release{false};
    std::atomic<int> started{0};
    std::vector<std::thread> threads;
    std::vector<int> tids;
    explicit Sleepers(int n, const char* name = nullptr) : tids(static_cast<std::size_t>(n), 0) {
        for (int i = 0; i < n; ++i)
            threads.emplace_back([this, i, name] {
                if (name) pthread_setname_np(pthread_self(), name);
                tids[static_cast<std::size_t>(i)] = static_cast<int>(gettid());
                started.fetch_add(1);
                while (!release.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
            });
        while (started.load() < n) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ~Sleepers() {
        release = true;
        for (auto& t : threads) t.join();
    }
};

TEST(DriverThreads, ListsThisThreadAndNewThreadsWithTheirNames) {
    const std::vector<ProcessThread> before = process_threads();
    ASSERT_FALSE(before.empty());
    const int self = static_cast<int>(gettid());
    EXPECT_TRUE(std::any_of(before.begin(), before.end(), [&](const ProcessThread& t) { return t.tid == self; }));
    EXPECT_TRUE(std::is_sorted(before.begin(), before.end(), [](const auto& a, const auto& b) { return a.tid < b.tid; }));
    EXPECT_FALSE(current_thread_name().empty());

    Sleepers named(2, "llvmpipe-7");
    Sleepers unnamed(1);
    Sleepers other(1, "tx:disk$0");
    const std::vector<ProcessThread> after = process_threads();
    const std::vector<ProcessThread> workers = new_worker_threads(before, after, current_thread_name());
    // The two "llvmpipe-" threads and the unnamed one (which kept this thread's name); not "disk$0", not old ones.
    std::set<int> got;
    for (const auto& t : workers) got.insert(t.tid);
    EXPECT_EQ(got, (std::set<int>{named.tids[0], named.tids[1], unnamed.tids[0]}));
    EXPECT_FALSE(got.count(other.tids[0]));
    EXPECT_FALSE(got.count(self));
}

TEST(DriverThreads, NewWorkerThreadsOfSyntheticListings) {
    const std::vector<ProcessThread> before = {{10, "app"}, {11, "app"}};
    const std::vector<ProcessThread> after = {{10, "app"}, {11, "app"}, {12, "app"}, {13, "llvmpipe-0"},
                                              {14, "app:disk$0"}, {15, "haptics"}, {16, "app"}};
    const std::vector<ProcessThread> w = new_worker_threads(before, after, "app");
    ASSERT_EQ(w.size(), 3u);
    EXPECT_EQ(w[0].tid, 12);
    EXPECT_EQ(w[1].tid, 13);
    EXPECT_EQ(w[2].tid, 16);
    // An unknown creator name: only the llvmpipe threads.
    const std::vector<ProcessThread> only = new_worker_threads(before, after, "");
    ASSERT_EQ(only.size(), 1u);
    EXPECT_EQ(only[0].tid, 13);
}

TEST(DriverThreads, SpreadPinsEachThreadToOneCoreInTurn) {
    Sleepers s(4);
    std::vector<ProcessThread> threads;
    for (const int tid : s.tids) threads.push_back({tid, "x"});
    const int cpus = allowed_cpus();
    const int pinned = spread_over_cpus(threads);
    if (cpus < 2) {
        EXPECT_EQ(pinned, 0) << "with one usable core nothing is pinned";
        for (const int tid : s.tids) EXPECT_EQ(static_cast<int>(affinity_of(tid).size()), cpus);
        return;
    }
    EXPECT_EQ(pinned, 4);
    std::vector<int> first;
    for (const int tid : s.tids) {
        const std::vector<int> a = affinity_of(tid);
        ASSERT_EQ(a.size(), 1u) << "thread " << tid;
        first.push_back(a[0]);
    }
    EXPECT_NE(first[0], first[1]) << "consecutive threads get different cores";
    EXPECT_EQ(first[0], first[static_cast<std::size_t>(std::min(cpus, 4)) % 4]) << "the cores are dealt in turn";
    // The calling thread is not pinned.
    EXPECT_EQ(static_cast<int>(affinity_of(static_cast<int>(gettid())).size()), cpus);
    // A thread id that does not exist is skipped, not fatal.
    EXPECT_EQ(spread_over_cpus(std::vector<ProcessThread>{{0x7ffffff0, "gone"}}), 0);
}

// Threads named llvmpipe-N that exist now.
std::vector<ProcessThread> llvmpipe_threads(const std::vector<ProcessThread>& before) {
    std::vector<ProcessThread> out;
    for (const auto& t : new_worker_threads(before, process_threads(), ""))
        if (t.name.rfind("llvmpipe-", 0) == 0) out.push_back(t);
    return out;
}

TEST(DriverThreads, ContextPinsLavapipeWorkersOnePerCore) {
    const int cpus = allowed_cpus();
    const std::vector<ProcessThread> before = process_threads();
    Context ctx = Context::create({});
    ASSERT_EQ(ctx.properties().deviceType, VK_PHYSICAL_DEVICE_TYPE_CPU) << ctx.device_name();
    if (cpus < 2) {  // one usable core (e.g. under taskset -c 0): lavapipe may start no workers; nothing is pinned
        EXPECT_EQ(ctx.spread_driver_threads(), 0);
        return;
    }
    const std::vector<ProcessThread> rast = llvmpipe_threads(before);
    ASSERT_FALSE(rast.empty()) << "lavapipe starts llvmpipe-N threads with the device";
    // lavapipe starts at least its queue thread, one rasteriser and one compute thread per core.
    EXPECT_GE(ctx.spread_driver_threads(), 1 + 2 * std::min(cpus, 2));
    std::set<int> cores;
    for (const auto& t : rast) {
        const std::vector<int> a = affinity_of(t.tid);
        ASSERT_EQ(a.size(), 1u) << t.name;
        cores.insert(a[0]);
    }
    EXPECT_EQ(static_cast<int>(cores.size()), std::min<int>(cpus, static_cast<int>(rast.size())));
    // The creating thread keeps every core.
    EXPECT_EQ(static_cast<int>(affinity_of(static_cast<int>(gettid())).size()), cpus);
    ctx.submit_and_wait([](VkCommandBuffer) {});
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(DriverThreads, OptionAndEnvironmentTurnPinningOff) {
    const int cpus = allowed_cpus();
    {
        const std::vector<ProcessThread> before = process_threads();
        ContextOptions o;
        o.spread_cpu_driver_threads = false;
        Context ctx = Context::create(o);
        EXPECT_EQ(ctx.spread_driver_threads(), 0);
        for (const auto& t : llvmpipe_threads(before)) EXPECT_EQ(static_cast<int>(affinity_of(t.tid).size()), cpus) << t.name;
    }
    {
        ::setenv("TRIDEX_DRIVER_AFFINITY", "0", 1);
        const std::vector<ProcessThread> before = process_threads();
        Context ctx = Context::create({});
        ::unsetenv("TRIDEX_DRIVER_AFFINITY");
        EXPECT_EQ(ctx.spread_driver_threads(), 0);
        for (const auto& t : llvmpipe_threads(before)) EXPECT_EQ(static_cast<int>(affinity_of(t.tid).size()), cpus) << t.name;
    }
}

}  // namespace
}  // namespace tridex::gpu
