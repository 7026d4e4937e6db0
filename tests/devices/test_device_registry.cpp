// Tests of devices/device_registry: drivers by name, clear refusals, the built-in drivers, USB detection.
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"
#include "devices/device_registry.hpp"
#include "devices/replay_device.hpp"
#include "devices/simulated_device.hpp"

namespace tridex::devices {
namespace {

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(DeviceRegistry, BuiltinSimulatedDriverMakesAClosedDeviceWithTheNamedProfile) {
    DeviceSpec spec{"simulated", "wand", ""};
    DeviceInputs in;
    in.period_s = 1e-3;
    in.hand_path.emplace(std::vector<double>{0.0, 1.0}, std::vector<Vec3>{Vec3(0.0), Vec3(0.01, 0.0, 0.0)});
    auto dev = builtin_registry().create(spec, in);
    ASSERT_NE(dynamic_cast<SimulatedDevice*>(dev.get()), nullptr);
    EXPECT_EQ(dev->profile().name, quanser_wand_5dof().name);
    EXPECT_EQ(dev->state(), DeviceLifecycle::kClosed);
    dev->bring_up();
    DeviceState s;
    for (int i = 0; i < 1000; ++i) ASSERT_TRUE(dev->read(s));
    EXPECT_NEAR(s.pose.position.x, 0.01, 1e-3);  // the hand followed the given path
}

TEST(DeviceRegistry, ReplayDriverPlaysTheGivenSamples) {
    DeviceInputs in;
    in.samples.resize(3);
    for (int i = 0; i < 3; ++i) in.samples[i].t_s = 1e-3 * (i + 1);
    auto dev = builtin_registry().create(DeviceSpec{"replay", "omni", ""}, in);
    ASSERT_NE(dynamic_cast<ReplayDevice*>(dev.get()), nullptr);
    DeviceState s;
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(dev->read(s));
    EXPECT_FALSE(dev->read(s));
}

TEST(DeviceRegistry, RefusesUnknownDriversProfilesAndHardwareWithoutADriver) {
    const DeviceRegistry& r = builtin_registry();
    const std::string unknown = message_of([&] { (void)r.create(DeviceSpec{"phantom", "omni", ""}, {}); });
    EXPECT_NE(unknown.find("device.driver: unknown driver 'phantom'"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("simulated, replay"), std::string::npos) << unknown;
    const std::string profile = message_of([&] { (void)r.create(DeviceSpec{"simulated", "premium", ""}, {}); });
    EXPECT_NE(profile.find("device.profile: unknown profile 'premium'"), std::string::npos) << profile;
    // Hardware with a driver but none plugged in (a container has no Falcon; skipped when one is plugged in).
    bool plugged = false;
    for (const auto& [id, where] : usb_devices()) plugged = plugged || usb_id_string(id) == "0403:cb48";
    if (!plugged) {
        const std::string falcon = message_of([&] { (void)r.create(DeviceSpec{"falcon", "", ""}, {}); });
        EXPECT_NE(falcon.find("no Novint Falcon is plugged in"), std::string::npos) << falcon;
    }
    // Hardware without a driver in this build is refused by name.
    DeviceRegistry mine;
    mine.add(DriverInfo{"gadget", "a known gadget", true, false, {}, {{0x1234, 0x5678}}, 3, 3}, nullptr);
    const std::string gadget = message_of([&] { (void)mine.create(DeviceSpec{"gadget", "", ""}, {}); });
    EXPECT_NE(gadget.find("not available in this build"), std::string::npos) << gadget;
}

TEST(DeviceRegistry, ListsDriversAndRefusesDuplicates) {
    const std::vector<DriverInfo> drivers = builtin_registry().drivers();
    ASSERT_GE(drivers.size(), 3u);
    EXPECT_EQ(drivers[0].name, "simulated");
    EXPECT_EQ(drivers[1].name, "replay");
    bool falcon = false;
    for (const DriverInfo& d : drivers)
        if (d.name == "falcon") {
            falcon = true;
            EXPECT_TRUE(d.hardware);
            ASSERT_EQ(d.usb_ids.size(), 1u);
            EXPECT_EQ(usb_id_string(d.usb_ids[0]), "0403:cb48");
        }
    EXPECT_TRUE(falcon);

    DeviceRegistry mine;
    mine.add(DriverInfo{"x", "a test driver", false, true, {}, {}, 3, 3}, nullptr);
    EXPECT_THROW(mine.add(DriverInfo{"x", "again", false, true, {}, {}, 3, 3}, nullptr), Error);
    EXPECT_THROW(mine.add(DriverInfo{"", "nameless", false, true, {}, {}, 3, 3}, nullptr), Error);
    // A registered driver without a factory is refused, not called.
    EXPECT_THROW((void)mine.create(DeviceSpec{"x", "", ""}, {}), Error);
}

TEST(DeviceRegistry, DetectionMatchesUsbIdsAndNeverThrows) {
    std::string error;
    const auto all = usb_devices(&error);  // no USB in a container: empty with a reason, or the real list
    const std::vector<DetectedDevice> seen = builtin_registry().detect(&error);
    for (const DetectedDevice& d : seen) {
        EXPECT_EQ(d.driver, "falcon");
        EXPECT_EQ(usb_id_string(d.id), "0403:cb48");
    }
    EXPECT_LE(seen.size(), all.size());
    // Profile names round-trip through product names (what a recording stores).
    EXPECT_EQ(profile_name_of(profile_by_name("wand").name), "wand");
    EXPECT_EQ(profile_name_of("no such product"), "");
}

}  // namespace
}  // namespace tridex::devices
