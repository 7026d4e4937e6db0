// The scaling technique divides the world's contact force by the gain: in WorkspaceMode::kScaling with
// gain s, the same world penetration sends 1/s of the gain-1 force to the device, and the device shows the
// world stiffness as authored (the same device displacement gives the same device force for any s).
// Other modes keep the world force (force_scale() = 1). Either way the stiffness the device feels is cut to its
// profile's max_stiffness_n_per_m.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "devices/device_profiles.hpp"
#include "haptics/safety_limits.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

constexpr double kH = 1e-3;        // cell, m
constexpr double kPlaneZ = 0.01025;  // world plane z = 10.25 mm, solid below
constexpr double kRadius = 2e-3;   // ball tool, m

// The force written to the device (device frame = world axes here) on the last of 200 step() ticks, the
// stylus ending at device position p; the mapping puts device point p_ref at world ref_world
// (offset = ref_world - s * p_ref).
Vec3 last_tick_force(WorkspaceMode mode, double s, const Vec3& p, const Vec3& p_ref, const Vec3& ref_world,
                     double stiffness_n_per_m = ContactParams{}.stiffness_n_per_m, bool* capped = nullptr) {
    test::PoseDevice dev(devices::generic_6dof());
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *test::z_plane(kH, static_cast<float>(kPlaneZ / kH)));
    SpscRing<ToolSample> ring(1024);
    HapticLoopConfig cfg;
    cfg.workspace.mode = mode;
    cfg.workspace_scale = s;
    cfg.device_to_world.position = ref_world - s * p_ref;
    cfg.contact.tool_radius_m = kRadius;
    cfg.contact.stiffness_n_per_m = stiffness_n_per_m;
    cfg.contact.damping_n_s_per_m = 0.0;
    cfg.ewma_alpha = 0.0;
    cfg.request_realtime = false;
    HapticLoop loop(dev, surface, ring, cfg);
    // Approach from 3 mm (device) above in 60 ticks, so the god-object meets the surface from outside, then
    // hold well past the 50 ms ramp-in.
    for (int k = 1; k <= 200; ++k) {
        const double above = k < 60 ? 0.003 * (1.0 - k / 60.0) : 0.0;
        dev.state.pose.position = p + Vec3(0.0, 0.0, above);
        loop.step(k * 1e-3);
    }
    const Vec3 f = dev.force;
    if (capped) *capped = loop.stiffness_capped();
    loop.stop();
    return f;
}

const Vec3 kTouch(0.012, 0.012, kPlaneZ + kRadius);  // world HIP where the ball just touches the plane

TEST(ScalingForce, SameWorldPenetrationGivesHalfTheForceAtGainTwo) {
    const double d = 1e-3;  // world penetration, m
    // The stylus sits at device p; the world HIP is kTouch - d z for both gains.
    const Vec3 p(0.01, -0.02, 0.03);
    const Vec3 hip = kTouch - Vec3(0.0, 0.0, d);
    const Vec3 f1 = last_tick_force(WorkspaceMode::kScaling, 1.0, p, p, hip);
    const Vec3 f2 = last_tick_force(WorkspaceMode::kScaling, 2.0, p, p, hip);
    const double k = ContactParams{}.stiffness_n_per_m;
    EXPECT_NEAR(f1.z, k * d, 1e-9);  // 0.7 N up
    EXPECT_NEAR(f2.z, 0.5 * f1.z, 1e-12);
    EXPECT_NEAR(glm::length(Vec3(f2.x, f2.y, 0.0)), 0.0, 1e-12);
}

TEST(ScalingForce, DeviceShowsTheWorldStiffnessWhateverTheGain) {
    // The stylus pressed 0.5 mm (device) past the touching point: the world penetration is s * 0.5 mm, the
    // device force k * 0.5 mm for every s.
    const Vec3 p_touch(0.0, 0.0, 0.0), dp(0.0, 0.0, -0.0005);
    const double k = ContactParams{}.stiffness_n_per_m;
    for (double s : {1.0, 2.0, 3.0}) {
        const Vec3 f = last_tick_force(WorkspaceMode::kScaling, s, p_touch + dp, p_touch, kTouch);
        EXPECT_NEAR(f.z, k * 0.0005, 1e-9) << "gain " << s;
    }
}

TEST(ScalingForce, OtherModesKeepTheWorldForce) {
    const Vec3 p_touch(0.0, 0.0, 0.0), dp(0.0, 0.0, -0.0005);
    const double k = 400.0;  // at gain 2 the device feels 800 N/m, within the generic 6-DOF's 1000 N/m
    // Peng's moving workspace at gain 2 (no button): the world force 2 k dp reaches the device unchanged.
    const Vec3 f = last_tick_force(WorkspaceMode::kPengMoving, 2.0, p_touch + dp, p_touch, kTouch, k);
    EXPECT_NEAR(f.z, 2.0 * k * 0.0005, 1e-9);
    const Pose id;
    EXPECT_EQ(WorkspaceMapper(WorkspaceConfig{}, id, 2.0, Aabb{}).force_scale(), 1.0);
    WorkspaceConfig sc;
    sc.mode = WorkspaceMode::kScaling;
    EXPECT_EQ(WorkspaceMapper(sc, id, 4.0, Aabb{}).force_scale(), 0.25);
}

TEST(ScalingForce, TheDeviceNeverFeelsMoreThanItsProfilesStiffness) {
    // Gain 2 in Peng's moving workspace doubles the stiffness the device feels: 700 N/m in the world would be
    // 1400 N/m at a device rated 1000 N/m, so the loop renders 500 N/m in the world (1000 at the device).
    const Vec3 p_touch(0.0, 0.0, 0.0), dp(0.0, 0.0, -0.0005);
    bool capped = false;
    const Vec3 f = last_tick_force(WorkspaceMode::kPengMoving, 2.0, p_touch + dp, p_touch, kTouch, 700.0, &capped);
    EXPECT_TRUE(capped);
    EXPECT_NEAR(f.z, devices::generic_6dof().max_stiffness_n_per_m * 0.0005, 1e-9);
    // In kScaling the device feels the world stiffness: 700 N/m is within the limit at any gain.
    (void)last_tick_force(WorkspaceMode::kScaling, 3.0, p_touch + dp, p_touch, kTouch, 700.0, &capped);
    EXPECT_FALSE(capped);
    // 1500 N/m is not, whatever the gain.
    const Vec3 fs = last_tick_force(WorkspaceMode::kScaling, 3.0, p_touch + dp, p_touch, kTouch, 1500.0, &capped);
    EXPECT_TRUE(capped);
    EXPECT_NEAR(fs.z, 1000.0 * 0.0005, 1e-9);
}

TEST(ScalingForce, MaterialStiffnessIsCappedToo) {
    ContactParams c;
    c.stiffness_n_per_m = 300.0;
    auto table = std::make_shared<MaterialTable>(Material{300.0, 0.5, 0.0, 0.0});
    table->set(7, Material{2000.0, 0.5, 0.0, 0.0});
    c.materials = table;
    EXPECT_TRUE(cap_contact_stiffness(c, 1000.0));
    EXPECT_EQ(c.stiffness_n_per_m, 300.0);
    EXPECT_EQ((*c.materials)[7].stiffness_n_per_m, 1000.0);
    EXPECT_EQ((*c.materials)[0].stiffness_n_per_m, 300.0);
    EXPECT_EQ((*table)[7].stiffness_n_per_m, 2000.0) << "the caller's table is not modified";
    EXPECT_FALSE(cap_contact_stiffness(c, 1000.0));
    // A profile without a limit caps nothing.
    devices::DeviceProfile none;
    EXPECT_TRUE(std::isinf(world_stiffness_cap_n_per_m(none, 2.0)));
    EXPECT_EQ(world_stiffness_cap_n_per_m(devices::generic_6dof(), 2.0), 500.0);
}

}  // namespace
}  // namespace tridex::haptics
