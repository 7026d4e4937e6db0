// Tests of haptics/haptic_loop: tick rate, records, ring hand-off and drops (none when running free), device loss,
// NaN samples, device <-> world mapping, configuration checks, and the period statistics of a 1 s run.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "devices/simulated_device.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

#if defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;  // a ThreadSanitizer build (the tsan preset)
#else
constexpr bool kSanitized = false;
#endif

using devices::DeviceProfile;
using devices::ScriptedPath;
using devices::SimulatedDevice;
using devices::SimulatedFaults;

constexpr double kH = 1e-3;  // cell, m

// World plane z = 10.25 mm (solid below) and a device path from 5 mm above it to 2 mm below in 0.1 s.
struct PressScene {
    std::unique_ptr<ActiveSurface> surface = test::z_plane(kH, 10.25f);
    ScriptedPath path{{0.0, 0.1}, {Vec3(0.012, 0.012, 0.01525), Vec3(0.012, 0.012, 0.00825)}};
};

double percentile(std::vector<double> v, double p) {
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

TEST(HapticLoop, RunsAtOneKilohertzAndRecordsEveryTick) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0, 0.0, 0.05)));
    TripleBuffer<ActiveSurface> surface;  // nothing published: free space
    SpscRing<ToolSample> ring(1024);
    HapticLoopConfig cfg;
    cfg.max_ticks = 1000;
    cfg.contact.tool_radius_m = 2e-3;
    cfg.op = ToolOp::kUnion;
    HapticLoop loop(dev, surface, ring, cfg);
    const auto wall0 = std::chrono::steady_clock::now();
    loop.start();
    EXPECT_TRUE(loop.running());
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    loop.stop();
    const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
    EXPECT_FALSE(loop.running());
    const LoopStats st = loop.stats();
    ASSERT_GE(st.ticks, 2u);
    // One tick per 1 ms deadline over the loop's own span (first to last tick), measured on its clock: a
    // shared machine that stalls the loop thread makes it overrun and skip deadlines (counted), and one
    // that stalls this thread lengthens the run; neither may add ticks beyond the deadlines.
    const double span_ms = loop.records().back().t_s * 1e3;
    std::printf("%.1f ms run (%.1f ms of ticks): %zu ticks, %zu overruns\n", wall_ms, span_ms, st.ticks, st.overruns);
    EXPECT_LE(static_cast<double>(st.ticks), std::floor(span_ms) + 2.0);
    if (st.overruns == 0) {
        EXPECT_GE(static_cast<double>(st.ticks), std::floor(span_ms) - 1.0) << "a deadline was skipped without an overrun";
    }
    EXPECT_LE(static_cast<double>(st.ticks), wall_ms + 2.0);
    EXPECT_GE(span_ms, 250.0) << "the loop ticked for only part of the 300 ms";
    EXPECT_FALSE(st.device_lost);
    EXPECT_EQ(st.invalid_samples, 0u);
    EXPECT_EQ(st.samples_dropped, 0u);
    const auto& recs = loop.records();
    ASSERT_EQ(recs.size(), st.ticks);
    std::vector<double> periods;
    for (std::size_t i = 1; i < recs.size(); ++i) {
        EXPECT_GT(recs[i].t_s, recs[i - 1].t_s);
        EXPECT_NEAR(recs[i].t_s - recs[i - 1].t_s, recs[i].period_us * 1e-6, 1e-6);
        periods.push_back(recs[i].period_us);
    }
    EXPECT_EQ(recs[0].period_us, 0.0f);
    EXPECT_NEAR(percentile(periods, 0.5), 1000.0, 100.0);  // us; absolute deadlines keep the median on 1 ms
    // Every tick pushed one ToolSample, in order: device time, the HIP, radius and op.
    ToolSample ts;
    std::size_t n = 0;
    while (ring.try_pop(ts)) {
        ASSERT_LT(n, recs.size());
        EXPECT_DOUBLE_EQ(ts.t_s, static_cast<double>(n + 1) * 1e-3);  // simulated device time
        EXPECT_EQ(ts.position, recs[n].hip_m);
        EXPECT_EQ(ts.tool.radius_m, 2e-3);
        EXPECT_EQ(ts.op, ToolOp::kUnion);
        ++n;
    }
    EXPECT_EQ(n, st.ticks);
    // Free space: zero force every tick, and zero force written last.
    for (const TickRecord& r : recs) EXPECT_EQ(r.force_n, Vec3(0.0));
    EXPECT_EQ(dev.writes(), st.ticks + 1);
    EXPECT_EQ(dev.last_force_n(), Vec3(0.0));
}

TEST(HapticLoop, FullRingCountsDropsAndKeepsGoing) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    SimulatedFaults f;
    f.vanish_after_reads = 100;
    dev.set_faults(f);
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring(16);  // nobody drains it
    HapticLoopConfig cfg;
    cfg.max_ticks = 50;  // fewer records than ticks: recording stops when full
    HapticLoop loop(dev, surface, ring, cfg);
    loop.start();
    ASSERT_TRUE(test::wait_until_stopped(loop, 5.0));
    loop.stop();
    const LoopStats st = loop.stats();
    EXPECT_EQ(st.ticks, 100u);
    EXPECT_EQ(st.samples_dropped, 100u - 16u);
    EXPECT_EQ(loop.records().size(), 50u);
    ToolSample ts;
    for (int i = 1; i <= 16; ++i) {  // the ring holds the first 16 samples
        ASSERT_TRUE(ring.try_pop(ts));
        EXPECT_DOUBLE_EQ(ts.t_s, i * 1e-3);
    }
    EXPECT_FALSE(ring.try_pop(ts));
}

// A free-running loop (a replay) waits for room in a full ring instead of dropping: a slow consumer gets every sample,
// in order; the loop clock is the tick count times the period, however fast the ticks ran.
TEST(HapticLoop, FreeRunningLoopWaitsForRoomAndDropsNothing) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    SimulatedFaults f;
    f.vanish_after_reads = 300;
    dev.set_faults(f);
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring(16);
    HapticLoopConfig cfg;
    cfg.max_ticks = 300;
    cfg.free_run = true;
    HapticLoop loop(dev, surface, ring, cfg);
    loop.start();
    std::vector<double> got;
    ToolSample ts;
    while (got.size() < 300) {  // a consumer slower than the loop: the ring is full most of the time
        if (ring.try_pop(ts))
            got.push_back(ts.t_s);
        else if (!loop.running())
            break;
        std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
    ASSERT_TRUE(test::wait_until_stopped(loop, 5.0));
    loop.stop();
    const LoopStats st = loop.stats();
    EXPECT_EQ(st.ticks, 300u);
    EXPECT_EQ(st.samples_dropped, 0u);
    EXPECT_EQ(st.overruns, 0u);
    ASSERT_EQ(got.size(), 300u);
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_DOUBLE_EQ(got[i], static_cast<double>(i + 1) * 1e-3);
    ASSERT_EQ(loop.records().size(), 300u);
    EXPECT_DOUBLE_EQ(loop.records()[299].t_s, 299 * cfg.period_s) << "the loop clock counts ticks";
}

TEST(HapticLoop, VanishedDeviceStopsTheLoopWithZeroForceLast) {
    PressScene scene;
    SimulatedDevice dev(DeviceProfile::phantom_omni(), scene.path);
    SimulatedFaults f;
    f.vanish_after_reads = 200;
    dev.set_faults(f);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *scene.surface);
    SpscRing<ToolSample> ring(1024);
    HapticLoopConfig cfg;
    cfg.max_ticks = 1000;
    HapticLoop loop(dev, surface, ring, cfg);
    loop.start();
    ASSERT_TRUE(test::wait_until_stopped(loop, 5.0));  // ends by itself
    const LoopStats st = loop.stats();
    EXPECT_TRUE(st.device_lost);
    EXPECT_EQ(st.ticks, 200u);
    loop.stop();
    ASSERT_EQ(loop.records().size(), 200u);
    // It was pushing on the device (pressed into the plane) right before the loss ...
    EXPECT_TRUE(loop.records().back().contact);
    EXPECT_GT(loop.records().back().force_n.z, 0.1);
    // ... and the last command it sent is zero.
    EXPECT_EQ(dev.writes(), 201u);
    EXPECT_EQ(dev.last_force_n(), Vec3(0.0));
    EXPECT_EQ(dev.last_torque_nm(), Vec3(0.0));
}

TEST(HapticLoop, NanSamplesAreCountedAndGetZeroForce) {
    PressScene scene;
    SimulatedDevice dev(DeviceProfile::phantom_omni(), scene.path);
    SimulatedFaults f;
    f.vanish_after_reads = 300;
    f.nan_first_read = 150;
    f.nan_count = 5;
    dev.set_faults(f);
    dev.enable_trace(400);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *scene.surface);
    SpscRing<ToolSample> ring(1024);
    HapticLoopConfig cfg;
    cfg.max_ticks = 1000;
    HapticLoop loop(dev, surface, ring, cfg);
    loop.start();
    ASSERT_TRUE(test::wait_until_stopped(loop, 5.0));
    loop.stop();
    const LoopStats st = loop.stats();
    EXPECT_EQ(st.invalid_samples, 5u);
    EXPECT_EQ(st.ticks, 300u);
    const auto& recs = loop.records();
    ASSERT_EQ(recs.size(), 300u);
    // Read n (1-based) is record n-1; its write acts during the device's step n+1 = trace[n].
    EXPECT_GT(recs[148].force_n.z, 0.1);
    EXPECT_GT(dev.trace()[149].device_force_n.z, 0.1);
    for (int n = 150; n <= 154; ++n) {
        EXPECT_FALSE(recs[n - 1].valid_sample) << n;
        EXPECT_EQ(recs[n - 1].force_n, Vec3(0.0)) << n;
        EXPECT_EQ(dev.trace()[n].device_force_n, Vec3(0.0)) << n;
        EXPECT_EQ(recs[n - 1].hip_m, recs[148].hip_m);  // the last valid HIP (read 149)
    }
    // The watchdog tripped once; it re-arms after SafetyConfig::rearm_s = 10 ms of healthy device time
    // (read 164: 0.164 - 0.154 >= 0.01), and the force ramps in again over ramp_s = 50 ms from there.
    EXPECT_EQ(st.watchdog_trips, 1u);
    EXPECT_EQ(recs[149].watchdog, kWatchdogNonFinite);
    const double t_rearm = 0.164;
    for (int n = 155; n <= 163; ++n) {
        EXPECT_TRUE(recs[n - 1].valid_sample) << n;
        EXPECT_EQ(recs[n - 1].watchdog, 0) << n;
        EXPECT_FALSE(recs[n - 1].force_enabled) << n;
        EXPECT_EQ(recs[n - 1].force_n, Vec3(0.0)) << n;
    }
    for (int n = 164; n <= 300; ++n) {
        const TickRecord& r = recs[n - 1];
        EXPECT_TRUE(r.force_enabled) << n;
        const double ramp = std::clamp((r.device.t_s - t_rearm) / 0.05, 0.0, 1.0);
        EXPECT_NEAR(r.ramp, ramp, 1e-6) << n;
    }
    EXPECT_EQ(recs[163].force_n, Vec3(0.0));  // the ramp starts at 0 on the re-arm tick
    EXPECT_GT(recs[163 + 25].force_n.z, 0.0);
    EXPECT_GT(recs[163 + 60].force_n.z, 0.1);  // full force again after the ramp
    // Invalid samples push no ToolSample.
    std::size_t samples = 0;
    ToolSample ts;
    while (ring.try_pop(ts)) {
        EXPECT_TRUE(is_finite(ts.position));
        ++samples;
    }
    EXPECT_EQ(samples, 295u);
}

TEST(HapticLoop, MapsDeviceToWorldAndRotatesForceBack) {
    // Device frame: x right, y up, z toward the user. World: the device's y is world z (90 deg about x),
    // the device origin sits at (12, 12, 10) mm, and device motion is scaled by 2.
    Pose d2w;
    d2w.orientation = glm::angleAxis(glm::radians(90.0), Vec3(1.0, 0.0, 0.0));
    d2w.position = Vec3(0.012, 0.012, 0.010);
    // World z = 10 mm + 2 * device y: device y from +2.5 mm to -1 mm crosses the plane at 10.25 mm.
    ScriptedPath path({0.0, 0.1}, {Vec3(0.0, 0.0025, 0.0), Vec3(0.0, -0.001, 0.0)});
    SimulatedDevice dev(DeviceProfile::phantom_omni(), path);
    SimulatedFaults f;
    f.vanish_after_reads = 250;
    dev.set_faults(f);
    dev.enable_trace(300);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *test::z_plane(kH, 10.25f));
    SpscRing<ToolSample> ring(1024);
    HapticLoopConfig cfg;
    cfg.max_ticks = 1000;
    cfg.device_to_world = d2w;
    cfg.workspace_scale = 2.0;
    HapticLoop loop(dev, surface, ring, cfg);
    loop.start();
    ASSERT_TRUE(test::wait_until_stopped(loop, 5.0));
    loop.stop();
    const auto& recs = loop.records();
    ASSERT_EQ(recs.size(), 250u);
    std::size_t contacts = 0;
    for (std::size_t k = 0; k < recs.size(); ++k) {
        const Vec3 expect_hip = d2w.apply(2.0 * dev.trace()[k].position_m);
        EXPECT_NEAR(glm::length(recs[k].hip_m - expect_hip), 0.0, 1e-15);
        if (k + 1 < dev.trace().size()) {
            const Vec3 f_dev = glm::conjugate(d2w.orientation) * recs[k].force_n;
            EXPECT_NEAR(glm::length(dev.trace()[k + 1].device_force_n - f_dev), 0.0, 1e-15);
        }
        if (recs[k].contact && k + 1 < dev.trace().size()) {
            ++contacts;
            // World +z is device +y: the device is pushed back up its own y axis.
            EXPECT_NEAR(dev.trace()[k + 1].device_force_n.z, 0.0, 1e-15);
            EXPECT_GE(dev.trace()[k + 1].device_force_n.y, 0.0);
        }
    }
    EXPECT_GT(contacts, 100u);
    // Each sample says where the active-surface window belongs: at the god-object, not at the HIP that
    // went below the plane (one point: the tool centre moved by the proxy offset = the proxy).
    ToolSample ts;
    std::size_t k = 0, below = 0;
    while (ring.try_pop(ts) && k < recs.size()) {
        EXPECT_NEAR(glm::length(ts.surface_m - recs[k].proxy_m), 0.0, 1e-12) << k;
        if (recs[k].contact) {
            EXPECT_GE(ts.surface_m.z, 0.01025 - 1e-6) << k;  // never below the plane
            if (ts.position.z < 0.01025) ++below;
        } else {
            EXPECT_EQ(ts.surface_m, ts.position) << k;
        }
        ++k;
    }
    EXPECT_EQ(k, recs.size());
    EXPECT_GT(below, 50u);  // the HIP did go below the plane
}

TEST(HapticLoop, RestartClearsRecordsAndCounters) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    SimulatedFaults f;
    f.vanish_after_reads = 30;
    dev.set_faults(f);
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring(64);
    HapticLoopConfig cfg;
    cfg.max_ticks = 100;
    HapticLoop loop(dev, surface, ring, cfg);
    loop.start();
    ASSERT_TRUE(test::wait_until_stopped(loop, 5.0));
    loop.stop();
    EXPECT_EQ(loop.records().size(), 30u);
    loop.start();  // the device stays gone: the loop ends at once, with nothing recorded
    ASSERT_TRUE(test::wait_until_stopped(loop, 5.0));
    loop.stop();
    EXPECT_EQ(loop.records().size(), 0u);
    EXPECT_EQ(loop.stats().ticks, 0u);
    EXPECT_TRUE(loop.stats().device_lost);
    loop.stop();  // idempotent
}

TEST(HapticLoop, RejectsBadConfiguration) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring(16);
    auto expect_error = [&](HapticLoopConfig cfg, const std::string& field) {
        try {
            HapticLoop loop(dev, surface, ring, cfg);
            ADD_FAILURE() << "no throw for " << field;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    HapticLoopConfig c;
    c.period_s = 0.0;
    expect_error(c, "period_s");
    c.period_s = 1e-9;  // would round to a zero-nanosecond deadline step
    expect_error(c, "period_s");
    c = {};
    c.ewma_alpha = 1.0;
    expect_error(c, "ewma_alpha");
    c = {};
    c.workspace_scale = -1.0;
    expect_error(c, "workspace_scale");
    c = {};
    c.device_to_world.orientation = Quat(2.0, 0.0, 0.0, 0.0);
    expect_error(c, "device_to_world.orientation");
    c = {};
    c.contact.stiffness_n_per_m = -5.0;
    expect_error(c, "stiffness_n_per_m");
}

TEST(HapticLoop, OneSecondPeriodStatistics) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    SimulatedFaults f;
    f.vanish_after_reads = 1000;
    dev.set_faults(f);
    PressScene scene;
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *scene.surface);
    SpscRing<ToolSample> ring(2048);
    HapticLoopConfig cfg;
    cfg.max_ticks = 1000;
    HapticLoop loop(dev, surface, ring, cfg);
    const auto t0 = std::chrono::steady_clock::now();
    loop.start();
    ASSERT_TRUE(test::wait_until_stopped(loop, 10.0));
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    loop.stop();
    const auto& recs = loop.records();
    ASSERT_EQ(recs.size(), 1000u);
    std::vector<double> period, compute;
    for (std::size_t i = 0; i < recs.size(); ++i) {
        if (i > 0) period.push_back(recs[i].period_us);
        compute.push_back(recs[i].compute_us);
    }
    const double med = percentile(period, 0.5), p99 = percentile(period, 0.99);
    std::printf("1 s run: %.3f s wall for 1000 ticks, period median %.1f us, p99 %.1f us, max %.1f us; "
                "compute median %.2f us, p99 %.2f us; overruns %zu\n",
                wall_s, med, p99, percentile(period, 1.0), percentile(compute, 0.5), percentile(compute, 0.99),
                loop.stats().overruns);
    EXPECT_NEAR(med, 1000.0, 50.0);
    // us: a few us of work, far below the 1 ms budget. ThreadSanitizer instruments every memory access, which makes
    // the same tick over ten times slower, so its bound is four times wider (still under half the budget).
    EXPECT_LT(percentile(compute, 0.5), kSanitized ? 400.0 : 100.0);
    // 1000 ticks on 1 ms deadlines take 1 s, plus the deadlines skipped while the shared machine stalled the thread:
    // the time of the periods over 2 ms beyond their 1 ms. What is left is the loop's own pace; a loop that lost time
    // on its own would exceed the bound however quiet the machine.
    double stalled_s = 0.0;
    for (const double p : period)
        if (p > 2000.0) stalled_s += 1e-6 * (p - 1000.0);
    EXPECT_GT(wall_s, 0.99);
    EXPECT_LT(wall_s - stalled_s, 1.5) << "stalls " << stalled_s << " s";
}

}  // namespace
}  // namespace tridex::haptics
