// GLFW lifetime: querying the instance extensions with no window open, then a
// presentation-capable Context, then two windows one after the other (each with a surface and a swapchain
// frame) must not crash. Before the fix GLFW was terminated after the query, the next window's new X
// connection could land at the freed one's address, and Mesa's WSI cache sent refused XFixes requests.
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "gpu/context.hpp"
#include "gpu/swapchain.hpp"
#include "renderer/window/window_glfw.hpp"
#include "test_window_xvfb.hpp"

namespace tridex::renderer {
namespace {

TEST(WindowLifetime, QueryThenTwoWindowsInARowKeepOneGlfwInitialisation) {
    test::VirtualDisplay display(1280, 1024);
    const std::uint64_t inits_before = window_system_initialisations();
    {
        const WindowSystemScope scope;
        const std::vector<std::string> ext = required_instance_extensions();  // no window open
        EXPECT_NE(std::find(ext.begin(), ext.end(), "VK_KHR_surface"), ext.end());
        EXPECT_TRUE(window_system_initialised());  // the query leaves GLFW up
        EXPECT_EQ(window_system_initialisations(), inits_before + 1);
        gpu::Context ctx = gpu::Context::create(window_context_options());
        ASSERT_TRUE(ctx.presentation_enabled());
        for (int k = 0; k < 2; ++k) {  // two windows in a row: the first is closed before the second opens
            WindowOptions wo;
            wo.title = "tridex lifetime " + std::to_string(k);
            wo.width = 320;
            wo.height = 200;
            Window w = Window::create(wo);
            w.poll_events();
            gpu::Surface s = w.create_surface(ctx);
            const gpu::SurfaceSupport sup = gpu::query_surface(ctx, s.handle());
            EXPECT_TRUE(sup.queue_can_present) << "window " << k;
            EXPECT_FALSE(sup.formats.empty()) << "window " << k;
        }
        // Closing the last window does not terminate GLFW while the scope lives.
        EXPECT_TRUE(window_system_initialised());
        EXPECT_EQ(window_system_initialisations(), inits_before + 1);
        EXPECT_EQ(ctx.validation_messages(), 0u);
    }
    EXPECT_FALSE(window_system_initialised());  // the scope ended with no window open
}

TEST(WindowLifetime, ScopeEndingWithAWindowOpenTerminatesWhenItCloses) {
    test::VirtualDisplay display(1280, 1024);
    std::optional<Window> w;
    {
        const WindowSystemScope scope;
        WindowOptions wo;
        wo.width = 64;
        wo.height = 64;
        w.emplace(Window::create(wo));
    }
    EXPECT_TRUE(window_system_initialised());  // still needed by the open window
    w.reset();
    EXPECT_FALSE(window_system_initialised());
    // A new session (a new scope) initialises GLFW again on the current DISPLAY.
    const WindowSystemScope scope;
    EXPECT_FALSE(list_monitors().empty());
    EXPECT_TRUE(window_system_initialised());
}

}  // namespace
}  // namespace tridex::renderer
