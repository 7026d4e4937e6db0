// Tests of devices/button_script: step lookup at and between the step times, before the first step,
// validation naming the index, and the simulated device reporting the scripted bits in device time.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "core/error.hpp"
#include "devices/button_script.hpp"
#include "devices/simulated_device.hpp"

namespace tridex::devices {
namespace {

TEST(ButtonScript, StepsHoldUntilTheNext) {
    const ButtonScript s({{0.5, 1u}, {1.0, 0u}, {1.5, 3u}, {2.0, 0x80000000u}});
    EXPECT_EQ(s.size(), 4u);
    EXPECT_EQ(s.bits_at(0.0), 0u);      // before the first step
    EXPECT_EQ(s.bits_at(0.4999), 0u);
    EXPECT_EQ(s.bits_at(0.5), 1u);      // a step takes effect at its own time
    EXPECT_EQ(s.bits_at(0.9999), 1u);
    EXPECT_EQ(s.bits_at(1.0), 0u);
    EXPECT_EQ(s.bits_at(1.7), 3u);
    EXPECT_EQ(s.bits_at(2.0), 0x80000000u);
    EXPECT_EQ(s.bits_at(1e9), 0x80000000u);  // the last step holds forever
    EXPECT_EQ(s.bits_at(std::numeric_limits<double>::quiet_NaN()), 0u);
    EXPECT_EQ(s.bits_at(-std::numeric_limits<double>::infinity()), 0u);
}

TEST(ButtonScript, EmptyScriptPressesNothing) {
    const ButtonScript s;
    EXPECT_TRUE(s.empty());
    EXPECT_EQ(s.bits_at(0.0), 0u);
    EXPECT_EQ(s.bits_at(10.0), 0u);
}

void expect_error(const std::vector<ButtonStep>& steps, const std::string& needle) {
    try {
        ButtonScript s(steps);
        FAIL() << "no error, expected one naming " << needle;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

TEST(ButtonScript, RefusesBadTimesNamingTheIndex) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    expect_error({{0.0, 1u}, {nan, 0u}}, "steps[1].t_s");
    expect_error({{inf, 1u}}, "steps[0].t_s");
    expect_error({{0.0, 1u}, {1.0, 0u}, {1.0, 1u}}, "steps[2].t_s");  // equal times do not increase
    expect_error({{0.0, 1u}, {1.0, 0u}, {0.5, 1u}}, "does not increase");
    EXPECT_NO_THROW(ButtonScript({{-1.0, 0u}, {0.0, 0xffffffffu}}));  // negative times and any bits are fine
}

TEST(SimulatedDeviceButtons, ScriptDecidesTheBitsInDeviceTime) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    dev.set_buttons(4u);  // overridden by the script
    dev.set_button_script(ButtonScript({{0.0105, 1u}, {0.0205, 0u}}));
    DeviceState s;
    for (int i = 1; i <= 30; ++i) {
        ASSERT_TRUE(dev.read(s));
        // Each read reports the bits at its own device time t = i ms.
        const std::uint32_t expect = (i >= 11 && i <= 20) ? 1u : 0u;
        EXPECT_EQ(s.buttons, expect) << "read " << i << " t = " << s.t_s;
    }
}

TEST(SimulatedDeviceButtons, WithoutAScriptSetButtonsDecides) {
    SimulatedDevice dev(DeviceProfile::phantom_omni(), ScriptedPath::hold(Vec3(0.0)));
    dev.set_buttons(5u);
    DeviceState s;
    ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.buttons, 5u);
    dev.set_button_script(ButtonScript({{0.0, 2u}}));
    ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.buttons, 2u);
    dev.clear_button_script();
    ASSERT_TRUE(dev.read(s));
    EXPECT_EQ(s.buttons, 5u);
}

}  // namespace
}  // namespace tridex::devices
