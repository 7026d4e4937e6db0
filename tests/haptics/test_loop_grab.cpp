// The grab's spring in the haptic loop: engaged on a surface, the hand is pulled back toward where it gripped with
// F = -k (hip - anchor); no spring before a touch, after the button is let go, or for another op.
#include <gtest/gtest.h>

#include "devices/mouse_device.hpp"
#include "haptics/grab_spring.hpp"
#include "haptics/haptic_loop.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

TEST(GrabSpring, GripsOnTouchPullsBackAndLetsGo) {
    GrabSpring g(100.0);
    EXPECT_EQ(g.update(true, false, Vec3(0.0, 0.0, 0.05)), Vec3(0.0));  // not touching: no grip yet
    EXPECT_FALSE(g.gripping());
    EXPECT_EQ(g.update(true, true, Vec3(0.0, 0.0, 0.01)), Vec3(0.0));   // grips here
    EXPECT_TRUE(g.gripping());
    const Vec3 f = g.update(true, false, Vec3(0.01, 0.0, 0.03));        // dragged away: still held
    EXPECT_NEAR(f.x, -1.0, 1e-12);
    EXPECT_NEAR(f.z, -2.0, 1e-12);
    EXPECT_EQ(g.update(false, false, Vec3(0.01, 0.0, 0.03)), Vec3(0.0));  // released
    EXPECT_FALSE(g.gripping());
}

struct GrabRig {
    std::unique_ptr<ActiveSurface> plane = test::z_plane(1e-3, 10.0f);  // material up to z = 10 mm
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring{4096};
    test::PoseDevice dev{devices::DeviceProfile::phantom_omni()};
    HapticLoop loop;
    int t = 0;

    static HapticLoopConfig config(ToolOp op) {
        HapticLoopConfig cfg;
        cfg.contact = ContactParams{700.0, 0.0, 0.002};
        cfg.op = op;
        cfg.engage_mask = devices::mouse_buttons::kEngage;
        cfg.workspace.mode = WorkspaceMode::kScaling;
        cfg.request_realtime = false;
        cfg.grab_stiffness_n_per_m = 70.0;
        return cfg;
    }
    explicit GrabRig(ToolOp op) : loop((test::publish(surface, *plane), dev), surface, ring, config(op)) {}
    // Holds the HIP at p (world m) for n ticks; the force last written.
    Vec3 hold(const Vec3& p, int n) {
        dev.state.pose.position = p;
        for (int k = 0; k < n; ++k) loop.step(1e-3 * t++);
        ToolSample s;
        while (ring.try_pop(s)) {}
        return dev.force;
    }
};

TEST(LoopGrab, AGrabbedHandIsPulledBackTowardWhereItGripped) {
    GrabRig r(ToolOp::kGrab);
    const Vec3 touch(0.015, 0.015, 0.0115);  // the 2 mm ball 0.5 mm into the face at 10 mm
    r.dev.state.buttons = devices::mouse_buttons::kEngage;
    r.hold(touch + Vec3(0.0, 0.0, 0.001), 50);  // from above (the god-object finds the face on the way in)
    EXPECT_GT(r.hold(touch, 300).z, 0.2);       // on the face: its contact force
    const Vec3 f = r.hold(touch + Vec3(0.003, 0.0, 0.008), 600);  // dragged 8 mm up and 3 mm across
    EXPECT_NEAR(f.z, -70.0 * 0.008, 0.02);
    EXPECT_NEAR(f.x, -70.0 * 0.003, 0.02);
    EXPECT_NEAR(f.y, 0.0, 1e-6);
    // Far enough, the device's force limit holds it.
    const Vec3 far = r.hold(touch + Vec3(0.0, 0.0, 0.1), 600);
    EXPECT_LE(glm::length(far), r.dev.profile().max_force_n + 1e-9);
    EXPECT_GT(glm::length(far), 0.9 * r.dev.profile().max_force_n);
    // The button let go: no spring.
    r.dev.state.buttons = 0;
    EXPECT_LT(glm::length(r.hold(touch + Vec3(0.0, 0.0, 0.008), 600)), 1e-3);
}

TEST(LoopGrab, NoSpringBeforeATouchNorForAnotherOp) {
    {
        GrabRig r(ToolOp::kGrab);
        r.dev.state.buttons = devices::mouse_buttons::kEngage;
        EXPECT_LT(glm::length(r.hold(Vec3(0.015, 0.015, 0.03), 300)), 1e-3);  // engaged in the air: nothing held
        EXPECT_LT(glm::length(r.hold(Vec3(0.015, 0.015, 0.04), 300)), 1e-3);
    }
    GrabRig r(ToolOp::kPull);
    r.dev.state.buttons = devices::mouse_buttons::kEngage;
    r.hold(Vec3(0.015, 0.015, 0.0125), 50);
    EXPECT_GT(r.hold(Vec3(0.015, 0.015, 0.0115), 300).z, 0.2);
    EXPECT_LT(glm::length(r.hold(Vec3(0.015, 0.015, 0.03), 600)), 1e-3);  // pull: no spring
}

}  // namespace
}  // namespace tridex::haptics
