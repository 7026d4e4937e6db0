// Tests of devices/device_registry: drivers by name, clear refusals, the built-in drivers, USB detection.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"
#include "devices/registry/device_registry.hpp"
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
    mine.add(DriverInfo{"gadget", "a known gadget", true, false, {}, {{0x1234, 0x5678}}, {}, "", "", {}}, nullptr);
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
    mine.add(DriverInfo{"x", "a test driver", false, true, {}, {}, {}, "", "", {}}, nullptr);
    EXPECT_THROW(mine.add(DriverInfo{"x", "again", false, true, {}, {}, {}, "", "", {}}, nullptr), Error);
    EXPECT_THROW(mine.add(DriverInfo{"", "nameless", false, true, {}, {}, {}, "", "", {}}, nullptr), Error);
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

namespace tridex::devices {
namespace {

// Every built-in driver describes itself: the capabilities sessions read instead of its name.
TEST(DriverCapabilities, EveryBuiltinDriverDescribesItself) {
    const DeviceRegistry& r = builtin_registry();
    for (const DriverInfo& d : r.drivers()) {
        EXPECT_FALSE(to_string(d.caps.input).empty()) << d.name;
        EXPECT_GE(d.caps.dof_in, 0) << d.name;
        EXPECT_LE(d.caps.dof_in, 6) << d.name;
        EXPECT_EQ(d.caps.renders_forces, d.caps.dof_out > 0 && d.caps.input != InputKind::kRecorded &&
                                             d.caps.input != InputKind::kPointer)
            << d.name;
        EXPECT_GE(d.caps.engage_button, -1) << d.name;
        EXPECT_LT(d.caps.engage_button, 32) << d.name;
        if (!d.caps.fixed_profile.empty()) {
            EXPECT_NO_THROW((void)profile_by_name(d.caps.fixed_profile)) << d.name;
        }
        for (const DriverOption& o : d.caps.options) {
            EXPECT_LE(o.min, o.fallback) << d.name << "." << o.name;
            EXPECT_GE(o.max, o.fallback) << d.name << "." << o.name;
            EXPECT_FALSE(o.doc.empty()) << d.name << "." << o.name;
        }
        if (d.caps.input == InputKind::kTracked) {
            EXPECT_GT(d.caps.target_ids, 0) << d.name;
        }
    }
    EXPECT_EQ(r.info("simulated").caps.input, InputKind::kScripted);
    EXPECT_TRUE(r.info("simulated").caps.servable);
    EXPECT_EQ(r.info("falcon").caps.input, InputKind::kHardware);
    EXPECT_TRUE(r.info("falcon").caps.takes_firmware);
    EXPECT_TRUE(r.info("net").caps.seals_link);  // --key-file, --passphrase-env
    EXPECT_FALSE(r.info("simulated").caps.seals_link);
    EXPECT_EQ(r.info("mouse").caps.input, InputKind::kPointer);
    EXPECT_EQ(r.info("mouse").caps.engage_button, 1);
    EXPECT_EQ(r.info("spacemouse").caps.input, InputKind::kRate);
    EXPECT_EQ(r.info("spacemouse").caps.options.size(), 4u);
    EXPECT_EQ(r.info("net").caps.input, InputKind::kRemote);
    EXPECT_FALSE(r.info("net").caps.servable);
    EXPECT_EQ(r.info("flystick").caps.input, InputKind::kTracked);
    EXPECT_TRUE(person_moves_hand(r.info("flystick").caps.input));
    EXPECT_FALSE(person_moves_hand(r.info("falcon-emulator").caps.input));
    try {
        (void)r.info("nosuch", "--device");
        FAIL() << "an unknown driver was found";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("--device: unknown driver 'nosuch'; drivers: simulated", 0), 0u) << e.what();
    }
}

// `--device TEXT` is read by the registry: a profile of the simulated hand, a driver, or NAME:ADDRESS.
TEST(DriverCapabilities, ChoosingADeviceFromACommandLine) {
    const DeviceRegistry& r = builtin_registry();
    DeviceChoice c = r.choose("wand", "--device");
    EXPECT_EQ(c.driver, "simulated");
    EXPECT_EQ(c.profile, "wand");
    c = r.choose("falcon", "--device");  // the driver, not the simulated hand's falcon profile
    EXPECT_EQ(c.driver, "falcon");
    EXPECT_EQ(c.profile, "falcon");
    c = r.choose("net:10.0.0.2:7000", "--device");
    EXPECT_EQ(c.driver, "net");
    EXPECT_EQ(c.address, "10.0.0.2:7000");
    c = r.choose("flystick:5001:2", "--device");
    EXPECT_EQ(c.driver, "flystick");
    EXPECT_EQ(c.profile, "tracked");
    EXPECT_EQ(c.address, "5001:2");
    c = r.choose("mouse", "--device");
    EXPECT_EQ(c.driver, "mouse");
    EXPECT_EQ(c.profile, "");
    const auto message = [&](const std::string& text, const DeviceRegistry::DriverFilter& usable = {}) {
        try {
            (void)r.choose(text, "--device", usable);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    EXPECT_NE(message("net").find("--device: net:HOST:PORT"), std::string::npos) << message("net");
    EXPECT_NE(message("mouse:3").find("takes nothing after its name"), std::string::npos);
    EXPECT_NE(message("replay").find("unknown device 'replay'"), std::string::npos);  // a recording's, not a choice
    const auto scripted = [](const DriverInfo& d) { return !person_moves_hand(d.caps.input); };
    EXPECT_EQ(message("foo", scripted),
              "--device: unknown device 'foo'; use omni, wand, 6dof, falcon, falcon-emulator or net:HOST:PORT");
    EXPECT_NE(message("mouse", scripted).find("unknown device 'mouse'"), std::string::npos);
    const std::vector<std::string> all = r.choices();
    EXPECT_NE(std::find(all.begin(), all.end(), "flystick[:PORT[:ID]]"), all.end());
    EXPECT_EQ(join_or({"a"}), "a");
    EXPECT_EQ(join_or({"a", "b", "c"}), "a, b or c");
}

}  // namespace
}  // namespace tridex::devices
