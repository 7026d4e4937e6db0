// app/input/glfw_device_host.hpp - the window system's input offered to drivers, through GLFW.
#pragma once

#include "devices/device_host.hpp"

namespace tridex::app {

/// The session's DeviceHost over GLFW 3.3: game controllers through its gamepad API (glfwJoystickIsGamepad,
/// glfwGetGamepadState, with the controller database GLFW carries). GLFW's joystick functions must be called on the
/// main thread (GLFW 3.3 reference, "Thread safety"), which is where sessions open devices and run their frame
/// loop. start_gamepads() initialises GLFW when no window has (glfwInit does nothing once GLFW runs); GLFW is never
/// terminated here, since a window may own it. One per process.
devices::DeviceHost& glfw_device_host();

}  // namespace tridex::app
