// The loop never turns a gap in valid device data into one long carving sweep.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "haptics/haptic_loop.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

TEST(LoopCarveGap, FirstSampleAfterInvalidDataDoesNotCarve) {
    auto plane = test::z_plane(1e-3, 10.0f);
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *plane);
    SpscRing<ToolSample> ring(1024);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg;
    cfg.contact = ContactParams{700.0, 0.0, 0.002};
    cfg.op = ToolOp::kSubtract;
    cfg.max_ticks = 100;
    cfg.request_realtime = false;
    HapticLoop loop(dev, surface, ring, cfg);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    // Ticks 0-9 valid, 10-12 NaN (the stylus "jumps" 5 cm meanwhile), 13-40 valid again.
    for (int t = 0; t <= 40; ++t) {
        dev.state.pose.position = t < 10 ? Vec3(0.015, 0.015, 0.02) : Vec3(0.065, 0.015, 0.02);
        if (t >= 10 && t <= 12) dev.state.pose.position = Vec3(nan);
        loop.step(t * 1e-3);
    }
    std::vector<ToolSample> s;
    ToolSample x;
    while (ring.try_pop(x)) s.push_back(x);
    ASSERT_EQ(s.size(), 38u);  // 41 ticks, 3 invalid: nothing pushed for them
    for (int k = 0; k < 10; ++k) EXPECT_EQ(s[k].op, ToolOp::kSubtract) << k;
    // The first valid sample after the gap ends the segment across the jump: it must not carve. The
    // watchdog then holds the output for its re-arm time; carving resumes once force is allowed again.
    EXPECT_EQ(s[10].op, ToolOp::kNone);
    EXPECT_EQ(s.back().op, ToolOp::kSubtract);
    int held = 0;
    for (std::size_t k = 10; k < s.size() && s[k].op == ToolOp::kNone; ++k) ++held;
    EXPECT_GE(held, 1);
    EXPECT_LE(held, 15);  // re-arm 10 ms (+1 tick)
}

}  // namespace
}  // namespace tridex::haptics
