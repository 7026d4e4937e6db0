// Tests of haptics/telemetry and haptics/realtime: exact histogram bookkeeping and quantiles, the
// loop's period and compute histograms (step() mode, exact periods; and a short threaded run), and the
// real-time request, which may be granted or refused but must be reported truthfully.
#include <gtest/gtest.h>

#include <pthread.h>
#include <sched.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "devices/simulated_device.hpp"
#include "haptics/realtime.hpp"
#include "haptics/telemetry.hpp"
#include "loop_fixture.hpp"

namespace tridex::haptics {
namespace {

using devices::DeviceProfile;
using devices::ScriptedPath;
using devices::SimulatedDevice;

TEST(Telemetry, HistogramCountsAndQuantilesAreExact) {
    AtomicHistogram h(10e-6);  // 200 bins of 10 us: [0, 2 ms), then overflow
    for (double x : {5e-6, 15e-6, 15e-6, 995e-6, 2.5e-3}) h.add(x);
    Histogram s = h.snapshot();
    EXPECT_EQ(s.bin_width_s, 10e-6);
    EXPECT_EQ(s.total(), 5u);
    EXPECT_EQ(s.counts[0], 1u);
    EXPECT_EQ(s.counts[1], 2u);
    EXPECT_EQ(s.counts[99], 1u);
    EXPECT_EQ(s.overflow, 1u);
    EXPECT_EQ(s.max_s, 2.5e-3);
    EXPECT_NEAR(s.quantile(0.0), 10e-6, 1e-15);   // rank 1 -> bin 0's upper edge
    EXPECT_NEAR(s.quantile(0.5), 20e-6, 1e-15);   // rank 3 -> bin 1
    EXPECT_NEAR(s.quantile(0.8), 1000e-6, 1e-15); // rank 4 -> bin 99
    EXPECT_EQ(s.quantile(1.0), 2.5e-3);           // rank 5 lies in the overflow: the maximum
    // A maximum inside a bin bounds the quantiles that bin holds: p99 never reports more than the largest sample.
    AtomicHistogram tight(20e-6);
    for (double x : {1001e-6, 1005e-6, 1028.9e-6}) tight.add(x);
    const Histogram t = tight.snapshot();
    EXPECT_EQ(t.quantile(0.99), 1028.9e-6);
    EXPECT_LE(t.quantile(0.99), t.max_s);
    EXPECT_NEAR(t.quantile(0.0), 1020e-6, 1e-15);  // below the maximum: the bin's upper edge
    h.add(-1.0);  // a clock going backwards, or NaN: bin 0, no crash
    h.add(std::nan(""));
    h.add(INFINITY);
    s = h.snapshot();
    EXPECT_EQ(s.counts[0], 3u);
    EXPECT_EQ(s.overflow, 2u);
    h.clear();
    s = h.snapshot();
    EXPECT_EQ(s.total(), 0u);
    EXPECT_EQ(s.quantile(0.5), 0.0);
}

TEST(Telemetry, LoopHistogramsInStepMode) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring(4096);
    HapticLoopConfig cfg;
    cfg.max_ticks = 200;
    HapticLoop loop(dev, surface, ring, cfg);
    // 100 ticks 1 ms apart (in microseconds on the loop clock: exact binary steps are not needed, the
    // period is 1000 us +- 1e-9), then one 5 ms gap: 5x the period, past the 4-period histogram range.
    double t = 0.0;
    for (int k = 0; k < 100; ++k) loop.step(t += 1e-3);
    loop.step(t += 5e-3);
    const LoopStats st = loop.stats();
    const Histogram& p = st.period_histogram;
    EXPECT_NEAR(p.bin_width_s, 20e-6, 1e-18);  // period / 50
    EXPECT_EQ(p.total(), 100u);                // no period for the first tick
    EXPECT_EQ(p.overflow, 1u);
    EXPECT_EQ(p.counts[49] + p.counts[50], 99u);  // 1 ms sits on the edge between bins 49 and 50
    EXPECT_NEAR(p.max_s, 5e-3, 1e-9);
    EXPECT_NEAR(p.quantile(0.5), 1e-3, 20e-6 + 1e-12);
    EXPECT_EQ(st.compute_histogram.total(), 101u);
    EXPECT_NEAR(st.compute_histogram.bin_width_s, 1e-6, 1e-18);
    EXPECT_FALSE(st.realtime_scheduling);  // step() mode never asks
    loop.stop();
    EXPECT_EQ(loop.records().size(), 101u);
    EXPECT_NEAR(loop.records()[100].period_us, 5000.0f, 1e-3f);
}

// Whatever the system decides, the answer must match the thread's actual policy.
TEST(Realtime, RequestIsReportedTruthfully) {
    RealtimeStatus st;
    int policy = -1;
    sched_param now{};
    std::thread th([&] {
        st = request_realtime(20, false);
        pthread_getschedparam(pthread_self(), &policy, &now);
    });
    th.join();
    std::printf("SCHED_FIFO %s (priority %d, errno %d)\n", st.fifo ? "granted" : "refused", st.priority, st.fifo_errno);
    if (st.fifo) {
        EXPECT_EQ(policy, SCHED_FIFO);
        EXPECT_EQ(now.sched_priority, 20);
        EXPECT_EQ(st.fifo_errno, 0);
    } else {
        EXPECT_NE(policy, SCHED_FIFO);
        EXPECT_NE(st.fifo_errno, 0);
    }
    EXPECT_FALSE(st.memory_locked);  // not asked
}

TEST(Realtime, LoopReportsWhatItGot) {
    // Expected answer: what a fresh thread gets for the same request.
    RealtimeStatus probe;
    std::thread th([&] { probe = request_realtime(80, false); });
    th.join();
    for (bool ask : {true, false}) {
        SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
        devices::SimulatedFaults f;
        f.vanish_after_reads = 50;
        dev.set_faults(f);
        TripleBuffer<ActiveSurface> surface;
        SpscRing<ToolSample> ring(128);
        HapticLoopConfig cfg;
        cfg.max_ticks = 100;
        cfg.request_realtime = ask;
        cfg.lock_memory = false;
        HapticLoop loop(dev, surface, ring, cfg);
        loop.start();
        ASSERT_TRUE(test::wait_until_stopped(loop, 10.0));
        loop.stop();
        const LoopStats st = loop.stats();
        std::printf("request_realtime %d: realtime_scheduling %d; period median <= %.0f us, p99 <= %.0f us, "
                    "compute p99 <= %.0f us\n",
                    ask, st.realtime_scheduling, st.period_histogram.quantile(0.5) * 1e6,
                    st.period_histogram.quantile(0.99) * 1e6, st.compute_histogram.quantile(0.99) * 1e6);
        EXPECT_EQ(st.realtime_scheduling, ask && probe.fifo);
        EXPECT_EQ(st.ticks, 50u);
        EXPECT_EQ(st.period_histogram.total(), 49u);
        EXPECT_EQ(st.compute_histogram.total(), 50u);
    }
}

}  // namespace
}  // namespace tridex::haptics
