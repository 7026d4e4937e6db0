// renderer/window/window_glfw.hpp - a GLFW window or fullscreen on a chosen monitor, with a Vulkan surface and input.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "gpu/swapchain.hpp"
#include "renderer/window/window_input.hpp"

namespace tridex::renderer {

/// One connected monitor as GLFW reports it.
struct MonitorInfo {
    int index = 0;          ///< position in list_monitors() (0 = primary)
    std::string name;       ///< human-readable name, e.g. "DP-1" or "Dell U2412M"
    int x_px = 0, y_px = 0; ///< position of its top-left corner on the virtual desktop, screen coordinates
    int width_px = 0, height_px = 0;  ///< current video mode, pixels
    int refresh_hz = 0;     ///< current video mode's refresh rate, Hz (0 when unknown)
    int width_mm = 0, height_mm = 0;  ///< physical size the monitor reports, mm (0 when unknown)
};

/// Bounds GLFW's process-wide lifetime. GLFW is initialised on first use (list_monitors,
/// required_instance_extensions, window_context_options, Window::create) and then stays initialised, one X
/// connection for the whole process: terminating it while a Vulkan instance that queried presentation
/// support still exists lets a new connection reuse the old one's address, and Mesa's WSI (which caches
/// per-connection state by that address) then sends requests the X server refuses, killing the process.
/// A WindowSystemScope ends that lifetime: when the last live scope is destroyed, GLFW is terminated (at
/// once if no Window is open, else when the last Window closes), and the next use initialises it again,
/// on the then-current DISPLAY. Create one before the Context(s) and windows of a session (so it is
/// destroyed after them), e.g. when the X server will go away (a test's Xvfb) or DISPLAY will change.
/// Without any scope GLFW stays initialised until process exit. Main thread only. Never throws.
class WindowSystemScope {
public:
    WindowSystemScope();
    ~WindowSystemScope();
    WindowSystemScope(const WindowSystemScope&) = delete;
    WindowSystemScope& operator=(const WindowSystemScope&) = delete;
};

/// True while GLFW is initialised (see WindowSystemScope).
bool window_system_initialised();
/// How many times GLFW has been initialised in this process (for tests: 1 per WindowSystemScope lifetime).
std::uint64_t window_system_initialisations();

/// The connected monitors, primary first. Initialises GLFW if needed. Throws tridex::Error when GLFW
/// cannot initialise (no display: DISPLAY / WAYLAND_DISPLAY unset or unreachable).
std::vector<MonitorInfo> list_monitors();

/// The Vulkan instance extensions windows need (glfwGetRequiredInstanceExtensions, e.g. VK_KHR_surface and
/// VK_KHR_xcb_surface). Throws tridex::Error when GLFW cannot initialise or finds no Vulkan loader / no
/// window-system surface extension.
std::vector<std::string> required_instance_extensions();

/// `base` with what a Context must have to present to GLFW windows: the required instance extensions
/// added, presentation = true, and can_present = glfwGetPhysicalDevicePresentationSupport (so the chosen
/// queue family can present on this display). Same errors as required_instance_extensions().
gpu::ContextOptions window_context_options(gpu::ContextOptions base = {});

/// How to open a Window.
struct WindowOptions {
    std::string title = "tridex";
    int width = 1280;          ///< client-area size in screen coordinates (windowed mode), >= 1
    int height = 720;
    bool fullscreen = false;   ///< fullscreen on the chosen monitor at its current video mode (size ignored)
    int monitor_index = -1;    ///< fullscreen monitor by list_monitors() index; -1 = by name, else primary
    std::string monitor_name;  ///< fullscreen monitor whose name contains this text (case-sensitive); "" = primary
    bool resizable = true;     ///< windowed mode: the user may resize (the swapchain follows)
    /// Windowed mode: 0 opens the window at width x height, shrunk (keeping its aspect) to fit the work area of the
    /// monitor it opens on (the chosen or primary monitor, less panels and docks); a fraction in (0, 1] opens it at
    /// that fraction of the work area's width and height instead (a desk window sized to its monitor).
    double fill_monitor = 0.0;
    bool visible = true;       ///< false: a hidden window (still presentable on X11)
};

/// A GLFW window (no client API: Vulkan draws into it), windowed or fullscreen on a chosen monitor. Its
/// keyboard, mouse-button, cursor and scroll callbacks fill input() with abstract InputEvents; resizes
/// are seen through framebuffer_size(). GLFW is initialised on first use and stays initialised (see
/// WindowSystemScope). GLFW rule: create, poll and destroy windows on the main thread only. Move-only.
class Window {
public:
    /// Opens the window. Throws tridex::Error when GLFW cannot initialise (no display), Vulkan is not
    /// supported by GLFW, width/height < 1 (windowed), fill_monitor outside [0, 1], the monitor index is out of
    /// range or no monitor name matches (the message lists the monitors), or the window cannot be created.
    static Window create(const WindowOptions& options);

    ~Window();
    Window(Window&&) noexcept;
    Window& operator=(Window&&) noexcept;
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    /// Creates a Vulkan surface for this window on the Context's instance (which must have the
    /// required_instance_extensions()). Throws tridex::Error on failure.
    gpu::Surface create_surface(const gpu::Context& context) const;

    /// Processes pending window-system events (callbacks fill input()); returns immediately.
    void poll_events();
    /// True once the user asked to close the window (close button, Alt+F4) or request_close() was called.
    bool should_close() const;
    /// Marks the window for closing (should_close() becomes true).
    void request_close();
    /// Framebuffer size in pixels (0 x 0 while minimised): the size a swapchain should have.
    VkExtent2D framebuffer_size() const;
    /// Resizes the client area (windowed mode), screen coordinates; the framebuffer follows after the
    /// window system has processed it (poll_events). Throws tridex::Error for a size < 1.
    void set_size(int width, int height);
    /// Changes the title bar text.
    void set_title(const std::string& title);
    /// The monitor the window is fullscreen on (index into list_monitors()), or -1 when windowed.
    int fullscreen_monitor() const;
    /// The input events the callbacks have queued since the app last drained it.
    InputQueue& input();

    struct Impl;

private:
    explicit Window(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace tridex::renderer
