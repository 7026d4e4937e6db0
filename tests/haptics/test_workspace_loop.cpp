// Workspace techniques inside the haptic loop (step() mode, a device whose samples the test sets):
// modelling paused while the button is held (ToolSamples with ToolOp::kNone), no carving segment across a
// workspace jump, the box published for the renderer, no force kick when a jump lands the tool inside
// material, and no force while declutched.
#include <gtest/gtest.h>

#include <vector>

#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

using devices::DeviceProfile;

constexpr double kT = 1e-3;

std::vector<ToolSample> drain(SpscRing<ToolSample>& ring) {
    std::vector<ToolSample> out;
    ToolSample s;
    while (ring.try_pop(s)) out.push_back(s);
    return out;
}

TEST(WorkspaceLoop, PengMovingPausesModellingAndNoCarvingSegmentSpansTheJump) {
    test::PoseDevice dev(DeviceProfile::phantom_omni());
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring(256);
    HapticLoopConfig cfg;
    cfg.device_to_world.position = Vec3(0.5, 0.5, 0.5);
    cfg.op = ToolOp::kSubtract;
    cfg.max_ticks = 100;
    HapticLoop loop(dev, surface, ring, cfg);
    const Vec3 p0(0.03, 0.0, 0.0);
    const Vec3 t0 = Vec3(0.5, 0.5, 0.5) + p0;  // tool before the jump
    dev.state.pose.position = p0;
    const std::uint32_t buttons[12] = {0, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0, 0};
    for (int k = 0; k < 12; ++k) {
        dev.state.buttons = buttons[k];
        const TickRecord r = loop.step((k + 1) * kT);
        EXPECT_EQ(r.modelling_paused, k >= 5 && k <= 8) << k;  // press .. release tick inclusive
        if (k == 6) {
            const LoopView& v = loop.latest_view();
            EXPECT_TRUE(v.modelling_paused);
            EXPECT_NEAR(glm::length(v.box.position - t0), 0.0, 1e-12);  // the box is centred on the tool
        }
    }
    const LoopView& v = loop.latest_view();
    EXPECT_EQ(v.tick, 12u);
    EXPECT_NEAR(glm::length(v.box.position - t0), 0.0, 1e-12);  // the workspace now sits where the box was
    EXPECT_NEAR(glm::length(v.box_half_extents_m - 0.5 * DeviceProfile::phantom_omni().workspace_m.size()), 0.0,
                1e-15);
    EXPECT_EQ(v.bubble_radius_m, 0.0);

    const std::vector<ToolSample> s = drain(ring);
    ASSERT_EQ(s.size(), 12u);
    for (int k = 0; k < 12; ++k) {
        EXPECT_EQ(s[k].op, (k >= 5 && k <= 8) ? ToolOp::kNone : ToolOp::kSubtract) << k;
        const Vec3 expect = k < 8 ? t0 : t0 + p0;  // the release tick (k = 8) is already in the new workspace
        EXPECT_NEAR(glm::length(s[k].position - expect), 0.0, 1e-12) << k;
    }
    // The sculpt thread carves the segment that ends at a carving sample: none of them spans the jump.
    for (int k = 1; k < 12; ++k) {
        if (s[k].op != ToolOp::kNone) {
            EXPECT_LT(glm::length(s[k].position - s[k - 1].position), 1e-12) << k;
        }
    }
    loop.stop();
}

// A jump that lands the tool 2.75 mm inside material resets the contact: no force kick (the god-object
// treats a HIP that starts inside material as free until it leaves).
TEST(WorkspaceLoop, JumpIntoMaterialGivesNoKick) {
    test::PoseDevice dev(DeviceProfile::phantom_omni());
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *test::z_plane(1e-3, 10.25f));  // solid below world z = 10.25 mm
    SpscRing<ToolSample> ring(256);
    HapticLoopConfig cfg;
    cfg.device_to_world.position = Vec3(0.012, 0.012, 0.0175);
    cfg.ewma_alpha = 0.0;
    cfg.safety.ramp_s = 0.0;
    cfg.max_ticks = 100;
    HapticLoop loop(dev, surface, ring, cfg);
    dev.state.pose.position = Vec3(0.0, 0.0, -0.005);  // world z = 12.5 mm: 2.25 mm above the surface
    int k = 0;
    for (; k < 5; ++k) EXPECT_FALSE(loop.step((k + 1) * kT).contact);
    dev.state.buttons = 1;
    loop.step((++k) * kT);
    dev.state.buttons = 0;
    const TickRecord jump = loop.step((++k) * kT);  // the workspace moves 5 mm down: tool at z = 7.5 mm
    EXPECT_NEAR(jump.hip_m.z, 0.0075, 1e-12);
    for (int i = 0; i < 20; ++i) {
        const TickRecord r = loop.step((++k) * kT);
        EXPECT_FALSE(r.contact);
        EXPECT_EQ(r.force_n, Vec3(0.0));
    }
    loop.stop();
}

TEST(WorkspaceLoop, DeclutchedToolFeelsNoForceAndStaysFrozen) {
    test::PoseDevice dev(DeviceProfile::phantom_omni());
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *test::z_plane(1e-3, 10.25f));
    SpscRing<ToolSample> ring(256);
    HapticLoopConfig cfg;
    cfg.workspace.mode = WorkspaceMode::kClutching;
    cfg.device_to_world.position = Vec3(0.012, 0.012, 0.0175);
    cfg.ewma_alpha = 0.0;
    cfg.safety.ramp_s = 0.0;
    cfg.max_ticks = 200;
    HapticLoop loop(dev, surface, ring, cfg);
    // Approach from 2.25 mm above to 0.75 mm inside in 0.1 mm steps: contact, F = 700 N/m * 0.75 mm.
    int k = 0;
    for (int i = 0; i <= 30; ++i) {
        dev.state.pose.position = Vec3(0.0, 0.0, -0.005 - 1e-4 * i);
        loop.step((++k) * kT);
    }
    TickRecord r = loop.step((++k) * kT);
    EXPECT_TRUE(r.contact);
    EXPECT_NEAR(r.force_n.z, 700.0 * 0.75e-3, 1e-9);
    dev.state.buttons = 1;  // declutch
    r = loop.step((++k) * kT);
    EXPECT_FALSE(r.contact);
    EXPECT_EQ(r.force_n, Vec3(0.0));
    const Vec3 frozen = r.hip_m;
    for (int i = 0; i < 20; ++i) {  // the stylus moves further in; the tool does not
        dev.state.pose.position.z -= 1e-4;
        r = loop.step((++k) * kT);
        EXPECT_EQ(r.hip_m, frozen);
        EXPECT_EQ(r.force_n, Vec3(0.0));
        EXPECT_TRUE(r.modelling_paused);
    }
    loop.stop();
}

}  // namespace
}  // namespace tridex::haptics
