// Tests of haptics/watchdog: non-finite, stale and stalled device data bring the commanded force to
// zero within 10 ms (of the simulated clocks), trips are counted once per episode, and the force comes
// back through the re-arm delay and the ramp. Unit tests drive the watchdog with hand-made clocks; loop
// tests run the haptic loop in step() mode against a simulated device pressed into a wall.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "devices/simulated_device.hpp"
#include "haptics/watchdog.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

using devices::DeviceProfile;
using devices::ScriptedPath;
using devices::SimulatedDevice;

constexpr double kT = 1e-3;

Watchdog make_watchdog() {
    const SafetyConfig c;  // stale 5 ms, stall factor 5, re-arm 10 ms
    return Watchdog(kT, c.stale_timeout_s, c.stall_factor, c.rearm_s);
}

TEST(Watchdog, NonFiniteTripsAtOnceAndRearmsAfterTheDelay) {
    Watchdog w = make_watchdog();
    for (int k = 1; k <= 10; ++k) EXPECT_TRUE(w.update(k * kT, k * kT, true).force_allowed);
    WatchdogStatus s = w.update(11 * kT, 11 * kT, false);
    EXPECT_FALSE(s.force_allowed);
    EXPECT_TRUE(s.tripped_now);
    EXPECT_EQ(s.causes, kWatchdogNonFinite);
    s = w.update(12 * kT, std::nan(""), false);  // same episode: not counted again
    EXPECT_FALSE(s.tripped_now);
    EXPECT_EQ(w.trips(), 1u);
    // Healthy again from 13 ms; the last bad device time is 11 ms: re-arm once 10 ms have passed.
    int rearm_tick = 0;
    for (int k = 13; k <= 30 && rearm_tick == 0; ++k) {
        s = w.update(k * kT, k * kT, true);
        EXPECT_EQ(s.causes, 0);
        if (s.rearmed_now) rearm_tick = k;
        else EXPECT_FALSE(s.force_allowed) << k;
    }
    EXPECT_GE(rearm_tick, 21);
    EXPECT_LE(rearm_tick, 22);  // 21 ms - 11 ms >= 10 ms up to rounding
    EXPECT_TRUE(s.force_allowed);
    EXPECT_FALSE(w.tripped());
    w.update(40 * kT, 40 * kT, false);
    EXPECT_EQ(w.trips(), 2u);  // a new episode
}

TEST(Watchdog, StaleTimeStampTripsWithinTenMilliseconds) {
    Watchdog w = make_watchdog();
    for (int k = 1; k <= 100; ++k) w.update(k * kT, k * kT, true);
    // The device time stays at 100 ms while the loop clock goes on.
    double trip_at = -1.0;
    for (int k = 101; k <= 130 && trip_at < 0.0; ++k) {
        const WatchdogStatus s = w.update(k * kT, 100 * kT, true);
        if (!s.force_allowed) {
            trip_at = k * kT;
            EXPECT_EQ(s.causes, kWatchdogStale);
        }
    }
    std::printf("stale time stamp: force cut %.1f ms after the last fresh sample\n", (trip_at - 0.1) * 1e3);
    EXPECT_GT(trip_at, 0.1 + 0.005 - 1e-9);  // not before the 5 ms timeout
    EXPECT_LE(trip_at, 0.1 + 0.010);         // within 10 ms
    EXPECT_EQ(w.trips(), 1u);
}

TEST(Watchdog, StalledTickTripsOnTheFirstTickAfterIt) {
    Watchdog w = make_watchdog();
    for (int k = 1; k <= 50; ++k) w.update(k * kT, k * kT, true);
    EXPECT_TRUE(w.update(55 * kT, 55 * kT, true).force_allowed);  // 5 ms step: = 5 periods, not above
    const WatchdogStatus s = w.update(63 * kT, 63 * kT, true);     // 8 ms step > 5 periods
    EXPECT_FALSE(s.force_allowed);
    EXPECT_EQ(s.causes, kWatchdogStalled);
    EXPECT_EQ(w.trips(), 1u);
}

// Loop scene: the simulated hand presses the stylus 2 mm into a wall at world z = 10.25 mm and holds.
struct WallScene {
    std::unique_ptr<ActiveSurface> wall = test::z_plane(1e-3, 10.25f);
    SimulatedDevice sim{DeviceProfile::phantom_omni(),
                        ScriptedPath({0.0, 0.1}, {Vec3(0.012, 0.012, 0.01525), Vec3(0.012, 0.012, 0.00825)})};
    test::ClockFaultDevice dev{sim};
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring{4096};
    HapticLoopConfig cfg;
    WallScene() {
        test::publish(surface, *wall);
        cfg.max_ticks = 1000;
    }
};

TEST(WatchdogLoop, StaleDataZeroesTheForceWithinTenMilliseconds) {
    WallScene s;
    s.dev.freeze_from = 200;  // reads 200..229 repeat the sample of read 199
    s.dev.freeze_count = 30;
    HapticLoop loop(s.dev, s.surface, s.ring, s.cfg);
    for (int k = 1; k <= 300; ++k) loop.step(k * kT);
    loop.stop();
    const auto& recs = loop.records();
    ASSERT_EQ(recs.size(), 300u);
    const double t_fresh = recs[198].t_s;  // loop time of the last fresh sample (read 199)
    EXPECT_GT(recs[198].force_n.z, 0.1);
    std::size_t first_zero = 0;
    for (std::size_t i = 199; i < recs.size() && first_zero == 0; ++i)
        if (recs[i].force_n == Vec3(0.0)) first_zero = i;
    ASSERT_GT(first_zero, 0u);
    std::printf("stale data in the loop: force zero %.1f ms after the last fresh sample\n",
                (recs[first_zero].t_s - t_fresh) * 1e3);
    EXPECT_LE(recs[first_zero].t_s - t_fresh, 0.010);
    EXPECT_EQ(recs[first_zero].watchdog, kWatchdogStale);
    for (std::size_t i = first_zero; i < 229; ++i) EXPECT_EQ(recs[i].force_n, Vec3(0.0)) << i;  // held while frozen
    EXPECT_EQ(loop.stats().watchdog_trips, 1u);
    EXPECT_GT(recs[299].force_n.z, 0.1);  // back after re-arm and ramp
}

TEST(WatchdogLoop, StalledLoopZeroesTheForceOnTheNextTick) {
    WallScene s;
    s.dev.stall_at = 200;  // the device runs 7 steps unseen: its clock jumps by 8 ms at read 200
    s.dev.stall_steps = 7;
    HapticLoop loop(s.dev, s.surface, s.ring, s.cfg);
    for (int k = 1; k <= 199; ++k) loop.step(k * kT);
    EXPECT_GT(s.sim.last_force_n().z, 0.1);
    const TickRecord r = loop.step(200 * kT + 0.007);  // the loop clock jumped with it
    EXPECT_EQ(r.watchdog, kWatchdogStalled);
    EXPECT_EQ(r.force_n, Vec3(0.0));
    EXPECT_EQ(s.sim.last_force_n(), Vec3(0.0));  // the device got zero 8 ms (device time) after the last tick
    EXPECT_NEAR(r.device.t_s - 0.199, 0.008, 1e-12);
    EXPECT_EQ(loop.stats().watchdog_trips, 1u);
    loop.stop();
}

TEST(WatchdogLoop, NonFiniteSampleZeroesTheForceAtOnce) {
    WallScene s;
    devices::SimulatedFaults f;
    f.nan_first_read = 200;
    f.nan_count = 3;
    s.sim.set_faults(f);
    HapticLoop loop(s.dev, s.surface, s.ring, s.cfg);
    for (int k = 1; k <= 199; ++k) loop.step(k * kT);
    EXPECT_GT(s.sim.last_force_n().z, 0.1);
    const TickRecord r = loop.step(200 * kT);
    EXPECT_FALSE(r.valid_sample);
    EXPECT_EQ(r.watchdog, kWatchdogNonFinite);
    EXPECT_EQ(s.sim.last_force_n(), Vec3(0.0));  // zero on the very tick (0 ms)
    EXPECT_EQ(loop.stats().watchdog_trips, 1u);
    EXPECT_EQ(loop.stats().invalid_samples, 1u);
    loop.stop();
}

}  // namespace
}  // namespace tridex::haptics
