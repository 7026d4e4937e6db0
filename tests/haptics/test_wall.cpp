// Closed-loop test: the simulated hand pushes the device into a stiff virtual wall (0.7 N/mm, the
// Omni's stable stiffness) with the 1 kHz loop running; the wall stops it where the hand's spring
// force balances the wall's, and the energy of the device stays bounded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "devices/simulated_device.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

using devices::DeviceProfile;
using devices::ScriptedPath;
using devices::SimulatedDevice;
using devices::SimulatedFaults;
using devices::SimulatedHandParams;

// Wall: world z = 0 (lattice origin 20 cells below, 1 mm cells), solid below. The hand's target goes
// from 10 mm above the wall to 2 mm inside it in 0.2 s and holds there; 1.5 s simulated in all.
struct WallRun {
    std::vector<devices::SimulatedTraceEntry> trace;
    std::vector<TickRecord> records;
    LoopStats stats;
};

WallRun run_wall(double ewma_alpha, double damping) {
    auto s = test::make_surface(1e-3, Vec3(-0.016, -0.016, -0.020));
    test::fill_set(*s, 2, 0, 0, [](int, int) { return test::Intervals{{0.0f, 20.0f}}; });
    const DeviceProfile omni = DeviceProfile::phantom_omni();
    SimulatedDevice dev(omni, ScriptedPath({0.0, 0.2}, {Vec3(0.0, 0.0, 0.010), Vec3(0.0, 0.0, -0.002)}));
    SimulatedFaults f;
    f.vanish_after_reads = 1500;
    dev.set_faults(f);
    dev.enable_trace(1500);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *s);
    SpscRing<ToolSample> ring(2048);
    HapticLoopConfig cfg;
    cfg.contact = ContactParams{omni.max_stiffness_n_per_m, damping, 0.0};
    cfg.ewma_alpha = ewma_alpha;
    cfg.max_ticks = 1500;
    HapticLoop loop(dev, surface, ring, cfg);
    loop.start();
    EXPECT_TRUE(test::wait_until_stopped(loop, 10.0));
    loop.stop();
    return WallRun{dev.trace(), loop.records(), loop.stats()};
}

TEST(HapticWall, StiffWallStopsTheHand) {
    for (double alpha : {0.9, 0.0}) {
        const WallRun run = run_wall(alpha, 0.5);
        ASSERT_EQ(run.trace.size(), 1500u);
        const SimulatedHandParams hand;
        const double kp = 700.0, kh = hand.hand_stiffness_n_per_m, m = hand.mass_kg;
        double max_pen = 0.0, max_energy = 0.0, max_speed_late = 0.0;
        for (std::size_t i = 0; i < run.trace.size(); ++i) {
            const auto& e = run.trace[i];
            const double pen = std::max(0.0, -e.position_m.z);
            max_pen = std::max(max_pen, pen);
            // Mechanical energy of the device: kinetic + wall spring + hand spring (J).
            const double energy = 0.5 * m * glm::dot(e.velocity_m_s, e.velocity_m_s) + 0.5 * kp * pen * pen +
                                  0.5 * kh * glm::dot(e.target_m - e.position_m, e.target_m - e.position_m);
            if (e.t_s > 0.25) max_energy = std::max(max_energy, energy);
            if (e.t_s > 1.3) max_speed_late = std::max(max_speed_late, std::abs(e.velocity_m_s.z));
        }
        const auto& last = run.trace.back();
        const double pen = -last.position_m.z;
        const double hand_force = kh * (last.position_m.z - last.target_m.z);  // N, pushing into the wall
        // Statics: kh * (x - target) = kp * pen with target 2 mm deep -> pen = kh * 2 mm / (kh + kp) = 0.6 mm.
        const double pen_exact = kh * 0.002 / (kh + kp);
        const double e_static = 0.5 * kp * pen_exact * pen_exact + 0.5 * kh * (0.002 - pen_exact) * (0.002 - pen_exact);
        std::printf("alpha %.1f: penetration %.4f mm (statics %.4f, hand force / k = %.4f mm), max %.4f mm; "
                    "max energy after 0.25 s %.3g J (static %.3g J); speed after 1.3 s < %.2g m/s; overruns %zu\n",
                    alpha, pen * 1e3, pen_exact * 1e3, hand_force / kp * 1e3, max_pen * 1e3, max_energy, e_static,
                    max_speed_late, run.stats.overruns);
        EXPECT_NEAR(pen, pen_exact, 0.02e-3);           // within 20 um of the statics
        EXPECT_NEAR(pen, hand_force / kp, 0.02e-3);     // penetration ~ hand force / k
        EXPECT_LT(max_pen, 2e-3);                       // never reaches the hand's target
        EXPECT_LT(max_speed_late, 1e-3);                // settled: no sustained oscillation
        EXPECT_LT(max_energy, 1.1 * e_static);          // after the impact: no energy gained (deterministic run)
        EXPECT_TRUE(run.records.back().contact);
        EXPECT_NEAR(run.records.back().force_n.z, kp * pen, 0.01);  // N
    }
}

}  // namespace
}  // namespace tridex::haptics
