// Tests of the HapticDevice lifecycle: the order open -> home -> enable, forces only while enabled, zero force
// on disable, the last-resort bound on what reaches a driver, and the status channel's faults.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"
#include "devices/haptic_device.hpp"

namespace tridex::devices {
namespace {

/// A driver that logs every hook and every force it is sent; homing can be made to fail.
class LogDevice : public HapticDevice {
public:
    explicit LogDevice(DeviceProfile p) : profile_(std::move(p)) {}
    const DeviceProfile& profile() const override { return profile_; }

    std::vector<std::string> hooks;
    std::vector<Vec3> forces, torques;
    bool fail_home = false;
    bool vanished = false;

protected:
    void on_open() override { hooks.push_back("open"); }
    void on_home() override {
        if (fail_home) throw Error("LogDevice: push the grip in to home it");
        hooks.push_back("home");
    }
    void on_enable() override { hooks.push_back("enable"); }
    void on_disable() noexcept override { hooks.push_back("disable"); }
    void on_close() noexcept override { hooks.push_back("close"); }
    bool do_read(DeviceState& out) override {
        out = DeviceState{};
        return !vanished;
    }
    void do_write(const Vec3& f, const Vec3& t) override {
        forces.push_back(f);
        torques.push_back(t);
    }

private:
    DeviceProfile profile_;
};

TEST(DeviceLifecycle, RunsTheHooksInOrderAndGatesForces) {
    LogDevice d(DeviceProfile::phantom_omni());
    EXPECT_EQ(d.state(), DeviceLifecycle::kClosed);
    d.write(Vec3(0.5, 0.0, 0.0), Vec3(0.0));  // closed: zero goes out, counted as suppressed
    ASSERT_EQ(d.forces.size(), 1u);
    EXPECT_EQ(d.forces.back(), Vec3(0.0));
    EXPECT_EQ(d.status().writes_suppressed, 1u);

    d.open();
    d.home();
    EXPECT_EQ(d.state(), DeviceLifecycle::kHomed);
    d.write(Vec3(0.5, 0.0, 0.0), Vec3(0.0));  // homed but not enabled: still zero
    EXPECT_EQ(d.forces.back(), Vec3(0.0));

    d.enable();
    EXPECT_EQ(d.state(), DeviceLifecycle::kEnabled);
    d.write(Vec3(0.5, 0.0, 0.0), Vec3(0.0));
    EXPECT_EQ(d.forces.back(), Vec3(0.5, 0.0, 0.0));

    d.disable();  // zero force is the last thing the motors get
    EXPECT_EQ(d.state(), DeviceLifecycle::kHomed);
    EXPECT_EQ(d.forces.back(), Vec3(0.0));
    d.write(Vec3(0.5, 0.0, 0.0), Vec3(0.0));
    EXPECT_EQ(d.forces.back(), Vec3(0.0));

    d.close();
    EXPECT_EQ(d.state(), DeviceLifecycle::kClosed);
    EXPECT_EQ(d.hooks, (std::vector<std::string>{"open", "home", "enable", "disable", "close"}));
    EXPECT_EQ(d.status().writes, 4u);
    EXPECT_EQ(d.status().writes_suppressed, 3u);
    EXPECT_EQ(d.status().faults, kFaultNone);
}

TEST(DeviceLifecycle, EnableBeforeHomeIsRefusedAndRaisesNotHomed) {
    LogDevice d(DeviceProfile::phantom_omni());
    d.open();
    try {
        d.enable();
        FAIL() << "enable() of an open, unhomed device must throw";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("not homed"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("PHANTOM Omni"), std::string::npos) << e.what();
    }
    EXPECT_EQ(d.state(), DeviceLifecycle::kOpen);
    EXPECT_TRUE(d.status().faults & kFaultNotHomed);
    EXPECT_EQ(fault_names(d.status().faults), "not_homed");
    d.clear_faults();
    EXPECT_EQ(d.status().faults, kFaultNone);
}

TEST(DeviceLifecycle, FailedHomingLeavesTheDeviceOpenAndClosesCleanly) {
    LogDevice d(DeviceProfile::phantom_omni());
    d.fail_home = true;
    EXPECT_THROW(d.bring_up(), Error);
    EXPECT_EQ(d.state(), DeviceLifecycle::kOpen);
    d.close();
    EXPECT_EQ(d.state(), DeviceLifecycle::kClosed);
    EXPECT_EQ(d.hooks, (std::vector<std::string>{"open", "close"}));  // never enabled: no disable hook
}

TEST(DeviceLifecycle, BringUpIsIdempotentAndCloseDisablesFirst) {
    LogDevice d(DeviceProfile::phantom_omni());
    d.bring_up();
    d.bring_up();
    EXPECT_EQ(d.hooks, (std::vector<std::string>{"open", "home", "enable"}));
    d.write(Vec3(0.1, 0.2, 0.3), Vec3(0.0));
    d.close();
    EXPECT_EQ(d.forces.back(), Vec3(0.0));
    EXPECT_EQ(d.hooks.back(), "close");
    EXPECT_EQ(d.hooks[d.hooks.size() - 2], "disable");
}

TEST(DeviceLifecycle, ForcesAreBoundedByTheProfileAndNonFiniteOnesZeroed) {
    LogDevice d(DeviceProfile::phantom_omni());  // 0.88 N, no torque
    d.bring_up();
    d.write(Vec3(0.0, 0.0, 100.0), Vec3(0.0));
    EXPECT_NEAR(glm::length(d.forces.back()), 0.88, 1e-12);
    EXPECT_NEAR(d.forces.back().z, 0.88, 1e-12);  // direction kept
    EXPECT_TRUE(d.status().faults & kFaultForceLimit);
    d.write(Vec3(0.1, 0.0, 0.0), Vec3(0.0, 0.0, 0.2));  // a 3-DOF device gets no torque
    EXPECT_EQ(d.torques.back(), Vec3(0.0));
    EXPECT_EQ(d.forces.back(), Vec3(0.1, 0.0, 0.0));
    d.write(Vec3(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0), Vec3(0.0));
    EXPECT_EQ(d.forces.back(), Vec3(0.0));
    d.write(Vec3(0.1, 0.0, 0.0), Vec3(std::numeric_limits<double>::infinity(), 0.0, 0.0));
    EXPECT_EQ(d.forces.back(), Vec3(0.0));
    EXPECT_EQ(d.torques.back(), Vec3(0.0));
    EXPECT_TRUE(d.status().faults & kFaultNonFinite);
    EXPECT_EQ(d.status().writes_clamped, 4u);
    // The force at the limit itself is not counted as cut.
    LogDevice w(quanser_wand_5dof());
    w.bring_up();
    const double fmax = w.profile().max_force_n, tmax = w.profile().max_torque_nm;
    w.write(Vec3(fmax, 0.0, 0.0), Vec3(0.0, 0.0, tmax));
    EXPECT_EQ(w.forces.back(), Vec3(fmax, 0.0, 0.0));
    EXPECT_EQ(w.torques.back(), Vec3(0.0, 0.0, tmax));
    EXPECT_EQ(w.status().writes_clamped, 0u);
}

TEST(DeviceLifecycle, AFailedReadRaisesVanished) {
    LogDevice d(DeviceProfile::phantom_omni());
    DeviceState s;
    EXPECT_TRUE(d.read(s));
    d.vanished = true;
    EXPECT_FALSE(d.read(s));
    EXPECT_TRUE(d.status().faults & kFaultVanished);
    EXPECT_EQ(fault_names(kFaultVanished | kFaultIo), "vanished, io_error");
    EXPECT_EQ(fault_names(kFaultNone), "none");
}

}  // namespace
}  // namespace tridex::devices
