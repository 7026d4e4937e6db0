// The loop's engage buttons and runtime op: a mouse stylus carves only while its left button is held.
#include <gtest/gtest.h>

#include <vector>

#include "devices/mouse_device.hpp"
#include "haptics/haptic_loop.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

std::vector<ToolSample> drain(SpscRing<ToolSample>& ring) {
    std::vector<ToolSample> s;
    ToolSample x;
    while (ring.try_pop(x)) s.push_back(x);
    return s;
}

TEST(LoopEngage, SamplesCarryTheOpOnlyWhileAnEngageButtonIsHeld) {
    auto plane = test::z_plane(1e-3, 10.0f);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *plane);
    SpscRing<ToolSample> ring(1024);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg;
    cfg.contact = ContactParams{700.0, 0.0, 0.002};
    cfg.op = ToolOp::kSubtract;
    cfg.material = 3;
    cfg.engage_mask = devices::mouse_buttons::kEngage;
    cfg.workspace.mode = WorkspaceMode::kScaling;  // no stylus-button semantics in the way
    cfg.request_realtime = false;
    HapticLoop loop(dev, surface, ring, cfg);
    dev.state.pose.position = Vec3(0.015, 0.015, 0.02);
    for (int t = 0; t < 5; ++t) loop.step(t * 1e-3);  // not held
    dev.state.buttons = devices::mouse_buttons::kEngage;
    for (int t = 5; t < 10; ++t) loop.step(t * 1e-3);  // held
    loop.set_tool_op(ToolOp::kPaint, 5);
    EXPECT_EQ(loop.tool_op(), ToolOp::kPaint);
    for (int t = 10; t < 15; ++t) loop.step(t * 1e-3);
    dev.state.buttons = devices::mouse_buttons::kStylus;  // another button does not engage
    for (int t = 15; t < 20; ++t) loop.step(t * 1e-3);
    const std::vector<ToolSample> s = drain(ring);
    ASSERT_EQ(s.size(), 20u);
    for (int k = 0; k < 5; ++k) EXPECT_EQ(s[k].op, ToolOp::kNone) << k;
    for (int k = 5; k < 10; ++k) {
        EXPECT_EQ(s[k].op, ToolOp::kSubtract) << k;
        EXPECT_EQ(s[k].material, 3) << k;
    }
    for (int k = 10; k < 15; ++k) {
        EXPECT_EQ(s[k].op, ToolOp::kPaint) << k;
        EXPECT_EQ(s[k].material, 5) << k;
    }
    for (int k = 15; k < 20; ++k) EXPECT_EQ(s[k].op, ToolOp::kNone) << k;
}

TEST(LoopEngage, WithoutAnEngageMaskTheToolIsAlwaysEngaged) {
    auto plane = test::z_plane(1e-3, 10.0f);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *plane);
    SpscRing<ToolSample> ring(64);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg;
    cfg.contact = ContactParams{700.0, 0.0, 0.002};
    cfg.op = ToolOp::kUnion;
    cfg.workspace.mode = WorkspaceMode::kScaling;
    cfg.request_realtime = false;
    HapticLoop loop(dev, surface, ring, cfg);
    dev.state.pose.position = Vec3(0.015, 0.015, 0.02);
    for (int t = 0; t < 3; ++t) loop.step(t * 1e-3);
    for (const ToolSample& x : drain(ring)) EXPECT_EQ(x.op, ToolOp::kUnion);
}

}  // namespace
}  // namespace tridex::haptics
