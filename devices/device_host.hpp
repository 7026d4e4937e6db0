// devices/device_host.hpp - the window-system input a session offers its drivers (a game controller's state).
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace tridex::devices {

/// One reading of a game controller in GLFW's gamepad layout (GLFW 3.3, "Gamepad input", GLFWgamepadstate): six
/// axes in [-1, 1] and fifteen buttons.
struct GamepadState {
    bool connected = false;       ///< a controller with a gamepad mapping was read
    std::array<float, 6> axes{};  ///< left x, left y, right x, right y, left trigger, right trigger (devices/gamepad)
    std::uint32_t buttons = 0;    ///< bit i = gamepad button i pressed (A, B, X, Y, bumpers, ...; devices/gamepad)
};

/// What the session's host (its window system) offers the drivers whose input it owns: drivers ask for what they
/// need through DeviceInputs::host, so that devices/ never sees the window system. Services run on the host's main
/// thread only (the thread that calls HapticDevice::poll_on_main_thread and opens devices).
class DeviceHost {
public:
    virtual ~DeviceHost() = default;
    /// Makes game controllers readable; throws tridex::Error saying why not (no desktop session).
    virtual void start_gamepads() = 0;
    /// Reads game controller slot `joystick` (0..15), or with -1 the first slot that holds a controller with a gamepad
    /// mapping, now. True with `out` filled (connected = true) and `name` (may be null) set to the controller's name;
    /// false when there is none. Never throws, never blocks.
    virtual bool read_gamepad(int joystick, GamepadState& out, std::string* name) noexcept = 0;
};

}  // namespace tridex::devices
