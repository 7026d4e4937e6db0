// Closed loop through the simulated device's wrist: a wand (two contact points) on the 5-DOF profile,
// held tilted by the virtual hand and pressed into a plane; the contact torque the loop writes turns the
// stylus back (less tilt), the wrist settles where the hand's torsion spring balances the torque sent,
// and the motion stays bounded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "devices/device_profiles.hpp"
#include "devices/rotation_vector.hpp"
#include "devices/simulated_device.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

TEST(LoopWrist, ContactTorqueTurnsTheWandBack) {
    // Solid z < 10 mm; a wand of half-length 20 mm tilted 60 degrees about x, its bottom point 1 mm into
    // the solid when the centre is at `centre` (as in test_loop_multipoint). The hand comes down from 5 mm
    // above and aims 2 mm lower still, so the hand spring presses the bottom point in.
    const double tilt = M_PI / 3.0;
    const Quat q_tilt = glm::angleAxis(tilt, Vec3(1.0, 0.0, 0.0));
    const Vec3 centre(0.015, 0.015, 0.009 + 0.02 * std::sin(tilt));
    const devices::ScriptedPath path({0.0, 0.05, 0.15},
                                     {centre + Vec3(0.0, 0.0, 0.005), centre + Vec3(0.0, 0.0, 0.005),
                                      centre - Vec3(0.0, 0.0, 0.002)});
    devices::SimulatedDevice dev(devices::quanser_wand_5dof(), path);
    dev.set_orientation_path(devices::ScriptedOrientation::hold(q_tilt));

    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *test::z_plane(1e-3, 10.0f));
    SpscRing<ToolSample> ring(1024);
    HapticLoopConfig cfg;
    cfg.contact = ContactParams{700.0, 0.0, 0.0};
    cfg.tool_points = ToolPoints::wand(0.02);
    cfg.max_ticks = 2000;
    cfg.request_realtime = false;
    HapticLoop loop(dev, surface, ring, cfg);
    ToolSample drained;
    double min_tilt = tilt, max_tilt = tilt;
    for (int t = 1; t <= 2000; ++t) {
        loop.step(t * 1e-3);
        while (ring.try_pop(drained)) {
        }
        const double a = devices::rotation_vector(dev.orientation()).x;
        min_tilt = std::min(min_tilt, a);
        max_tilt = std::max(max_tilt, a);
    }
    const Vec3 tau = dev.last_torque_nm();  // device frame = world axes here
    const Vec3 theta = devices::rotation_vector(dev.orientation());
    std::printf("wand: torque sent %.4g N*m about x, tilt %.5f rad (hand %.5f), range [%.5f, %.5f]\n", tau.x,
                theta.x, tilt, min_tilt, max_tilt);
    // The bottom point pushed up at r = (0, -10, -17.3) mm from the centre: tau_x < 0, less tilt.
    EXPECT_LT(tau.x, -1e-3);
    EXPECT_LT(theta.x, tilt - 1e-3);
    EXPECT_NEAR(tau.y, 0.0, 1e-15);  // the wand's roll is not actuated: the loop sends none
    // Settled where the hand's torsion spring balances the torque sent: k_r (tilt - theta) = -tau_x.
    const double kr = dev.hand().hand_torsion_stiffness_nm_per_rad;
    EXPECT_NEAR(kr * (tilt - theta.x), -tau.x, 1e-6);
    EXPECT_LT(glm::length(dev.angular_velocity_rad_s()), 1e-4);
    // Bounded: never tilted past the hand's target, never turned back by more than the torque limit allows.
    EXPECT_LE(max_tilt, tilt + 1e-12);
    EXPECT_GT(min_tilt, tilt - 0.230 / kr);
    loop.stop();
}

}  // namespace
}  // namespace tridex::haptics
