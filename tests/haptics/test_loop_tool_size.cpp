// The loop's tool size at run time (the desk's [ and ] keys): set_tool changes the samples' tool and the contact
// points together; a replay's schedule applies op, symmetry and tool changes at recorded device times; the samples
// carry the symmetry set any time.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/error.hpp"
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

HapticLoopConfig ball_config(double radius_m) {
    HapticLoopConfig cfg;
    cfg.contact = ContactParams{700.0, 0.0, radius_m};
    cfg.op = ToolOp::kSubtract;
    cfg.material = 2;
    cfg.workspace.mode = WorkspaceMode::kScaling;  // no stylus-button semantics in the way
    cfg.request_realtime = false;
    return cfg;
}

TEST(LoopToolSize, SetToolResizesTheSweptToolAndTheContactTogether) {
    auto plane = test::z_plane(1e-3, 10.0f);  // material below z = 10 mm
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *plane);
    SpscRing<ToolSample> ring(1024);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoop loop(dev, surface, ring, ball_config(0.002));
    dev.state.pose.position = Vec3(0.015, 0.015, 0.02);
    const TickRecord first = loop.step(0.0);
    // Put the tool centre 3 mm above the plane, over the snapshot's window: free with a 2 mm ball, touching
    // with a 4 mm one.
    dev.state.pose.position += Vec3(0.015, 0.015, 0.013) - first.hip_m;
    for (int t = 1; t < 5; ++t) {
        const TickRecord r = loop.step(t * 1e-3);
        ASSERT_NEAR(glm::length(r.hip_m - Vec3(0.015, 0.015, 0.013)), 0.0, 1e-9);
        EXPECT_FALSE(r.contact) << t;
        EXPECT_EQ(r.tool.radius_m, 0.002);
    }
    ToolShape bigger;
    bigger.radius_m = 0.004;
    EXPECT_TRUE(loop.set_tool(bigger));
    // Lifted to 6 mm above the plane, then lowered 0.5 mm per tick to 3 mm: the larger ball meets the plane.
    dev.state.pose.position.z += 0.003;
    bool touched = false;
    for (int t = 5; t < 15; ++t) {
        if (t > 5 && t <= 11) dev.state.pose.position.z -= 0.0005;
        const TickRecord r = loop.step(t * 1e-3);
        EXPECT_EQ(r.tool.radius_m, 0.004) << t;
        EXPECT_EQ(r.op, ToolOp::kSubtract);
        EXPECT_EQ(r.material, 2);
        touched = touched || r.contact;
    }
    EXPECT_TRUE(touched) << "the 4 mm ball 3 mm above the plane did not touch it";
    EXPECT_EQ(loop.latest_view().tool.radius_m, 0.004);
    const std::vector<ToolSample> s = drain(ring);
    ASSERT_EQ(s.size(), 15u);
    for (int k = 0; k < 5; ++k) EXPECT_EQ(s[k].tool.radius_m, 0.002) << k;
    for (int k = 5; k < 15; ++k) EXPECT_EQ(s[k].tool.radius_m, 0.004) << k;

    // Refused: another kind, a bad size; nothing changes.
    ToolShape flat;
    flat.kind = ToolKind::kFlatEnd;
    flat.radius_m = 0.003;
    flat.length_m = 0.01;
    EXPECT_FALSE(loop.set_tool(flat));
    ToolShape bad;
    bad.radius_m = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(loop.set_tool(bad));
    bad.radius_m = -0.001;
    EXPECT_FALSE(loop.set_tool(bad));
    EXPECT_EQ(loop.step(15e-3).tool.radius_m, 0.004);
}

TEST(LoopToolSize, ScheduledChangesApplyAtTheirDeviceTime) {
    auto plane = test::z_plane(1e-3, 10.0f);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *plane);
    SpscRing<ToolSample> ring(1024);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());  // device time = reads * 1 ms
    HapticLoopConfig cfg = ball_config(0.002);
    ToolChange c;
    c.device_t_s = 0.004;
    c.op = ToolOp::kPaint;
    c.material = 5;
    c.tool.radius_m = 0.003;
    c.symmetry = Symmetry{Symmetry::kMirrorX | Symmetry::kMirrorZ, 0, 0};
    cfg.tool_schedule.push_back(c);
    c.device_t_s = 0.007;
    c.symmetry = Symmetry{0, 1, 6};
    c.op = ToolOp::kUnion;
    c.tool.radius_m = 0.0;  // the tool stays
    cfg.tool_schedule.push_back(c);
    HapticLoop loop(dev, surface, ring, cfg);
    dev.state.pose.position = Vec3(0.015, 0.015, 0.04);
    for (int t = 0; t < 9; ++t) loop.step(t * 1e-3);
    const std::vector<ToolSample> s = drain(ring);
    ASSERT_EQ(s.size(), 9u);
    for (std::size_t k = 0; k < s.size(); ++k) {
        SCOPED_TRACE(k);
        const double t = s[k].t_s;
        EXPECT_EQ(s[k].op, t < 0.0035 ? ToolOp::kSubtract : t < 0.0065 ? ToolOp::kPaint : ToolOp::kUnion);
        EXPECT_EQ(s[k].material, t < 0.0035 ? 2 : 5);
        EXPECT_EQ(s[k].tool.radius_m, t < 0.0035 ? 0.002 : 0.003);
        EXPECT_EQ(to_string(s[k].symmetry), t < 0.0035 ? "off" : t < 0.0065 ? "xz" : "radial:6:y");
    }
}

TEST(LoopToolSize, SamplesCarryTheSymmetrySetAnyTime) {
    auto plane = test::z_plane(1e-3, 10.0f);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *plane);
    SpscRing<ToolSample> ring(1024);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg = ball_config(0.002);
    cfg.symmetry = Symmetry{Symmetry::kMirrorY, 0, 0};
    HapticLoop loop(dev, surface, ring, cfg);
    dev.state.pose.position = Vec3(0.015, 0.015, 0.04);
    EXPECT_EQ(to_string(loop.symmetry()), "y");
    loop.step(0.0);
    loop.set_symmetry(Symmetry{0, 2, 32});
    const TickRecord r = loop.step(1e-3);
    EXPECT_EQ(to_string(r.symmetry), "radial:32:z");
    EXPECT_THROW(loop.set_symmetry(Symmetry{1, 0, 3}), Error);  // mirrors and radial copies together
    const std::vector<ToolSample> s = drain(ring);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(to_string(s[0].symmetry), "y");
    EXPECT_EQ(to_string(s[1].symmetry), "radial:32:z");
}

}  // namespace
}  // namespace tridex::haptics
