// The loop with a multi-point tool: torque about the tool centre reaches a 5-DOF device within its
// limits, a 3-DOF device gets none, and the per-point record carries Table 3's fields.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "devices/device_profiles.hpp"
#include "haptics/haptic_loop.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

// Solid z < 10 mm (Z rays, 1 mm cells, window over x, y in [0, 31] mm). A wand of half-length 20 mm
// tilted 60 degrees about x: its bottom point 1 mm into the solid, its top point free.
struct WandOnPlane {
    std::unique_ptr<ActiveSurface> plane = test::z_plane(1e-3, 10.0f);
    Quat tilt = rotation_from_axis_angle(Vec3(1.0, 0.0, 0.0), M_PI / 3.0);
    Vec3 centre = Vec3(0.015, 0.015, 0.009 + 0.02 * std::sin(M_PI / 3.0));
    Vec3 force_sent{0.0}, torque_sent{0.0};  // the device's last write while the loop ran (device frame = world)

    TickRecord run(const devices::DeviceProfile& profile, test::PoseDevice& dev) {
        TripleBuffer<ActiveSurface> surface;
        SpscRing<ToolSample> ring(1024);
        test::publish(surface, *plane);
        HapticLoopConfig cfg;
        cfg.contact = ContactParams{700.0, 0.0, 0.0};
        cfg.tool_points = ToolPoints::wand(0.02);
        cfg.max_ticks = 1000;
        cfg.request_realtime = false;
        dev.state.pose.orientation = tilt;
        HapticLoop loop(dev, surface, ring, cfg);
        TickRecord rec;
        ToolSample drained;
        // Approach from 5 mm above (a god-object only touches what the tool crossed into), press in
        // over 100 ticks, then hold past the force ramp and the EWMA filter's settling.
        for (int t = 0; t < 500; ++t) {
            const double lift = 0.005 * std::clamp(1.0 - (t - 50) / 100.0, 0.0, 1.0);
            dev.state.pose.position = centre + Vec3(0.0, 0.0, lift);
            rec = loop.step(t * 1e-3);
            while (ring.try_pop(drained)) {
            }
        }
        (void)profile;
        force_sent = dev.force;  // before the loop's end writes zero force
        torque_sent = dev.torque;
        return rec;
    }
};

TEST(LoopMultiPoint, WandTorqueReachesAFiveDofDeviceAndNotAnOmni) {
    WandOnPlane scene;
    // F = k * 1 mm = 0.7 N up at the bottom point; r = bottom - centre = (0, -10, -17.32) mm;
    // tau = r x F = (-0.01 * 0.7, 0, 0) N*m.
    const devices::DeviceProfile wand = devices::quanser_wand_5dof();
    test::PoseDevice wand_dev(wand);
    const TickRecord w = scene.run(wand, wand_dev);
    EXPECT_NEAR(w.force_n.z, 0.7, 1e-3);
    EXPECT_NEAR(w.torque_nm.x, -0.007, 1e-5);
    EXPECT_NEAR(scene.torque_sent.x, -0.007, 1e-5);  // about device x: actuated on the wand (230 N*mm limit)
    EXPECT_NEAR(scene.force_sent.z, 0.7, 1e-3);
    EXPECT_EQ(wand_dev.force, Vec3(0.0));  // and zero force once the loop ended

    const devices::DeviceProfile omni = devices::DeviceProfile::phantom_omni();
    test::PoseDevice omni_dev(omni);
    const TickRecord o = scene.run(omni, omni_dev);
    EXPECT_NEAR(o.force_n.z, 0.7, 1e-3);
    EXPECT_EQ(scene.torque_sent, Vec3(0.0));  // 3-DOF output: no torque at all
    EXPECT_NEAR(scene.force_sent.z, 0.7, 1e-3);
}

TEST(LoopMultiPoint, RecordCarriesTopAndBottomPoints) {
    WandOnPlane scene;
    test::PoseDevice dev(devices::quanser_wand_5dof());
    const TickRecord r = scene.run(devices::quanser_wand_5dof(), dev);
    EXPECT_EQ(r.points_in_contact, 1);
    // Point 0 is the top (+y in the tool frame): free. Point 1, the bottom: 1 mm deep on the Z rays.
    EXPECT_EQ(r.points[0].collision_id, -1);
    EXPECT_EQ(r.points[0].depth_m, 0.0);
    EXPECT_EQ(r.points[1].collision_id, 2);
    EXPECT_NEAR(r.points[1].depth_m, 0.001, 1e-6);
    EXPECT_NEAR(r.points[1].proxy_m.z, 0.010, 1e-6);  // the god-object rests on the surface
    EXPECT_NEAR(glm::length(r.points[1].world_m - r.points[0].world_m), 0.04, 1e-9);
}

}  // namespace
}  // namespace tridex::haptics
