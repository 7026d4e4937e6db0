// tests/devices/test_gamepad_device.cpp - the game-controller driver against a scripted source: rate control, dead
// zone, triggers (and a pad without them), turning, clamping, buttons, a disconnect, malformed axes, and the
// main-thread to haptic-thread hand-off under concurrent polling.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <utility>
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
    bool next_op_bound = false;
    for (const ButtonInfo& b : caps.buttons)
        next_op_bound = next_op_bound || (b.default_action == "op.next" && (1u << b.bit) == gamepad_device_buttons::kNextOp);
    EXPECT_TRUE(next_op_bound);
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

// GLFW reports an axis a controller lacks as 0.0 (glfwGetGamepadState): a pad without analog triggers reads both
// triggers half pressed, and the two cancel, so the tool does not drift up or down.
TEST(GamepadDevice, AControllerWithoutAnalogTriggersDoesNotDrift) {
    GamepadState s = at_rest();
    s.axes[gamepad_axis::kLeftTrigger] = s.axes[gamepad_axis::kRightTrigger] = 0.0f;
    Rig rig({at_rest(), s});
    EXPECT_EQ(rig.frame(100).pose.position, rig.start);
}

// Plays `states` round and round, for as many polls as a test needs (ScriptedGamepadSource repeats its last state).
// Polled from one thread at a time.
class CyclingGamepadSource : public GamepadSource {
public:
    explicit CyclingGamepadSource(std::vector<GamepadState> states) : states_(std::move(states)) {}
    bool poll(GamepadState& out) noexcept override {
        out = states_[next_++ % states_.size()];
        return true;
    }
    std::string describe() const override { return "a cycling scripted controller"; }

private:
    std::vector<GamepadState> states_;
    std::size_t next_ = 0;
};

// The window's thread polls while the haptic thread reads: every read sees one whole published state. State k has
// all four stick axes at one value v_k, A pressed when v_k > 0 and B when v_k < 0. A read that mixed two states would
// move x and z at different speeds, turn about an axis off the x = y diagonal, or report a button that does not match
// the motion. The workspace is far larger than any motion here, so clamping never tells x from z. After each publish
// the polling thread waits for a read that began after it, so every state is read (and the next one is written
// while the reader is at work).
TEST(GamepadDevice, ConcurrentPollingHandsOverWholeStates) {
    using namespace gamepad_axis;
    std::vector<GamepadState> states;
    for (const float v : {1.0f, -0.6f, 0.8f, -1.0f, 0.4f, -0.8f}) {  // beyond the dead zone; neighbours differ
        GamepadState s = at_rest();
        s.axes[kLeftX] = s.axes[kLeftY] = s.axes[kRightX] = s.axes[kRightY] = v;
        s.buttons = 1u << (v > 0.0f ? gamepad_button::kA : gamepad_button::kB);
        states.push_back(s);
    }
    DeviceProfile profile = DeviceProfile::phantom_omni();
    profile.workspace_m = Aabb{Vec3(-1e6), Vec3(1e6)};
    GamepadDevice dev(profile, Vec3(0.0), kDt, {}, std::make_unique<CyclingGamepadSource>(states));
    dev.bring_up();  // open() polls once, on this thread, before the polling thread starts
    DeviceState s;
    ASSERT_TRUE(dev.read(s));  // nothing published yet: at rest
    Quat last_q = s.pose.orientation;
    constexpr int kPolls = 2000;
    std::atomic<std::uint64_t> reads{0};
    std::atomic<bool> done{false};
    std::thread window_thread([&] {
        for (int i = 0; i < kPolls; ++i) {
            dev.poll_on_main_thread();
            // reads + 1 may have fetched its state before the publish; reads + 2 began after it.
            const std::uint64_t target = reads.load(std::memory_order_acquire) + 2;
            while (reads.load(std::memory_order_acquire) < target) std::this_thread::yield();
        }
        done.store(true, std::memory_order_release);
    });
    int torn = 0, failed_reads = 0, changes = 0;
    double last_vx = 0.0;
    while (!done.load(std::memory_order_acquire)) {
        if (!dev.read(s)) ++failed_reads;
        reads.fetch_add(1, std::memory_order_acq_rel);
        const double vx = s.velocity_m_s.x;
        const Quat turn = s.pose.orientation * glm::conjugate(last_q);  // this read's turn, about (v, v, 0)
        const bool a = (s.buttons & gamepad_device_buttons::kStylus) != 0;
        const bool b = (s.buttons & gamepad_device_buttons::kSecond) != 0;
        if (std::fabs(vx - s.velocity_m_s.z) > 1e-9 || std::fabs(turn.x - turn.y) > 1e-9 || a != (vx > 0.0) ||
            b != (vx < 0.0))
            ++torn;
        if (vx != last_vx) ++changes;
        last_vx = vx;
        last_q = s.pose.orientation;
        std::this_thread::yield();  // on one core, lets the polling thread run
    }
    window_thread.join();
    EXPECT_EQ(failed_reads, 0);
    EXPECT_EQ(torn, 0);
    EXPECT_GE(changes, kPolls - 1);  // every published state was read: neighbours differ in speed
    EXPECT_EQ(dev.link_stats().malformed_frames, 0u);
}

}  // namespace
}  // namespace tridex::devices
