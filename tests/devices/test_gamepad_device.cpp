// tests/devices/test_gamepad_device.cpp - the game-controller driver against a scripted source: rate control, dead
// zone, triggers, turning, clamping, buttons, a disconnect, malformed axes, and the main-thread to haptic-thread
// hand-off under concurrent polling.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"
#include "devices/registry/device_registry.hpp"
#include "devices/gamepad/gamepad_device.hpp"
#include "devices/gamepad/gamepad_source.hpp"

namespace tridex::devices {
namespace {

constexpr double kDt = 1e-3;

GamepadState at_rest() {
    GamepadState s;
    s.axes = {0.0f, 0.0f, 0.0f, 0.0f, -1.0f, -1.0f};  // sticks centred, triggers released
    return s;
}

GamepadState with_axis(int axis, float value) {
    GamepadState s = at_rest();
    s.axes[static_cast<std::size_t>(axis)] = value;
    return s;
}

// An opened, homed and enabled gamepad device on the omni profile, its tip at the workspace centre.
struct Rig {
    std::unique_ptr<GamepadDevice> dev;
    ScriptedGamepadSource* source = nullptr;
    Vec3 start{0.0};

    explicit Rig(std::vector<GamepadState> states, GamepadParams p = {}, std::size_t disconnect_after = 0) {
        auto src = std::make_unique<ScriptedGamepadSource>(std::move(states), disconnect_after);
        source = src.get();
        const DeviceProfile profile = DeviceProfile::phantom_omni();
        start = profile.workspace_m.centre();
        dev = std::make_unique<GamepadDevice>(profile, start, kDt, p, std::move(src));
        dev->open();
        dev->home();
        dev->enable();
    }
    // One displayed frame: the source polled on "the main thread", then `reads` haptic ticks.
    DeviceState frame(int reads) {
        dev->poll_on_main_thread();
        DeviceState s;
        for (int i = 0; i < reads; ++i) EXPECT_TRUE(dev->read(s));
        return s;
    }
};

TEST(GamepadDevice, FullDeflectionMovesAtTheMaximumSpeed) {
    Rig rig({at_rest(), with_axis(gamepad_axis::kLeftX, 1.0f)});  // the probe at open, then full right
    const DeviceState s = rig.frame(100);
    EXPECT_NEAR(s.pose.position.x - rig.start.x, 0.1 * 100 * kDt, 1e-9);
    EXPECT_NEAR(s.pose.position.y, rig.start.y, 1e-12);
    EXPECT_NEAR(s.pose.position.z, rig.start.z, 1e-12);
    EXPECT_NEAR(s.velocity_m_s.x, 0.1, 1e-9);
}

TEST(GamepadDevice, PushingTheLeftStickAwayMovesIntoTheScene) {
    Rig rig({at_rest(), with_axis(gamepad_axis::kLeftY, -1.0f)});  // up on the stick = -1
    const DeviceState s = rig.frame(50);
    EXPECT_NEAR(s.pose.position.z - rig.start.z, -0.1 * 50 * kDt, 1e-9);  // -z: away from the viewer
}

TEST(GamepadDevice, TheDeadZoneHoldsStillAndTheOutputIsContinuousAtItsEdge) {
    GamepadParams p;
    p.dead_zone = 0.2;
    Rig inside({at_rest(), with_axis(gamepad_axis::kLeftX, 0.19f)}, p);
    EXPECT_EQ(inside.frame(100).pose.position, inside.start);
    // Just past the edge the speed is just above zero, not a jump to 20 % of the maximum.
    Rig edge({at_rest(), with_axis(gamepad_axis::kLeftX, 0.21f)}, p);
    const double moved = edge.frame(100).pose.position.x - edge.start.x;
    EXPECT_GT(moved, 0.0);
    EXPECT_NEAR(moved, 0.1 * 100 * kDt * (0.21 - 0.2) / 0.8, 1e-6);
    // Half-way between the edge and full deflection: half the speed.
    Rig half({at_rest(), with_axis(gamepad_axis::kLeftX, -0.6f)}, p);
    EXPECT_NEAR(half.frame(100).pose.position.x - half.start.x, -0.5 * 0.1 * 100 * kDt, 1e-6);
}

TEST(GamepadDevice, TriggersMoveUpAndDown) {
    Rig up({at_rest(), with_axis(gamepad_axis::kRightTrigger, 1.0f)});
    EXPECT_NEAR(up.frame(100).pose.position.y - up.start.y, 0.1 * 100 * kDt, 1e-9);
    Rig down({at_rest(), with_axis(gamepad_axis::kLeftTrigger, 1.0f)});
    EXPECT_NEAR(down.frame(100).pose.position.y - down.start.y, -0.1 * 100 * kDt, 1e-9);
    // Released triggers (-1) are at rest: no drift.
    Rig rest({at_rest(), at_rest()});
    EXPECT_EQ(rest.frame(100).pose.position, rest.start);
}

TEST(GamepadDevice, TheRightStickAndBumpersTurnTheStylus) {
    Rig yaw({at_rest(), with_axis(gamepad_axis::kRightX, 1.0f)});
    const Quat q = yaw.frame(100).pose.orientation;
    const double angle = 2.0 * std::acos(std::min(1.0, std::fabs(static_cast<double>(q.w))));
    EXPECT_NEAR(angle, 1.5 * 100 * kDt, 1e-6);
    const Vec3 axis = glm::normalize(Vec3(q.x, q.y, q.z)) * (q.w < 0 ? -1.0 : 1.0);
    EXPECT_NEAR(axis.y, 1.0, 1e-6);  // about +y
    GamepadState roll = at_rest();
    roll.buttons = 1u << gamepad_button::kLeftBumper;
    Rig r({at_rest(), roll});
    const Quat qr = r.frame(10).pose.orientation;
    EXPECT_NEAR(glm::normalize(Vec3(qr.x, qr.y, qr.z)).z * (qr.w < 0 ? -1.0 : 1.0), -1.0, 1e-6);  // about -z
}

TEST(GamepadDevice, TheTipStaysInTheWorkspace) {
    Rig rig({at_rest(), with_axis(gamepad_axis::kLeftX, 1.0f)});
    const DeviceState s = rig.frame(5000);  // 0.5 m at full speed: far past the Omni's 0.16 m width
    EXPECT_DOUBLE_EQ(s.pose.position.x, DeviceProfile::phantom_omni().workspace_m.hi.x);
    EXPECT_EQ(s.velocity_m_s.x, 0.0);
}

TEST(GamepadDevice, ButtonsMapToTheStylusAndTheOperationButton) {
    GamepadState a = at_rest();
    a.buttons = 1u << gamepad_button::kA;
    GamepadState y = at_rest();
    y.buttons = (1u << gamepad_button::kY) | (1u << gamepad_button::kB);
    GamepadState x = at_rest();
    x.buttons = 1u << gamepad_button::kX;  // not mapped
    Rig rig({at_rest(), a, y, x});
    EXPECT_EQ(rig.frame(1).buttons, gamepad_device_buttons::kStylus);
    EXPECT_EQ(rig.frame(1).buttons, gamepad_device_buttons::kNextOp | gamepad_device_buttons::kSecond);
    EXPECT_EQ(rig.frame(1).buttons, 0u);
    // The registry says which bit switches the operation and which is the stylus button.
    const DriverCapabilities& caps = builtin_registry().info("gamepad").caps;
    EXPECT_EQ(1u << caps.next_op_button, gamepad_device_buttons::kNextOp);
    EXPECT_EQ(1u << caps.workspace_button, gamepad_device_buttons::kStylus);
    EXPECT_EQ(caps.input, InputKind::kRate);
    EXPECT_TRUE(person_moves_hand(caps.input));
}

TEST(GamepadDevice, ADisconnectHoldsThePoseReleasesTheButtonsAndRaisesVanished) {
    GamepadState push = with_axis(gamepad_axis::kLeftX, 1.0f);
    push.buttons = 1u << gamepad_button::kA;
    Rig rig({at_rest(), push}, {}, 2);  // the probe and one frame, then gone
    const DeviceState before = rig.frame(10);
    EXPECT_EQ(before.buttons, gamepad_device_buttons::kStylus);
    EXPECT_EQ(rig.dev->status().faults & kFaultVanished, 0u);
    const DeviceState after = rig.frame(10);
    EXPECT_EQ(after.pose.position, before.pose.position);
    EXPECT_EQ(after.buttons, 0u);
    EXPECT_NE(rig.dev->status().faults & kFaultVanished, 0u);
    EXPECT_EQ(rig.dev->link_stats().missed_frames, 10u);
}

TEST(GamepadDevice, NonFiniteOrOutOfRangeAxesReadAsRestAndAreCounted) {
    GamepadState bad = at_rest();
    bad.axes[gamepad_axis::kLeftX] = std::numeric_limits<float>::quiet_NaN();
    bad.axes[gamepad_axis::kLeftY] = 7.0f;
    bad.axes[gamepad_axis::kRightTrigger] = std::numeric_limits<float>::infinity();
    Rig rig({at_rest(), bad});
    const DeviceState s = rig.frame(100);
    EXPECT_EQ(s.pose.position, rig.start);
    EXPECT_TRUE(is_finite(s.pose.position));
    EXPECT_EQ(rig.dev->link_stats().malformed_frames, 3u);
}

TEST(GamepadDevice, BadParametersAndNoControllerAreRefusedByName) {
    const DeviceProfile omni = DeviceProfile::phantom_omni();
    const auto message = [&](GamepadParams p, double dt, bool source) {
        try {
            GamepadDevice d(omni, Vec3(0.0), dt, p,
                            source ? std::make_unique<ScriptedGamepadSource>(std::vector<GamepadState>{at_rest()}) : nullptr);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    GamepadParams p;
    p.max_speed_m_s = 0.0;
    EXPECT_NE(message(p, kDt, true).find("max_speed_m_s"), std::string::npos);
    p = {};
    p.max_rate_rad_s = std::nan("");
    EXPECT_NE(message(p, kDt, true).find("max_rate_rad_s"), std::string::npos);
    p = {};
    p.dead_zone = 0.95;
    EXPECT_NE(message(p, kDt, true).find("dead_zone"), std::string::npos);
    EXPECT_NE(message({}, 0.0, true).find("dt_s"), std::string::npos);
    EXPECT_NE(message({}, kDt, false).find("source"), std::string::npos);
    EXPECT_EQ(message({}, kDt, true), "(accepted)");
    // No controller at open: one line saying so.
    GamepadDevice none(omni, Vec3(0.0), kDt, {}, std::make_unique<ScriptedGamepadSource>(std::vector<GamepadState>{}));
    try {
        none.open();
        FAIL() << "opened without a controller";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no game controller found"), std::string::npos) << e.what();
    }
}

// The window's thread polls while the haptic thread reads: every read sees one whole published state. Each state
// has all four stick axes equal; a torn read would mix two of them (checked through the motion it produces).
TEST(GamepadDevice, ConcurrentPollingHandsOverWholeStates) {
    std::vector<GamepadState> states{at_rest()};
    for (int i = 0; i < 400; ++i) {
        const float v = (i % 2 == 0) ? 1.0f : -1.0f;
        GamepadState s = at_rest();
        s.axes[gamepad_axis::kLeftX] = s.axes[gamepad_axis::kLeftY] = v;
        states.push_back(s);
    }
    Rig rig(states);
    std::atomic<bool> done{false};
    std::thread main_thread([&] {
        for (int i = 0; i < 400; ++i) rig.dev->poll_on_main_thread();
        done = true;
    });
    int torn = 0, reads = 0;
    DeviceState s;
    while (!done.load() || reads < 10) {
        ASSERT_TRUE(rig.dev->read(s));
        ++reads;
        // x and z move together (both +v or both -v): a read mixing two states would move them apart.
        if (std::fabs(s.velocity_m_s.x - s.velocity_m_s.z) > 1e-9) ++torn;
    }
    main_thread.join();
    EXPECT_EQ(torn, 0);
    EXPECT_GT(reads, 0);
}

}  // namespace
}  // namespace tridex::devices
