// tests/devices/test_falcon_device.cpp - the Falcon driver over the emulator: the homing gate, LEDs, the force ramp,
// the loop closing through kinematics and motor commands, and every fault of the injector ending in zero force
// within one tick.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "core/error.hpp"
#include "devices/registry/device_registry.hpp"
#include "devices/falcon/falcon_device.hpp"
#include "devices/falcon/falcon_emulator.hpp"
#include "devices/falcon/falcon_firmware.hpp"
#include "devices/falcon/falcon_usb_transport.hpp"

namespace tridex::devices::falcon {
namespace {

struct Rig {
    FalconEmulator* emu = nullptr;
    std::unique_ptr<FalconDevice> dev;
};

Rig make(FalconEmulatorConfig c = {}, double ramp_s = 0.5) {
    auto emu = std::make_unique<FalconEmulator>(std::move(c));
    Rig r;
    r.emu = emu.get();
    r.emu->record_commands(true);
    FalconDeviceOptions o;
    o.firmware_image = emulator_firmware_image();
    o.ramp_s = ramp_s;
    r.dev = std::make_unique<FalconDevice>(std::move(emu), o);
    return r;
}

bool zero(const FalconCommand& c) { return c.motor == std::array<std::int16_t, 3>{0, 0, 0}; }

TEST(FalconDevice, NoForceBeforeHomingAndLedsShowTheState) {
    Rig r = make();
    r.dev->open();
    EXPECT_THROW(r.dev->enable(), Error);  // the lifecycle gate: not homed
    DeviceState s;
    for (int i = 0; i < 50; ++i) {
        ASSERT_TRUE(r.dev->read(s));
        r.dev->write(Vec3(0.0, 0.0, 3.0), Vec3(0.0));
    }
    for (const FalconCommand& c : r.emu->commands()) EXPECT_TRUE(zero(c));
    EXPECT_EQ(r.emu->last_command().leds, kLedRed);
    EXPECT_NE(r.emu->homing_status(), kAllHomed);
    // Homing: the emulator's scripted grip pull passes the three indexes.
    r.dev->home();
    EXPECT_EQ(r.emu->homing_status(), kAllHomed);
    EXPECT_GT(r.dev->stats().homed_at_s, 0.0);
    std::printf("falcon emulator: homed after %d exchanges (%.3f s of device time)\n", r.dev->stats().homing_exchanges,
                r.dev->stats().homed_at_s);
    ASSERT_TRUE(r.dev->read(s));
    EXPECT_EQ(r.emu->last_command().leds, kLedBlue);
    EXPECT_LT(glm::length(s.pose.position - FalconKinematics::home_m()), 1e-4);  // within an encoder count or two
    r.dev->write(Vec3(0.0, 0.0, 3.0), Vec3(0.0));                                // homed but not enabled: still zero
    ASSERT_TRUE(r.dev->read(s));
    EXPECT_TRUE(zero(r.emu->last_command()));
    r.dev->enable();
    r.dev->write(Vec3(0.0, 0.0, 3.0), Vec3(0.0));
    ASSERT_TRUE(r.dev->read(s));
    EXPECT_EQ(r.emu->last_command().leds, kLedGreen);
    EXPECT_FALSE(zero(r.emu->last_command()));
}

TEST(FalconDevice, ForceRampsInAndReachesTheGripThroughTheJacobian) {
    Rig r = make({}, 0.5);
    r.dev->bring_up();
    DeviceState s;
    const Vec3 f(1.0, -2.0, 3.0);
    double prev = 0.0;
    for (int i = 0; i < 700; ++i) {
        ASSERT_TRUE(r.dev->read(s));
        r.dev->write(f, Vec3(0.0));
        const double got = glm::length(r.emu->applied_force_n());
        if (i > 1 && i < 500) {
            EXPECT_GE(got, prev - 1e-3) << i;  // monotone ramp (the grip moves a little)
        }
        if (i == 251) {
            EXPECT_NEAR(got / glm::length(f), 0.5, 0.05);
        }
        prev = got;
    }
    // At full force the emulator's grip feels what was written, within the motor command rounding.
    EXPECT_LT(glm::length(r.emu->applied_force_n() - f), 0.02 * glm::length(f));
    r.dev->disable();
    EXPECT_TRUE(zero(r.emu->last_command()));
}

TEST(FalconDevice, FollowsTheSimulatedHandWithEncoderQuantisation) {
    FalconEmulatorConfig c;
    const Vec3 h = FalconKinematics::home_m();
    c.hand_path.emplace(std::vector<double>{0.0, 1.0}, std::vector<Vec3>{h, h + Vec3(0.02, -0.01, 0.015)});
    Rig r = make(c);
    r.dev->bring_up();
    DeviceState s;
    double worst = 0.0;
    for (int i = 0; i < 1200; ++i) {
        ASSERT_TRUE(r.dev->read(s));
        r.dev->write(Vec3(0.0), Vec3(0.0));
        worst = std::max(worst, glm::length(s.pose.position - r.emu->position_m()));
    }
    // The driver's position is the emulator's true one up to the encoders' quantisation (~64 um per count).
    EXPECT_LT(worst, 1.5e-4);
    EXPECT_LT(glm::length(s.pose.position - (h + Vec3(0.02, -0.01, 0.015))), 5e-3);
    std::printf("falcon emulator: driver vs true grip position, max %.1f um; mean exchange %.2f us, max %.2f us\n",
                worst * 1e6, r.dev->stats().exchange_mean_s * 1e6, r.dev->stats().exchange_max_s * 1e6);
}

// Runs `ticks` ticks writing a constant 2 N force.
void run(Rig& r, int ticks, bool expect_ok = true) {
    DeviceState s;
    for (int i = 0; i < ticks; ++i) {
        const bool ok = r.dev->read(s);
        if (expect_ok) {
            ASSERT_TRUE(ok) << i;
        }
        r.dev->write(Vec3(0.0, 0.0, 2.0), Vec3(0.0));
    }
}

// The fault at exchange n: the command frame the Falcon receives at exchange n + 1 (the next tick) is zero.
void expect_zero_next_tick(Rig& r, std::uint64_t fault_exchange) {
    const std::vector<FalconCommand>& log = r.emu->commands();
    // commands() holds every command frame received; exchange numbers count from the first exchange of the emulator.
    const std::uint64_t first = r.emu->exchanges() - log.size() + 1;  // exchange number of log[0]
    const std::uint64_t next = fault_exchange + 1 - first;
    ASSERT_LT(next, log.size());
    EXPECT_FALSE(zero(log[next - 1])) << "force was flowing before the fault";
    EXPECT_TRUE(zero(log[next])) << "force not zero the tick after the fault";
}

TEST(FalconDevice, EveryInjectedFaultEndsInZeroForceWithinOneTick) {
    struct Case {
        const char* name;
        void (*set)(FalconFaults&, std::uint64_t at);
    };
    const Case cases[] = {
        {"torn frame", [](FalconFaults& f, std::uint64_t at) { f.torn_frame_at = at; }},
        {"bad framing byte", [](FalconFaults& f, std::uint64_t at) { f.bad_framing_at = at; }},
        {"bad payload byte", [](FalconFaults& f, std::uint64_t at) { f.bad_payload_at = at; }},
        {"stall", [](FalconFaults& f, std::uint64_t at) { f.stall_at = at, f.stall_exchanges = 20; }},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        Rig r = make({}, 0.05);
        r.dev->bring_up();
        run(r, 100);  // force flows (ramp 50 ms)
        const std::uint64_t at = r.emu->exchanges() + 1;
        FalconFaults f;
        c.set(f, at);
        r.emu->set_faults(f);
        run(r, 40);
        expect_zero_next_tick(r, at);
        EXPECT_TRUE(r.dev->status().faults & kFaultIo);
        EXPECT_FALSE(r.dev->status().faults & kFaultVanished);
        EXPECT_GT(r.dev->stats().zeroed_ticks, 0u);
        // The link recovers and the force ramps in again.
        run(r, 100);
        EXPECT_FALSE(zero(r.emu->last_command()));
    }
}

// The velocity estimate divides by the time that really passed: after missed frames (a stall) the device time of the
// exchanges in between, after a late loop the monotonic clock's interval, never one period regardless.
TEST(FalconDevice, VelocityAfterMissedFramesAndALateLoopUsesTheTimeThatPassed) {
    FalconEmulatorConfig c;
    const Vec3 h = FalconKinematics::home_m();
    const double speed = 0.04;  // m/s along x, 40 mm over the path's second
    c.hand_path.emplace(std::vector<double>{0.0, 1.0}, std::vector<Vec3>{h, h + Vec3(speed, 0.0, 0.0)});
    auto emu = std::make_unique<FalconEmulator>(std::move(c));
    FalconEmulator* e = emu.get();
    double clock = 0.0;  // an on-time 1 kHz loop unless the test makes it late
    FalconDeviceOptions o;
    o.firmware_image = emulator_firmware_image();
    o.clock_s = [&clock] { return clock; };
    FalconDevice dev(std::move(emu), o);
    dev.bring_up();
    DeviceState s;
    auto tick = [&](double late_s = 0.0) {
        clock += o.period_s + late_s;
        const bool ok = dev.read(s);
        dev.write(Vec3(0.0), Vec3(0.0));
        return ok;
    };
    for (int i = 0; i < 300; ++i) ASSERT_TRUE(tick());
    // Averaged over 20 on-time ticks the estimate is the grip's true speed (encoder quantisation averages out).
    Vec3 true_before = e->position_m();
    double sum = 0.0;
    for (int i = 0; i < 20; ++i) {
        ASSERT_TRUE(tick());
        sum += s.velocity_m_s.x;
    }
    const double true_vx = (e->position_m().x - true_before.x) / (20 * o.period_s);
    EXPECT_GT(true_vx, 0.5 * speed);
    EXPECT_NEAR(sum / 20, true_vx, 0.25 * true_vx);

    // A stall of 20 exchanges: the first frame after it moved 21 periods' worth, over 21 periods.
    FalconFaults f;
    f.stall_at = e->exchanges() + 1;
    f.stall_exchanges = 20;
    e->set_faults(f);
    true_before = e->position_m();
    for (int i = 0; i < 20; ++i) tick();
    ASSERT_TRUE(tick());
    const double true_stall_vx = (e->position_m().x - true_before.x) / (21 * o.period_s);
    EXPECT_NEAR(s.velocity_m_s.x, true_stall_vx, 0.3 * true_stall_vx) << "divided by one period instead of 21";

    // A loop 9 ms late on one tick: the emulator's hand moved one period's worth, over 10 ms of clock.
    for (int i = 0; i < 50; ++i) ASSERT_TRUE(tick());
    const Vec3 before = s.pose.position;
    ASSERT_TRUE(tick(9e-3));
    const double expect = (s.pose.position.x - before.x) / 10e-3;
    EXPECT_NEAR(s.velocity_m_s.x, expect, 1e-9) << "the clock's interval was not used";
    EXPECT_LT(std::abs(s.velocity_m_s.x), 0.5 * true_vx);
}

TEST(FalconDevice, UnplugAndLongStallsVanishWithZeroForce) {
    {
        Rig r = make({}, 0.05);
        r.dev->bring_up();
        run(r, 100);
        const std::uint64_t at = r.emu->exchanges() + 1;
        FalconFaults f;
        f.disconnect_at = at;
        r.emu->set_faults(f);
        DeviceState s;
        EXPECT_FALSE(r.dev->read(s));
        r.dev->write(Vec3(0.0, 0.0, 2.0), Vec3(0.0));
        EXPECT_TRUE(zero(r.dev->command()));  // nothing can reach an unplugged Falcon; the driver holds zero
        const DeviceStatus st = r.dev->status();
        EXPECT_TRUE(st.faults & kFaultVanished);
        EXPECT_TRUE(st.faults & kFaultIo);
        EXPECT_FALSE(r.dev->read(s));
        r.dev->close();  // never throws
    }
    {
        Rig r = make({}, 0.05);
        r.dev->bring_up();
        run(r, 100);
        FalconFaults f;
        f.stall_at = r.emu->exchanges() + 1;
        f.stall_exchanges = 1000;
        r.emu->set_faults(f);
        DeviceState s;
        int ok = 0;
        while (r.dev->read(s) && ok < 1000) {
            r.dev->write(Vec3(0.0, 0.0, 2.0), Vec3(0.0));
            ++ok;
        }
        EXPECT_EQ(ok, 249);  // 250 ms of stall at 1 kHz: vanished
        EXPECT_TRUE(r.dev->status().faults & kFaultVanished);
    }
}

// Homing in the order libnifalcon documents (include/falcon/core/FalconFirmware.h, "Homing Mode", at f7c727a): the
// commands of open() carry no homing bit; from home() on every command carries it, through enable, the force loop,
// disable and close, since the Falcon stays homed only while the bit is set; the user is told to pull the grip out,
// then push it in. The emulator loses its homing on a command without the bit, as the firmware does.
TEST(FalconDevice, TheHomingBitIsSetInEveryCommandFromHomingOn) {
    Rig r = make({}, 0.05);
    r.dev->open();
    const std::size_t before_home = r.emu->commands().size();
    r.dev->home();
    r.dev->enable();
    DeviceState s;
    for (int i = 0; i < 300; ++i) {
        ASSERT_TRUE(r.dev->read(s));
        r.dev->write(Vec3(0.5, 0.0, 1.0), Vec3(0.0));
    }
    EXPECT_EQ(r.emu->homing_status(), kAllHomed);
    r.dev->disable();
    r.dev->close();
    const std::vector<FalconCommand>& log = r.emu->commands();
    ASSERT_GT(log.size(), before_home + 300);
    for (std::size_t i = 0; i < before_home; ++i) EXPECT_FALSE(log[i].homing_mode) << "command " << i << " of open()";
    std::size_t without = 0;
    for (std::size_t i = before_home; i < log.size(); ++i) without += log[i].homing_mode ? 0 : 1;
    EXPECT_EQ(without, 0u) << "commands after home() without the homing bit";
    EXPECT_EQ(r.emu->homing_lost(), 0);
    // The grip stayed where the hand holds it (home): its encoders kept the homed origin.
    EXPECT_LT(glm::length(s.pose.position - FalconKinematics::home_m()), 0.01);

    auto emu = std::make_unique<FalconEmulator>();
    FalconDeviceOptions o;
    o.firmware_image = emulator_firmware_image();
    o.homing_timeout_s = 0.01;  // shorter than the emulator's scripted pull takes to pass the indexes
    FalconDevice dev(std::move(emu), o);
    dev.open();
    try {
        dev.home();
        FAIL() << "homed in 10 ms";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("pull the grip all the way out toward you, then push it all the way in"), std::string::npos) << m;
    }
}

TEST(FalconDevice, RegistryMakesTheEmulatorAndRefusesAnAbsentFalcon) {
    DeviceInputs in;
    auto dev = builtin_registry().create(DeviceSpec{"falcon-emulator", "falcon", ""}, in);
    ASSERT_NE(dynamic_cast<FalconDevice*>(dev.get()), nullptr);
    EXPECT_EQ(dev->profile().name, "Novint Falcon");
    dev->bring_up();
    DeviceState s;
    EXPECT_TRUE(dev->read(s));
    bool falcon_plugged = false;
    for (const auto& [id, where] : usb_devices())
        falcon_plugged = falcon_plugged || (id.vendor == 0x0403 && id.product == 0xcb48);
    if (!falcon_plugged) {
        // The libusb transport says in one line that none is there (or that USB cannot be used at all).
        FalconUsbTransport usb;
        try {
            usb.open();
            FAIL() << "opened a Falcon that is not plugged in";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("Novint Falcon"), std::string::npos) << e.what();
        }
        std::size_t got = 1;
        EXPECT_EQ(usb.exchange({}, {}, 100, got), TransferStatus::kError);  // not open: refused, nothing read
        EXPECT_EQ(got, 0u);
        try {
            (void)builtin_registry().create(DeviceSpec{"falcon", "falcon", ""}, in);
            FAIL() << "created a Falcon that is not plugged in";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("no Novint Falcon is plugged in"), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace tridex::devices::falcon
