// app/input/glfw_device_host.cpp - game controllers through GLFW's gamepad API.
#include "app/input/glfw_device_host.hpp"

#include <GLFW/glfw3.h>

#include <string>

#include "core/error.hpp"

namespace tridex::app {
namespace {

class GlfwDeviceHost : public devices::DeviceHost {
public:
    void start_gamepads() override {
        if (glfwInit() == GLFW_TRUE) return;
        const char* why = nullptr;
        glfwGetError(&why);
        throw Error(std::string("gamepad: GLFW could not start (") + (why ? why : "unknown reason") +
                    "); game controllers are read through the desktop session: run where DISPLAY is set");
    }

    bool read_gamepad(int joystick, devices::GamepadState& out, std::string* name) noexcept override {
        int jid = joystick;
        if (jid < 0) {
            for (int j = GLFW_JOYSTICK_1; jid < 0 && j <= GLFW_JOYSTICK_LAST; ++j)
                if (glfwJoystickIsGamepad(j) == GLFW_TRUE) jid = j;
            if (jid < 0) return false;
        }
        if (jid > GLFW_JOYSTICK_LAST) return false;
        GLFWgamepadstate s{};
        if (glfwGetGamepadState(jid, &s) != GLFW_TRUE) return false;
        out.connected = true;
        for (int i = 0; i <= GLFW_GAMEPAD_AXIS_LAST; ++i) out.axes[static_cast<std::size_t>(i)] = s.axes[i];
        out.buttons = 0;
        for (int b = 0; b <= GLFW_GAMEPAD_BUTTON_LAST; ++b)
            if (s.buttons[b] == GLFW_PRESS) out.buttons |= 1u << b;
        if (name) {
            const char* n = glfwGetGamepadName(jid);
            *name = std::string(n ? n : "a gamepad") + " (joystick " + std::to_string(jid + 1) + ")";
        }
        return true;
    }
};

}  // namespace

devices::DeviceHost& glfw_device_host() {
    static GlfwDeviceHost host;
    return host;
}

}  // namespace tridex::app
