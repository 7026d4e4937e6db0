// renderer/window/window_glfw.cpp - GLFW lifetime, monitors, window creation, surface, input callbacks.
#define GLFW_INCLUDE_VULKAN
#include "renderer/window/window_glfw.hpp"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdint>
#include <mutex>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "gpu/check.hpp"

namespace tridex::renderer {
namespace {

// The text of the last GLFW error (GLFW reports errors through a callback, not return values).
std::mutex g_mutex;
std::string g_last_error;

// GLFW's process-wide lifetime. GLFW (and with it its X connection) is initialised on first use and stays
// initialised: a Vulkan instance that asked about presentation on that connection (Mesa's WSI caches
// per-connection state keyed by the connection's address) must never meet a new connection at the same
// address. It is terminated only when the last WindowSystemScope ends with no Window open (or, if windows
// are still open then, when the last of them closes). Main thread only, as GLFW requires.
struct GlfwState {
    bool initialised = false;
    int windows = 0;             // open Windows
    int scopes = 0;              // live WindowSystemScopes
    bool terminate_pending = false;  // the last scope ended while windows were open
    std::uint64_t initialisations = 0;
};
GlfwState g_glfw;

void on_glfw_error(int code, const char* text) {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_last_error = "GLFW error " + std::to_string(code) + ": " + (text ? text : "(no text)");
}

std::string last_error() {
    std::lock_guard<std::mutex> lock(g_mutex);
    return g_last_error.empty() ? std::string("no GLFW error text") : g_last_error;
}

// Initialises GLFW unless it is already. Throws tridex::Error when it cannot.
void ensure_glfw() {
    if (g_glfw.initialised) return;
    glfwSetErrorCallback(on_glfw_error);
    if (glfwInit() != GLFW_TRUE)
        throw Error("window: GLFW cannot initialise (is DISPLAY set to a running X server?): " + last_error());
    g_glfw.initialised = true;
    g_glfw.terminate_pending = false;
    ++g_glfw.initialisations;
}

void terminate_glfw() {
    if (!g_glfw.initialised) return;
    glfwTerminate();
    g_glfw.initialised = false;
    g_glfw.terminate_pending = false;
}

// One open Window's claim on GLFW (initialises it; counts open windows).
class WindowClaim {
public:
    WindowClaim() {
        ensure_glfw();
        ++g_glfw.windows;
    }
    ~WindowClaim() {
        if (--g_glfw.windows == 0 && g_glfw.terminate_pending) terminate_glfw();
    }
    WindowClaim(const WindowClaim&) = delete;
    WindowClaim& operator=(const WindowClaim&) = delete;
};

}  // namespace

WindowSystemScope::WindowSystemScope() { ++g_glfw.scopes; }

WindowSystemScope::~WindowSystemScope() {
    if (--g_glfw.scopes > 0) return;
    if (g_glfw.windows == 0)
        terminate_glfw();
    else
        g_glfw.terminate_pending = g_glfw.initialised;
}

bool window_system_initialised() { return g_glfw.initialised; }
std::uint64_t window_system_initialisations() { return g_glfw.initialisations; }

namespace {

MonitorInfo describe(GLFWmonitor* m, int index) {
    MonitorInfo info;
    info.index = index;
    const char* name = glfwGetMonitorName(m);
    info.name = name ? name : "";
    glfwGetMonitorPos(m, &info.x_px, &info.y_px);
    if (const GLFWvidmode* mode = glfwGetVideoMode(m)) {
        info.width_px = mode->width;
        info.height_px = mode->height;
        info.refresh_hz = mode->refreshRate;
    }
    glfwGetMonitorPhysicalSize(m, &info.width_mm, &info.height_mm);
    return info;
}

std::string monitor_list_text() {
    int n = 0;
    GLFWmonitor** monitors = glfwGetMonitors(&n);
    std::string text = std::to_string(n) + " monitor(s):";
    for (int i = 0; i < n; ++i) {
        const char* name = glfwGetMonitorName(monitors[i]);
        text += " " + std::to_string(i) + " '" + (name ? name : "") + "'";
    }
    return text;
}

// The monitor the options choose for fullscreen, and its index.
GLFWmonitor* choose_monitor(const WindowOptions& o, int& index) {
    int n = 0;
    GLFWmonitor** monitors = glfwGetMonitors(&n);
    if (n == 0 || !monitors) throw Error("window: fullscreen requested but GLFW reports no monitor");
    if (o.monitor_index >= 0) {
        if (o.monitor_index >= n)
            throw Error("window: WindowOptions.monitor_index " + std::to_string(o.monitor_index) + " is out of range; " +
                        monitor_list_text());
        index = o.monitor_index;
        return monitors[index];
    }
    if (!o.monitor_name.empty()) {
        for (int i = 0; i < n; ++i) {
            const char* name = glfwGetMonitorName(monitors[i]);
            if (name && std::string(name).find(o.monitor_name) != std::string::npos) {
                index = i;
                return monitors[i];
            }
        }
        throw Error("window: WindowOptions.monitor_name '" + o.monitor_name + "' matches no monitor; " +
                    monitor_list_text());
    }
    index = 0;
    return monitors[0];
}

// The windowed size: width x height shrunk to fit the monitor's work area, or `fill` of the work area (see
// WindowOptions::fill_monitor). Without a monitor (a headless X server still has one) the size asked for.
std::pair<int, int> windowed_size(const WindowOptions& o) {
    int n = 0;
    GLFWmonitor** monitors = glfwGetMonitors(&n);
    if (n == 0 || !monitors) return {o.width, o.height};
    int index = 0;
    GLFWmonitor* m = (o.monitor_index >= 0 && o.monitor_index < n) ? monitors[o.monitor_index] : choose_monitor(o, index);
    int x = 0, y = 0, aw = 0, ah = 0;
    glfwGetMonitorWorkarea(m, &x, &y, &aw, &ah);
    if (aw < 1 || ah < 1) return {o.width, o.height};
    if (o.fill_monitor > 0.0)
        return {std::max(1, static_cast<int>(o.fill_monitor * aw)), std::max(1, static_cast<int>(o.fill_monitor * ah))};
    const double shrink = std::min({1.0, static_cast<double>(aw) / o.width, static_cast<double>(ah) / o.height});
    return {std::max(1, static_cast<int>(shrink * o.width)), std::max(1, static_cast<int>(shrink * o.height))};
}

}  // namespace

struct Window::Impl {
    WindowClaim claim;
    GLFWwindow* window = nullptr;
    InputQueue input;
    int monitor = -1;

    ~Impl() {
        if (window) glfwDestroyWindow(window);
    }

    static Impl& of(GLFWwindow* w) { return *static_cast<Impl*>(glfwGetWindowUserPointer(w)); }
    static void on_key(GLFWwindow* w, int key, int /*scancode*/, int action, int mods) {
        of(w).input.on_key(key, action, mods, glfwGetTime());
    }
    static void on_button(GLFWwindow* w, int button, int action, int mods) {
        double x = 0, y = 0;
        glfwGetCursorPos(w, &x, &y);
        of(w).input.on_mouse_button(button, action, mods, x, y, glfwGetTime());
    }
    static void on_cursor(GLFWwindow* w, double x, double y) { of(w).input.on_cursor(x, y, glfwGetTime()); }
    static void on_scroll(GLFWwindow* w, double dx, double dy) {
        Impl& im = of(w);
        im.input.on_scroll(dx, dy, im.input.cursor_x(), im.input.cursor_y(), glfwGetTime());
    }
    static void on_enter(GLFWwindow* w, int /*entered*/) { of(w).input.reset_cursor(); }
    static void on_focus(GLFWwindow* w, int /*focused*/) { of(w).input.reset_cursor(); }
};

std::vector<MonitorInfo> list_monitors() {
    ensure_glfw();
    int n = 0;
    GLFWmonitor** monitors = glfwGetMonitors(&n);
    std::vector<MonitorInfo> out;
    for (int i = 0; i < n; ++i) out.push_back(describe(monitors[i], i));
    return out;
}

std::vector<std::string> required_instance_extensions() {
    ensure_glfw();
    if (glfwVulkanSupported() != GLFW_TRUE)
        throw Error("window: GLFW finds no usable Vulkan loader: " + last_error());
    std::uint32_t n = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&n);
    if (!names || n == 0)
        throw Error("window: GLFW finds no Vulkan surface extension for this window system: " + last_error());
    return std::vector<std::string>(names, names + n);
}

gpu::ContextOptions window_context_options(gpu::ContextOptions base) {
    for (const std::string& e : required_instance_extensions()) {
        bool listed = false;
        for (const std::string& have : base.instance_extensions) listed = listed || have == e;
        if (!listed) base.instance_extensions.push_back(e);
    }
    base.presentation = true;
    // GLFW stays initialised after this (see GlfwState), so the connection the query uses outlives the Context.
    base.can_present = [](VkInstance instance, VkPhysicalDevice device, std::uint32_t family) {
        return glfwGetPhysicalDevicePresentationSupport(instance, device, family) == GLFW_TRUE;
    };
    return base;
}

Window Window::create(const WindowOptions& o) {
    auto impl = std::make_unique<Impl>();
    if (glfwVulkanSupported() != GLFW_TRUE) throw Error("window: GLFW finds no usable Vulkan loader: " + last_error());
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_VISIBLE, o.visible ? GLFW_TRUE : GLFW_FALSE);
    GLFWwindow* w = nullptr;
    if (o.fullscreen) {
        int index = 0;
        GLFWmonitor* monitor = choose_monitor(o, index);
        const GLFWvidmode* mode = glfwGetVideoMode(monitor);
        if (!mode) throw Error("window: monitor " + std::to_string(index) + " reports no video mode: " + last_error());
        // Ask for the monitor's current mode so that no mode switch happens.
        glfwWindowHint(GLFW_RED_BITS, mode->redBits);
        glfwWindowHint(GLFW_GREEN_BITS, mode->greenBits);
        glfwWindowHint(GLFW_BLUE_BITS, mode->blueBits);
        glfwWindowHint(GLFW_REFRESH_RATE, mode->refreshRate);
        w = glfwCreateWindow(mode->width, mode->height, o.title.c_str(), monitor, nullptr);
        impl->monitor = index;
    } else {
        if (o.width < 1 || o.height < 1)
            throw Error("window: WindowOptions.width/height must be >= 1 (got " + std::to_string(o.width) + "x" +
                        std::to_string(o.height) + ")");
        if (!(o.fill_monitor >= 0.0 && o.fill_monitor <= 1.0))
            throw Error("window: WindowOptions.fill_monitor must be in [0, 1] (got " + std::to_string(o.fill_monitor) + ")");
        glfwWindowHint(GLFW_RESIZABLE, o.resizable ? GLFW_TRUE : GLFW_FALSE);
        const auto [ww, wh] = windowed_size(o);
        w = glfwCreateWindow(ww, wh, o.title.c_str(), nullptr, nullptr);
    }
    if (!w) throw Error("window: glfwCreateWindow failed: " + last_error());
    impl->window = w;
    glfwSetWindowUserPointer(w, impl.get());
    glfwSetKeyCallback(w, &Impl::on_key);
    glfwSetMouseButtonCallback(w, &Impl::on_button);
    glfwSetCursorPosCallback(w, &Impl::on_cursor);
    glfwSetScrollCallback(w, &Impl::on_scroll);
    glfwSetCursorEnterCallback(w, &Impl::on_enter);
    glfwSetWindowFocusCallback(w, &Impl::on_focus);
    return Window(std::move(impl));
}

Window::Window(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Window::~Window() = default;
Window::Window(Window&&) noexcept = default;
Window& Window::operator=(Window&&) noexcept = default;

gpu::Surface Window::create_surface(const gpu::Context& context) const {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    const VkResult r = glfwCreateWindowSurface(context.instance(), impl_->window, nullptr, &surface);
    if (r != VK_SUCCESS)
        throw Error("window: glfwCreateWindowSurface failed (" + std::string(gpu::result_name(r)) +
                    "; does the Context have window_context_options()?): " + last_error());
    return gpu::Surface(context.instance(), surface);
}

void Window::poll_events() { glfwPollEvents(); }
bool Window::should_close() const { return glfwWindowShouldClose(impl_->window) == GLFW_TRUE; }
void Window::request_close() { glfwSetWindowShouldClose(impl_->window, GLFW_TRUE); }

VkExtent2D Window::framebuffer_size() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(impl_->window, &w, &h);
    return VkExtent2D{static_cast<std::uint32_t>(w > 0 ? w : 0), static_cast<std::uint32_t>(h > 0 ? h : 0)};
}

void Window::set_size(int width, int height) {
    if (width < 1 || height < 1)
        throw Error("window: set_size needs width/height >= 1 (got " + std::to_string(width) + "x" +
                    std::to_string(height) + ")");
    glfwSetWindowSize(impl_->window, width, height);
}

void Window::set_title(const std::string& title) { glfwSetWindowTitle(impl_->window, title.c_str()); }
int Window::fullscreen_monitor() const { return impl_->monitor; }
InputQueue& Window::input() { return impl_->input; }

}  // namespace tridex::renderer
