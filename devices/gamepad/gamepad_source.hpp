// devices/gamepad/gamepad_source.hpp - where a game controller's state comes from: the session's host (its window
// system: GLFW's gamepad API), or a script.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "devices/device_host.hpp"

namespace tridex::devices {

/// Axis indices of GamepadState::axes, in GLFW's gamepad layout (GLFW 3.3, "Gamepad input": GLFW_GAMEPAD_AXIS_*).
namespace gamepad_axis {
inline constexpr int kLeftX = 0;         ///< left stick, -1 left .. +1 right
inline constexpr int kLeftY = 1;         ///< left stick, -1 up .. +1 down (the SDL game controller convention)
inline constexpr int kRightX = 2;        ///< right stick, -1 left .. +1 right
inline constexpr int kRightY = 3;        ///< right stick, -1 up .. +1 down
inline constexpr int kLeftTrigger = 4;   ///< left trigger, -1 released .. +1 fully pressed
inline constexpr int kRightTrigger = 5;  ///< right trigger, -1 released .. +1 fully pressed
}  // namespace gamepad_axis

/// Button bits of GamepadState::buttons, in GLFW's gamepad order (GLFW_GAMEPAD_BUTTON_*): bit i = button i.
namespace gamepad_button {
inline constexpr int kA = 0;
inline constexpr int kB = 1;
inline constexpr int kX = 2;
inline constexpr int kY = 3;
inline constexpr int kLeftBumper = 4;
inline constexpr int kRightBumper = 5;
inline constexpr int kBack = 6;
inline constexpr int kStart = 7;
inline constexpr int kGuide = 8;
inline constexpr int kLeftThumb = 9;
inline constexpr int kRightThumb = 10;
inline constexpr int kDpadUp = 11;
inline constexpr int kDpadRight = 12;
inline constexpr int kDpadDown = 13;
inline constexpr int kDpadLeft = 14;
inline constexpr int kCount = 15;
}  // namespace gamepad_button

/// Where a GamepadDevice reads its controller. poll() is called only on the thread that owns the window (GLFW's
/// main thread), once per displayed frame, through HapticDevice::poll_on_main_thread().
class GamepadSource {
public:
    virtual ~GamepadSource() = default;
    /// Reads the controller now: true with `out` filled (connected = true) when one is present; false when none is
    /// (unplugged, never found). Must not block; never throws.
    virtual bool poll(GamepadState& out) noexcept = 0;
    /// What it reads, for messages ("Xbox Controller (joystick 1)", "a scripted controller").
    virtual std::string describe() const = 0;
};

/// A controller read through the session's host (DeviceHost::read_gamepad: GLFW's gamepad API in tridex's sessions).
class HostGamepadSource : public GamepadSource {
public:
    /// `joystick`: slot 0..15, or -1 for the first controller with a gamepad mapping. Starts the host's gamepad
    /// service; throws tridex::Error "gamepad: ..." for a slot out of range or a host that cannot read controllers.
    HostGamepadSource(DeviceHost& host, int joystick) : host_(host), joystick_(joystick) {
        if (joystick < -1 || joystick > 15)
            throw Error("gamepad: joystick " + std::to_string(joystick + 1) + " is not a slot 1..16 (0 = the first found)");
        host_.start_gamepads();
    }
    bool poll(GamepadState& out) noexcept override { return host_.read_gamepad(joystick_, out, &name_); }
    std::string describe() const override {
        if (!name_.empty()) return name_;
        return joystick_ < 0 ? std::string("the first gamepad found") : "joystick " + std::to_string(joystick_ + 1);
    }

private:
    DeviceHost& host_;
    int joystick_;
    std::string name_;
};

/// A test double and a script: plays a list of states, one per poll(), then keeps returning the last (or, after
/// disconnect_after polls, reports none). Not thread-safe: poll it from one thread, as GLFW's source.
class ScriptedGamepadSource : public GamepadSource {
public:
    /// `states`: what successive polls return (the last repeats); `disconnect_after`: polls after which the
    /// controller is gone (0 = never).
    explicit ScriptedGamepadSource(std::vector<GamepadState> states, std::size_t disconnect_after = 0)
        : states_(std::move(states)), disconnect_after_(disconnect_after) {}
    bool poll(GamepadState& out) noexcept override {
        ++polls_;
        if (states_.empty() || (disconnect_after_ > 0 && polls_ > disconnect_after_)) return false;
        out = states_[std::min(next_, states_.size() - 1)];
        out.connected = true;
        ++next_;
        return true;
    }
    std::string describe() const override { return "a scripted controller"; }
    std::size_t polls() const { return polls_; }  ///< poll() calls so far

private:
    std::vector<GamepadState> states_;
    std::size_t disconnect_after_ = 0;
    std::size_t next_ = 0;
    std::size_t polls_ = 0;
};

}  // namespace tridex::devices
