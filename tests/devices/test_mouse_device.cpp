// The mouse device: a speed-limited glide toward the hand the app sets, buttons, forces gated and ignored.
#include <gtest/gtest.h>

#include <limits>
#include <thread>

#include "core/error.hpp"
#include "devices/registry/device_registry.hpp"
#include "devices/mouse_device.hpp"

namespace tridex::devices {
namespace {

TEST(MouseDevice, RestsAtStartThenGlidesToTargetAtMaxSpeed) {
    MouseDevice dev(DeviceProfile::phantom_omni(), Vec3(0.01, 0.0, 0.0), 1e-3, MouseFollowParams{0.5});
    dev.bring_up();
    DeviceState s;
    ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.pose.position, Vec3(0.01, 0.0, 0.0));  // no target yet: at rest
    EXPECT_DOUBLE_EQ(s.t_s, 1e-3);
    dev.set_hand(Vec3(0.01, 0.01, 0.0), mouse_buttons::kEngage);
    ASSERT_TRUE(dev.read(s));
    EXPECT_NEAR(s.pose.position.y, 0.5e-3, 1e-12);  // 0.5 m/s for 1 ms
    EXPECT_NEAR(s.velocity_m_s.y, 0.5, 1e-9);
    EXPECT_EQ(s.buttons, mouse_buttons::kEngage);
    for (int i = 0; i < 30; ++i) ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.pose.position, Vec3(0.01, 0.01, 0.0));  // 10 mm in 20 ms, then held there
    EXPECT_EQ(s.velocity_m_s, Vec3(0.0));
    EXPECT_DOUBLE_EQ(s.t_s, 32e-3);
    EXPECT_EQ(s.pose.orientation, Quat(1.0, 0.0, 0.0, 0.0));
}

TEST(MouseDevice, NonFiniteTargetKeepsThePreviousOne) {
    MouseDevice dev(DeviceProfile::phantom_omni(), Vec3(0.0), 1e-3);
    dev.set_hand(Vec3(0.0, 0.0, 1e-4), 0);
    dev.set_hand(Vec3(std::numeric_limits<double>::quiet_NaN()), mouse_buttons::kStylus);
    DeviceState s;
    ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.pose.position, Vec3(0.0, 0.0, 1e-4));
    EXPECT_EQ(s.buttons, mouse_buttons::kStylus);
    EXPECT_EQ(dev.rejected_targets(), 1u);
}

TEST(MouseDevice, ForcesAreGatedAndBoundedThenIgnored) {
    MouseDevice dev(DeviceProfile::phantom_omni(), Vec3(0.0), 1e-3);
    dev.write(Vec3(1.0, 0.0, 0.0), Vec3(0.0));  // closed: sent as zero
    EXPECT_EQ(dev.last_force_n(), Vec3(0.0));
    EXPECT_EQ(dev.status().writes_suppressed, 1u);
    dev.bring_up();
    dev.write(Vec3(100.0, 0.0, 0.0), Vec3(0.0));
    EXPECT_NEAR(glm::length(dev.last_force_n()), DeviceProfile::phantom_omni().max_force_n, 1e-12);
    EXPECT_EQ(dev.status().writes_clamped, 1u);
    dev.write(Vec3(std::numeric_limits<double>::infinity()), Vec3(0.0));
    EXPECT_EQ(dev.last_force_n(), Vec3(0.0));
    DeviceState s;
    ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.pose.position, Vec3(0.0));  // a force moves nothing
}

TEST(MouseDevice, BadParametersAreRefused) {
    EXPECT_THROW(MouseDevice(DeviceProfile::phantom_omni(), Vec3(0.0), 0.0), Error);
    EXPECT_THROW(MouseDevice(DeviceProfile::phantom_omni(), Vec3(std::numeric_limits<double>::quiet_NaN()), 1e-3), Error);
    EXPECT_THROW(MouseDevice(DeviceProfile::phantom_omni(), Vec3(0.0), 1e-3, MouseFollowParams{0.0}), Error);
}

TEST(MouseDevice, RegistryMakesOneNamedAfterItsProfile) {
    DeviceInputs in;
    in.hand_path.emplace(ScriptedPath::hold(Vec3(0.0, 0.02, 0.0)));
    auto dev = builtin_registry().create(DeviceSpec{"mouse", "omni", ""}, in);
    ASSERT_NE(dynamic_cast<MouseDevice*>(dev.get()), nullptr);
    EXPECT_EQ(dev->profile().name, "mouse (PHANTOM Omni limits)");
    DeviceState s;
    ASSERT_TRUE(dev->read(s));
    EXPECT_EQ(s.pose.position, Vec3(0.0, 0.02, 0.0));
}

// The render thread sets hands while the loop thread reads: every read sees a target the writer set (the
// writer only sets points on the x axis, with the button bit telling which half), never a torn value.
TEST(MouseDevice, HandOffFromAnotherThreadIsLatestValueAndWhole) {
    MouseDevice dev(DeviceProfile::phantom_omni(), Vec3(0.0), 1e-3, MouseFollowParams{1e6});
    dev.bring_up();
    std::thread writer([&] {
        for (int i = 1; i <= 20000; ++i)
            dev.set_hand(Vec3(1e-6 * i, 0.0, 0.0), i > 10000 ? mouse_buttons::kEngage : 0u);
    });
    DeviceState s;
    double prev = 0.0;
    for (int i = 0; i < 20000; ++i) {
        ASSERT_TRUE(dev.read(s));
        EXPECT_EQ(s.pose.position.y, 0.0);
        EXPECT_GE(s.pose.position.x, prev);  // the latest value only moves forward
        if (s.buttons == mouse_buttons::kEngage) {
            EXPECT_GT(s.pose.position.x, 1e-2 - 1e-12);
        }
        prev = s.pose.position.x;
    }
    writer.join();
    ASSERT_TRUE(dev.read(s));
    EXPECT_DOUBLE_EQ(s.pose.position.x, 0.02);
}

}  // namespace
}  // namespace tridex::devices
