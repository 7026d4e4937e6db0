// Window smoke tests under a private Xvfb (started by the test): monitors, a window, a vsync'd swapchain on
// lavapipe's X11 surface, every stereo output that works on it (read back from the swapchain and checked
// against compose()), quad refused with the list of working outputs, resize, and frame timing.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "gpu/context.hpp"
#include "gpu/swapchain.hpp"
#include "renderer/output/anaglyph_pass.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/output/stereo_output.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "renderer/window/window_glfw.hpp"
#include "renderer/window/window_presenter.hpp"
#include "test_scene.hpp"
#include "test_window_xvfb.hpp"

namespace tridex::renderer {
namespace {

constexpr int kEyeW = 160, kEyeH = 120;  // eye image size of the output tests, pixels

// Resizes the window and polls until the framebuffer has that size (Xvfb has no window manager: quick).
void resize_and_wait(Window& w, int width, int height) {
    w.set_size(width, height);
    for (int i = 0; i < 200; ++i) {
        w.poll_events();
        const VkExtent2D fb = w.framebuffer_size();
        if (fb.width == static_cast<std::uint32_t>(width) && fb.height == static_cast<std::uint32_t>(height)) return;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    FAIL() << "window did not reach " << width << "x" << height;
}

// Expects `got` to match `want` within `tolerance` per channel on R, G, B (the swapchain's alpha is not shown).
void expect_rgb_near(const Image& got, const Image& want, int tolerance, const std::string& what) {
    ASSERT_EQ(got.width, want.width) << what;
    ASSERT_EQ(got.height, want.height) << what;
    int worst = 0;
    for (std::size_t i = 0; i < got.rgba.size(); ++i) {
        if (i % 4 == 3) continue;
        worst = std::max(worst, std::abs(int(got.rgba[i]) - int(want.rgba[i])));
    }
    EXPECT_LE(worst, tolerance) << what;
    if (worst > tolerance) {
        write_png(what + "_got.png", got);
        write_png(what + "_want.png", want);
        write_png(what + "_diff.png", difference_image(got, want, tolerance));
    }
}

TEST(WindowSmoke, ListsMonitorsAndRefusesBadChoices) {
    test::VirtualDisplay display(1280, 1024);
    const WindowSystemScope glfw_scope;  // GLFW ends (after the Context and windows) before this Xvfb does
    const std::vector<MonitorInfo> monitors = list_monitors();
    ASSERT_GE(monitors.size(), 1u);
    EXPECT_EQ(monitors[0].index, 0);
    EXPECT_EQ(monitors[0].width_px, 1280);
    EXPECT_EQ(monitors[0].height_px, 1024);
    std::printf("[window] Xvfb %s: monitor 0 '%s' %dx%d @ %d Hz, %dx%d mm\n", display.display().c_str(),
                monitors[0].name.c_str(), monitors[0].width_px, monitors[0].height_px, monitors[0].refresh_hz,
                monitors[0].width_mm, monitors[0].height_mm);
    const std::vector<std::string> ext = required_instance_extensions();
    EXPECT_NE(std::find(ext.begin(), ext.end(), "VK_KHR_surface"), ext.end());

    WindowOptions o;
    o.fullscreen = true;
    o.monitor_index = static_cast<int>(monitors.size());
    try {
        (void)Window::create(o);
        ADD_FAILURE() << "an out-of-range monitor index was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("monitor_index"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("'" + monitors[0].name + "'"), std::string::npos) << e.what();
    }
    o.monitor_index = -1;
    o.monitor_name = "no such monitor";
    EXPECT_THROW((void)Window::create(o), Error);
    WindowOptions bad;
    bad.width = 0;
    EXPECT_THROW((void)Window::create(bad), Error);

    // Fullscreen on monitor 0 by name covers it at its current mode.
    o.monitor_name = monitors[0].name;
    Window full = Window::create(o);
    EXPECT_EQ(full.fullscreen_monitor(), 0);
    full.poll_events();
    EXPECT_EQ(full.framebuffer_size().width, 1280u);
    EXPECT_EQ(full.framebuffer_size().height, 1024u);
}

TEST(WindowSmoke, PresentsEveryWorkingOutputAndRefusesQuad) {
    test::VirtualDisplay display(1280, 1024);
    const WindowSystemScope glfw_scope;  // GLFW ends (after the Context and windows) before this Xvfb does
    gpu::Context ctx = gpu::Context::create(window_context_options());
    ASSERT_TRUE(ctx.validation_enabled());
    ASSERT_TRUE(ctx.presentation_enabled());

    const TriMesh cube = test::test_cube();
    const SceneView scene = test::test_scene(cube);
    OffscreenStereoRenderer renderer = OffscreenStereoRenderer::create(ctx, kEyeW, kEyeH);
    const StereoImages eyes = renderer.render(scene, test::small_screen(), test::test_head(), 0.065);
    EXPECT_GE(renderer.last_gpu_ms(), 0.0);
    EXPECT_EQ(renderer.frames_rendered(), 1u);

    WindowOptions wo;
    wo.title = "tridex window smoke test";
    wo.width = 2 * kEyeW;
    wo.height = kEyeH;
    Window window = Window::create(wo);

    // What lavapipe's X11 surface offers; quad needs maxImageArrayLayers >= 2.
    std::uint32_t max_layers = 0;
    {
        gpu::Surface s = window.create_surface(ctx);
        const gpu::SurfaceSupport sup = gpu::query_surface(ctx, s.handle());
        EXPECT_TRUE(sup.queue_can_present);
        max_layers = sup.capabilities.maxImageArrayLayers;
        std::printf("[window] lavapipe X11 surface: maxImageArrayLayers %u, images %u..%u, %zu formats, "
                    "%zu present modes\n",
                    max_layers, sup.capabilities.minImageCount, sup.capabilities.maxImageCount, sup.formats.size(),
                    sup.present_modes.size());
    }
    if (max_layers < 2) {
        PresenterOptions po;
        po.output = StereoOutput::kQuad;
        try {
            (void)WindowPresenter::create(ctx, window, po);
            ADD_FAILURE() << "quad was accepted on a surface with maxImageArrayLayers " << max_layers;
        } catch (const Error& e) {
            const std::string m = e.what();
            std::printf("[window] quad refused: %s\n", m.c_str());
            for (const char* name : {"frame-sequential", "side-by-side", "top-bottom", "anaglyph", "mono"})
                EXPECT_NE(m.find(name), std::string::npos) << name << " missing from: " << m;
        }
    }

    // Every other output: size the window as output_size() says, present 3 frames, read the swapchain image
    // back and compare with compose(): 1:1 blits exactly, 2:1 squeezes (linear blit vs box filter) within 1.
    struct Case {
        StereoOutput output;
        int tolerance;
    };
    for (const Case c : {Case{StereoOutput::kSideBySide, 0}, Case{StereoOutput::kSideBySideHalf, 1},
                         Case{StereoOutput::kTopBottom, 0}, Case{StereoOutput::kTopBottomHalf, 1},
                         Case{StereoOutput::kMono, 0}}) {
        const std::string name(to_string(c.output));
        const auto [w, h] = output_size(c.output, kEyeW, kEyeH);
        resize_and_wait(window, w, h);
        PresenterOptions po;
        po.output = c.output;
        po.capture = true;
        WindowPresenter p = WindowPresenter::create(ctx, window, po);
        EXPECT_STREQ(p.present_mode(), "fifo");
        for (int i = 0; i < 3; ++i) {
            window.poll_events();
            EXPECT_EQ(p.present(renderer), 1) << name;
        }
        EXPECT_EQ(p.presents(), 3u);
        expect_rgb_near(p.last_capture(), compose(c.output, eyes.left, eyes.right), c.tolerance, "window_" + name);
        if (c.output == StereoOutput::kSideBySide) {  // swap eyes: the halves exchange
            p.set_swap_eyes(true);
            EXPECT_EQ(p.present(renderer), 1);
            ComposeOptions swapped;
            swapped.swap_eyes = true;
            expect_rgb_near(p.last_capture(), compose(c.output, eyes.left, eyes.right, swapped), 0,
                            "window_side_by_side_swapped");
        }
    }

    // Frame-sequential: two presents per stereo frame, eyes alternating, the hook names each shutter.
    {
        resize_and_wait(window, kEyeW, kEyeH);
        PresenterOptions po;
        po.output = StereoOutput::kFrameSequential;
        po.capture = true;
        WindowPresenter p = WindowPresenter::create(ctx, window, po);
        std::vector<std::pair<int, std::uint64_t>> shown;
        p.sequencer().on_eye([&](int eye, std::uint64_t n) { shown.emplace_back(eye, n); });
        EXPECT_EQ(p.present(renderer), 2);
        EXPECT_EQ(p.last_eye(), 1);
        expect_rgb_near(p.last_capture(), eyes.right, 0, "window_frame_sequential_right");
        EXPECT_EQ(p.present(renderer), 2);
        ASSERT_EQ(shown.size(), 4u);
        for (std::uint64_t n = 0; n < 4; ++n) {
            EXPECT_EQ(shown[n].first, static_cast<int>(n % 2));
            EXPECT_EQ(shown[n].second, n);
        }
        p.set_swap_eyes(true);  // the right image now shows while the left shutter is open, and vice versa
        EXPECT_EQ(p.present(renderer), 2);
        EXPECT_EQ(p.last_eye(), 0);
        expect_rgb_near(p.last_capture(), eyes.left, 0, "window_frame_sequential_swapped");
        EXPECT_EQ(shown.back().first, 1);
        EXPECT_EQ(p.presents(), 6u);
    }

    // Anaglyph: composed on the CPU (compose), uploaded and blitted 1:1 - exact; or on the GPU.
    {
        PresenterOptions po;
        po.output = StereoOutput::kAnaglyph;
        po.capture = true;
        WindowPresenter p = WindowPresenter::create(ctx, window, po);
        EXPECT_THROW(p.present(renderer), Error);
        const Image composed = compose(StereoOutput::kAnaglyph, eyes.left, eyes.right);
        for (int i = 0; i < 2; ++i) EXPECT_EQ(p.present_composed(composed), 1);
        expect_rgb_near(p.last_capture(), composed, 0, "window_anaglyph");
        // The GPU anaglyph pass recorded into the present's command buffer (as WindowSink does): within 1 code.
        // Written as RGBA it is blitted; in the swapchain's format (BGRA here) it is copied: the same picture.
        for (const VkFormat format : {VK_FORMAT_R8G8B8A8_UNORM, p.format()}) {
            AnaglyphPass pass = AnaglyphPass::create(ctx, kEyeW, kEyeH, format);
            EXPECT_EQ(pass.format(), format);
            const auto record = [&](VkCommandBuffer cmd) {
                pass.record(cmd, renderer, AnaglyphMethod::kDubois, false);
            };
            for (int i = 0; i < 2; ++i) EXPECT_EQ(p.present_image(pass.image(), format, kEyeW, kEyeH, record), 1);
            expect_rgb_near(p.last_capture(), composed, 1, "window_anaglyph_gpu");
            expect_rgb_near(pass.compose(renderer, AnaglyphMethod::kDubois, false), composed, 1,
                            "anaglyph_pass_read_back");
        }
        EXPECT_THROW(p.present_image(VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, kEyeW, kEyeH), Error);
        AnaglyphPass rgba = AnaglyphPass::create(ctx, kEyeW, kEyeH);
        EXPECT_THROW(p.present_image(rgba.image(), VK_FORMAT_R8G8B8A8_SRGB, kEyeW, kEyeH), Error);
        EXPECT_THROW(AnaglyphPass::create(ctx, kEyeW, kEyeH, VK_FORMAT_R8G8B8A8_SRGB), Error);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(WindowSmoke, FollowsResizeAndReportsFrameTimes) {
    test::VirtualDisplay display(1280, 1024);
    const WindowSystemScope glfw_scope;  // GLFW ends (after the Context and windows) before this Xvfb does
    gpu::Context ctx = gpu::Context::create(window_context_options());
    const TriMesh cube = test::test_cube();
    const SceneView scene = test::test_scene(cube);
    constexpr int kW = 640, kH = 360;  // side-by-side full in a 1280 x 360 window
    OffscreenStereoRenderer renderer = OffscreenStereoRenderer::create(ctx, kW, kH);
    WindowOptions wo;
    wo.width = 2 * kW;
    wo.height = kH;
    Window window = Window::create(wo);
    PresenterOptions po;
    po.output = StereoOutput::kSideBySide;
    WindowPresenter p = WindowPresenter::create(ctx, window, po);
    EXPECT_THROW(p.present(renderer), Error);  // nothing rendered yet
    EXPECT_EQ(p.extent().width, 2u * kW);

    constexpr int kFrames = 30;
    for (int i = 0; i < kFrames; ++i) {
        window.poll_events();
        Pose head = test::test_head();
        head.position.x += 0.002 * i;
        renderer.draw(scene, test::small_screen(), head, 0.065);
        ASSERT_EQ(p.present(renderer), 1);
    }
    p.finish();  // the presents in flight
    const FrameTimings& t = p.timings();
    // Frames in flight: at a present the renderer's latest finished frame is one or two before it (none at first).
    EXPECT_GE(t.render_gpu_ms.count(), static_cast<std::uint64_t>(kFrames - 2));
    EXPECT_EQ(t.blit_gpu_ms.count(), static_cast<std::uint64_t>(kFrames));
    EXPECT_EQ(t.interval_ms.count(), static_cast<std::uint64_t>(kFrames - 1));
    EXPECT_GT(t.blit_gpu_ms.mean_ms(), 0.0);
    std::printf("[window] side-by-side %dx%d per eye on Xvfb, %s, %d frames: render GPU p50 %.2f ms (mean %.2f), "
                "present pass GPU p50 %.2f ms (mean %.2f), present interval p50 %.2f ms (mean %.2f, max %.2f)\n",
                kW, kH, p.present_mode(), kFrames, t.render_gpu_ms.percentile_ms(0.5), t.render_gpu_ms.mean_ms(),
                t.blit_gpu_ms.percentile_ms(0.5), t.blit_gpu_ms.mean_ms(), t.interval_ms.percentile_ms(0.5),
                t.interval_ms.mean_ms(), t.interval_ms.max_ms());

    // Presents alone (no rendering in between): FIFO paces them at the display's rate, if the X server has one.
    DurationHistogram present_only(0.25, 400);
    for (int i = 0; i < 20; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        ASSERT_EQ(p.present(renderer), 1);
        present_only.add(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::printf("[window] present() alone, 20 calls: p50 %.2f ms, mean %.2f ms, min %.2f ms, max %.2f ms\n",
                present_only.percentile_ms(0.5), present_only.mean_ms(), present_only.min_ms(), present_only.max_ms());

    // The user resizes the window: the next present recreates the swapchain at the new size.
    const std::uint64_t before = p.recreations();
    resize_and_wait(window, 800, 300);
    ASSERT_EQ(p.present(renderer), 1);
    EXPECT_EQ(p.recreations(), before + 1);
    EXPECT_EQ(p.extent().width, 800u);
    EXPECT_EQ(p.extent().height, 300u);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
