// tests/devices/test_falcon_firmware.cpp - the firmware load against the emulator: the handshake, the echo check,
// failed echoes and silent loaders with retries, an unplug during the load, and the one line without a file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>

#include "core/error.hpp"
#include "devices/falcon/falcon_device.hpp"
#include "devices/falcon/falcon_emulator.hpp"
#include "devices/falcon/falcon_firmware.hpp"

namespace tridex::devices::falcon {
namespace {

TEST(FalconFirmware, LoadsOnTheFirstAttemptAndTheFirmwareThenAnswers) {
    FalconEmulator emu;
    emu.open();
    EXPECT_FALSE(firmware_running(emu));
    const std::vector<std::uint8_t> image = emulator_firmware_image();
    ASSERT_EQ(image.size(), 1024u);
    const FirmwareLoadReport r = load_firmware(emu, image);
    EXPECT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.attempts, 1);
    EXPECT_EQ(emu.firmware_bytes(), image.size());
    EXPECT_EQ(emu.firmware_loads(), 1);
    EXPECT_TRUE(firmware_running(emu));
}

TEST(FalconFirmware, RetriesAfterAFailedEchoAndASilentLoader) {
    FalconEmulatorConfig c;
    c.faults.corrupt_echo_loads = 1;  // the first load's echo has one flipped byte
    FalconEmulator emu(c);
    emu.open();
    FirmwareLoadReport r = load_firmware(emu, emulator_firmware_image());
    EXPECT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.attempts, 2);
    EXPECT_EQ(r.echo_mismatches, 1);
    EXPECT_EQ(emu.firmware_loads(), 1);

    // A loader that ignores 150 handshake queries: the first attempt (100 tries) fails, the second answers.
    FalconEmulatorConfig s;
    s.faults.silent_handshakes = 150;
    FalconEmulator quiet(s);
    quiet.open();
    r = load_firmware(quiet, emulator_firmware_image());
    EXPECT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.attempts, 2);
    EXPECT_EQ(r.handshake_failures, 1);

    // Every echo bad: all attempts fail, and the report says why.
    FalconEmulatorConfig bad;
    bad.faults.corrupt_echo_loads = 10;
    FalconEmulator broken(bad);
    broken.open();
    FirmwareLoadOptions o;
    o.attempts = 3;
    r = load_firmware(broken, emulator_firmware_image(), o);
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.attempts, 3);
    EXPECT_EQ(r.echo_mismatches, 3);
    EXPECT_NE(r.error.find("echo mismatch at byte 100"), std::string::npos) << r.error;
    EXPECT_FALSE(broken.firmware_loaded());
}

TEST(FalconFirmware, AnUnpluggedFalconEndsTheLoadAtOnce) {
    FalconEmulator emu;
    emu.open();
    emu.unplug();
    const FirmwareLoadReport r = load_firmware(emu, emulator_firmware_image());
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.attempts, 1);
    EXPECT_NE(r.error.find("unplugged"), std::string::npos);
}

TEST(FalconFirmware, DriverSaysWhatItNeedsWithoutAFile) {
    FalconDevice dev(std::make_unique<FalconEmulator>(), FalconDeviceOptions{});
    try {
        dev.open();
        FAIL() << "opened without firmware";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("--falcon-firmware FILE"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;  // one line
    }
    EXPECT_EQ(dev.state(), DeviceLifecycle::kClosed);
    FalconDeviceOptions missing;
    missing.firmware_path = "/no/such/falcon_firmware.bin";
    FalconDevice dev2(std::make_unique<FalconEmulator>(), missing);
    EXPECT_THROW(dev2.open(), Error);

    // A user's file (here: any bytes; the emulator accepts them) is loaded through the same path.
    const std::filesystem::path f = std::filesystem::path(testing::TempDir()) / "falcon_fw_test.bin";
    {
        std::ofstream out(f, std::ios::binary);
        const auto img = emulator_firmware_image();
        out.write(reinterpret_cast<const char*>(img.data()), 300);
    }
    FalconDeviceOptions given;
    given.firmware_path = f.string();
    auto emu = std::make_unique<FalconEmulator>();
    FalconEmulator* e = emu.get();
    FalconDevice dev3(std::move(emu), given);
    dev3.open();
    EXPECT_EQ(e->firmware_bytes(), 300u);
    EXPECT_EQ(dev3.stats().firmware_attempts, 1);
    // Already running firmware (a warm Falcon) is not loaded again.
    FalconEmulatorConfig warm;
    warm.firmware_loaded = true;
    FalconDevice dev4(std::make_unique<FalconEmulator>(warm), FalconDeviceOptions{});
    EXPECT_NO_THROW(dev4.open());
    EXPECT_EQ(dev4.stats().firmware_attempts, 0);
}

}  // namespace
}  // namespace tridex::devices::falcon
