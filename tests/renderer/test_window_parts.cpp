// Tests of the window-system-free parts of the window path: input translation and the event ring, the blit
// layout of every stereo output, and the frame-time histogram. No display needed.
#include <gtest/gtest.h>

#include <GLFW/glfw3.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/window/window_blit_layout.hpp"
#include "renderer/window/window_frame_timing.hpp"
#include "renderer/window/window_input.hpp"

namespace tridex::renderer {
namespace {

TEST(WindowInput, TranslatesGlfwKeysButtonsAndModifiers) {
    EXPECT_EQ(key_from_glfw(GLFW_KEY_A), Key::kA);
    EXPECT_EQ(key_from_glfw(GLFW_KEY_Z), Key::kZ);
    EXPECT_EQ(key_from_glfw(GLFW_KEY_W), Key::kW);
    EXPECT_EQ(key_from_glfw(GLFW_KEY_0), Key::k0);
    EXPECT_EQ(key_from_glfw(GLFW_KEY_9), Key::k9);
    EXPECT_EQ(key_from_glfw(GLFW_KEY_ESCAPE), Key::kEscape);
    EXPECT_EQ(key_from_glfw(GLFW_KEY_PAGE_DOWN), Key::kPageDown);
    EXPECT_EQ(key_from_glfw(GLFW_KEY_F12), Key::kF12);
    EXPECT_EQ(key_from_glfw(GLFW_KEY_KP_ADD), Key::kKeypadAdd);
    EXPECT_EQ(key_from_glfw(GLFW_KEY_CAPS_LOCK), Key::kUnknown);
    EXPECT_EQ(key_from_glfw(GLFW_KEY_UNKNOWN), Key::kUnknown);
    EXPECT_EQ(to_string(Key::kQ), "Q");
    EXPECT_EQ(to_string(Key::k7), "7");
    EXPECT_EQ(to_string(Key::kLeft), "Left");
    EXPECT_EQ(to_string(Key::kUnknown), "Unknown");
    EXPECT_EQ(button_from_glfw(GLFW_MOUSE_BUTTON_LEFT), MouseButton::kLeft);
    EXPECT_EQ(button_from_glfw(GLFW_MOUSE_BUTTON_RIGHT), MouseButton::kRight);
    EXPECT_EQ(button_from_glfw(GLFW_MOUSE_BUTTON_MIDDLE), MouseButton::kMiddle);
    EXPECT_EQ(button_from_glfw(GLFW_MOUSE_BUTTON_5), MouseButton::kOther);
    EXPECT_EQ(modifiers_from_glfw(GLFW_MOD_SHIFT | GLFW_MOD_ALT), modifier::kShift | modifier::kAlt);
    EXPECT_EQ(modifiers_from_glfw(GLFW_MOD_CONTROL | GLFW_MOD_SUPER), modifier::kControl | modifier::kSuper);
    EXPECT_EQ(modifiers_from_glfw(0), 0);
}

TEST(WindowInput, QueueProducesEventsWithDeltasInOrder) {
    InputQueue q(16);
    q.on_cursor(100.0, 50.0, 0.1);  // first position: an event with the position and no delta
    ASSERT_EQ(q.size(), 1u);
    {
        InputEvent first;
        ASSERT_TRUE(q.pop(first));
        EXPECT_EQ(first.type, InputType::kMouseMove);
        EXPECT_EQ(first.x_px, 100.0);
        EXPECT_EQ(first.y_px, 50.0);
        EXPECT_TRUE(std::isnan(first.dx_px) && std::isnan(first.dy_px));
    }
    q.on_cursor(103.5, 48.0, 0.2);
    q.on_cursor(103.5, 48.0, 0.25);  // no motion: no event
    q.on_key(GLFW_KEY_W, GLFW_PRESS, GLFW_MOD_SHIFT, 0.3);
    q.on_key(GLFW_KEY_W, GLFW_REPEAT, 0, 0.35);
    q.on_key(GLFW_KEY_W, 12345, 0, 0.36);  // unknown action: ignored
    q.on_mouse_button(GLFW_MOUSE_BUTTON_RIGHT, GLFW_PRESS, GLFW_MOD_CONTROL, 103.5, 48.0, 0.4);
    q.on_scroll(0.0, -2.0, 103.5, 48.0, 0.5);
    q.on_key(GLFW_KEY_W, GLFW_RELEASE, 0, 0.6);
    ASSERT_EQ(q.size(), 6u);

    InputEvent e;
    ASSERT_TRUE(q.pop(e));
    EXPECT_EQ(e.type, InputType::kMouseMove);
    EXPECT_EQ(e.dx_px, 3.5);
    EXPECT_EQ(e.dy_px, -2.0);
    EXPECT_EQ(e.x_px, 103.5);
    EXPECT_EQ(e.time_s, 0.2);
    ASSERT_TRUE(q.pop(e));
    EXPECT_EQ(e.type, InputType::kKey);
    EXPECT_EQ(e.key, Key::kW);
    EXPECT_EQ(e.action, InputAction::kPress);
    EXPECT_EQ(e.modifiers, modifier::kShift);
    ASSERT_TRUE(q.pop(e));
    EXPECT_EQ(e.action, InputAction::kRepeat);
    ASSERT_TRUE(q.pop(e));
    EXPECT_EQ(e.type, InputType::kMouseButton);
    EXPECT_EQ(e.button, MouseButton::kRight);
    EXPECT_EQ(e.modifiers, modifier::kControl);
    EXPECT_EQ(e.y_px, 48.0);
    ASSERT_TRUE(q.pop(e));
    EXPECT_EQ(e.type, InputType::kScroll);
    EXPECT_EQ(e.dx_px, 0.0);
    EXPECT_EQ(e.dy_px, -2.0);
    ASSERT_TRUE(q.pop(e));
    EXPECT_EQ(e.type, InputType::kKey);
    EXPECT_EQ(e.action, InputAction::kRelease);
    EXPECT_FALSE(q.pop(e));
    EXPECT_EQ(q.dropped(), 0u);

    // After reset_cursor() the next position is a new origin: its event has no delta (no jump).
    q.reset_cursor();
    q.on_cursor(10.0, 10.0, 1.0);
    ASSERT_EQ(q.size(), 1u);
    ASSERT_TRUE(q.pop(e));
    EXPECT_TRUE(std::isnan(e.dx_px));
    q.on_cursor(11.0, 9.0, 1.1);
    ASSERT_TRUE(q.pop(e));
    EXPECT_EQ(e.dx_px, 1.0);
    EXPECT_EQ(e.dy_px, -1.0);
}

TEST(WindowInput, FullQueueDropsAndCountsAndWrapsAround) {
    InputQueue q(3);
    EXPECT_EQ(q.capacity(), 3u);
    for (int i = 0; i < 5; ++i) q.on_scroll(0.0, static_cast<double>(i), 0.0, 0.0, i);
    EXPECT_EQ(q.size(), 3u);
    EXPECT_EQ(q.dropped(), 2u);
    InputEvent e;
    ASSERT_TRUE(q.pop(e));
    EXPECT_EQ(e.dy_px, 0.0);
    q.on_scroll(0.0, 10.0, 0.0, 0.0, 10.0);  // wraps into the freed slot
    for (double want : {1.0, 2.0, 10.0}) {
        ASSERT_TRUE(q.pop(e));
        EXPECT_EQ(e.dy_px, want);
    }
    EXPECT_EQ(q.size(), 0u);
    EXPECT_EQ(InputQueue(0).capacity(), 1u);
}

TEST(WindowBlitLayout, SplitsAndPlacesEyesPerOutput) {
    BlitPlan p = plan_blits(StereoOutput::kSideBySide, 641, 240);
    ASSERT_EQ(p.count, 2);
    EXPECT_EQ(p.blits[0].eye, 0);
    EXPECT_EQ(p.blits[0].x0, 0);
    EXPECT_EQ(p.blits[0].x1, 320);
    EXPECT_EQ(p.blits[0].y1, 240);
    EXPECT_EQ(p.blits[1].eye, 1);
    EXPECT_EQ(p.blits[1].x0, 320);
    EXPECT_EQ(p.blits[1].x1, 641);

    p = plan_blits(StereoOutput::kTopBottomHalf, 320, 241, true);
    ASSERT_EQ(p.count, 2);
    EXPECT_EQ(p.blits[0].eye, 1);  // swapped: the right eye on top
    EXPECT_EQ(p.blits[0].y0, 0);
    EXPECT_EQ(p.blits[0].y1, 120);
    EXPECT_EQ(p.blits[1].eye, 0);
    EXPECT_EQ(p.blits[1].y0, 120);
    EXPECT_EQ(p.blits[1].y1, 241);
    EXPECT_EQ(p.blits[1].x1, 320);

    p = plan_blits(StereoOutput::kQuad, 100, 80);
    ASSERT_EQ(p.count, 2);
    EXPECT_EQ(p.blits[0].dst_layer, 0);
    EXPECT_EQ(p.blits[1].dst_layer, 1);
    EXPECT_EQ(p.blits[1].eye, 1);
    EXPECT_EQ(p.blits[1].x1, 100);
    EXPECT_EQ(swapchain_layers(StereoOutput::kQuad), 2u);
    EXPECT_EQ(swapchain_layers(StereoOutput::kSideBySide), 1u);

    p = plan_blits(StereoOutput::kFrameSequential, 100, 80, true, 1);  // frame_eye already holds the swap
    ASSERT_EQ(p.count, 1);
    EXPECT_EQ(p.blits[0].eye, 1);
    p = plan_blits(StereoOutput::kMono, 100, 80, true);  // mono ignores the swap
    ASSERT_EQ(p.count, 1);
    EXPECT_EQ(p.blits[0].eye, 0);
    EXPECT_EQ(p.blits[0].y1, 80);

    EXPECT_EQ(eye_size_for(StereoOutput::kSideBySide, 1920, 1080), std::make_pair(960, 1080));
    EXPECT_EQ(eye_size_for(StereoOutput::kSideBySideHalf, 1921, 1080), std::make_pair(960, 1080));
    EXPECT_EQ(eye_size_for(StereoOutput::kTopBottomHalf, 1920, 1080), std::make_pair(1920, 540));
    EXPECT_EQ(eye_size_for(StereoOutput::kFrameSequential, 1920, 1080), std::make_pair(1920, 1080));
    EXPECT_EQ(eye_size_for(StereoOutput::kAnaglyph, 1920, 1080), std::make_pair(1920, 1080));
    EXPECT_THROW(eye_size_for(StereoOutput::kTopBottom, 100, 1), Error);

    EXPECT_THROW(plan_blits(StereoOutput::kAnaglyph, 100, 80), Error);
    EXPECT_THROW(plan_blits(StereoOutput::kSideBySide, 1, 80), Error);
    EXPECT_THROW(plan_blits(StereoOutput::kMono, 0, 80), Error);
    EXPECT_THROW(plan_blits(StereoOutput::kFrameSequential, 10, 10, false, 2), Error);
}

TEST(DurationHistogram, BinsPercentilesAndJson) {
    DurationHistogram h(1.0, 10, 0);  // [0,1) .. [9,10) ms, then overflow
    EXPECT_EQ(h.percentile_ms(0.5), 0.0);
    for (double ms : {0.5, 1.0, 1.5, 2.2, 16.0, 3.0, 3.9, 9.99}) h.add(ms);
    h.add(-1.0);
    h.add(std::numeric_limits<double>::quiet_NaN());
    EXPECT_EQ(h.count(), 8u);
    EXPECT_EQ(h.rejected(), 2u);
    EXPECT_EQ(h.overflow(), 1u);
    EXPECT_EQ(h.bins()[0], 1u);
    EXPECT_EQ(h.bins()[1], 2u);
    EXPECT_EQ(h.bins()[2], 1u);
    EXPECT_EQ(h.bins()[3], 2u);
    EXPECT_EQ(h.bins()[9], 1u);
    EXPECT_EQ(h.min_ms(), 0.5);
    EXPECT_EQ(h.max_ms(), 16.0);
    EXPECT_NEAR(h.mean_ms(), (0.5 + 1.0 + 1.5 + 2.2 + 16.0 + 3.0 + 3.9 + 9.99) / 8.0, 1e-12);
    // Sorted: 0.5 1.0 1.5 2.2 3.0 3.9 9.99 16 -> rank ceil(0.5*8)=4 is 2.2 in [2,3): upper edge 3.
    EXPECT_EQ(h.percentile_ms(0.5), 3.0);
    EXPECT_EQ(h.percentile_ms(0.0), 1.0);    // the first sample's bin [0,1)
    EXPECT_EQ(h.percentile_ms(0.875), 10.0); // rank 7: 9.99 in [9,10)
    EXPECT_EQ(h.percentile_ms(1.0), 16.0);   // rank 8 overflowed: max
    EXPECT_THROW(h.percentile_ms(1.5), Error);
    const nlohmann::json j = histogram_json(h);
    EXPECT_EQ(j["count"], 8);
    EXPECT_EQ(j["overflow"], 1);
    EXPECT_EQ(j["p50_ms"], 3.0);
    ASSERT_EQ(j["bins"].size(), 5u);  // non-empty bins only
    EXPECT_EQ(j["bins"][1][0], 1.0);
    EXPECT_EQ(j["bins"][1][1], 2);
    h.clear();
    EXPECT_EQ(h.count(), 0u);
    EXPECT_EQ(h.bins()[1], 0u);
    EXPECT_EQ(h.bins().size(), 10u);
    EXPECT_THROW(DurationHistogram(0.0, 10), Error);
    EXPECT_THROW(DurationHistogram(1.0, 0), Error);
    EXPECT_THROW(DurationHistogram(1.0, 10, 10, 0.5), Error);
    // Coarse bins above the fine ones: slow frames (a CPU Vulkan implementation's 100-500 ms) keep their percentiles.
    DurationHistogram slow;  // 0.25 ms bins to 100 ms, then 5 ms bins to 2.1 s
    for (int i = 0; i < 10; ++i) slow.add(10.0);
    for (int i = 0; i < 20; ++i) slow.add(112.0);
    slow.add(513.8);
    slow.add(5000.0);
    EXPECT_EQ(slow.overflow(), 1u);
    EXPECT_EQ(slow.percentile_ms(0.25), 10.25);  // rank 8: a fine bin [10, 10.25)
    EXPECT_EQ(slow.percentile_ms(0.5), 115.0);   // rank 16: 112 in the coarse bin [110, 115)
    EXPECT_EQ(slow.percentile_ms(31.0 / 32.0), 515.0);
    EXPECT_EQ(slow.percentile_ms(1.0), 5000.0);  // overflowed: the largest sample
    DurationHistogram one;
    one.add(2.2);
    EXPECT_EQ(one.percentile_ms(0.5), 2.2);  // the bin's upper edge 2.25 lies above every sample: the largest
    const DurationHistogram lat = DurationHistogram::latency();
    EXPECT_EQ(lat.bin_width_ms(), 0.25);
    EXPECT_EQ(lat.bin_lower_ms(1600), 400.0);  // the first coarse bin
    EXPECT_EQ(lat.bins().size(), 2000u);
    const nlohmann::json sj = histogram_json(slow);
    ASSERT_EQ(sj["bins"].size(), 3u);
    EXPECT_EQ(sj["bins"][1][0], 110.0);
    EXPECT_EQ(sj["bins"][2][0], 510.0);
    FrameTimings t;
    t.interval_ms.add(16.7);
    EXPECT_EQ(t.to_json()["interval_ms"]["count"], 1);
}

TEST(WindowContextOptions, RefusesUnknownExtensionsAndPresentWithoutPresentation) {
    gpu::ContextOptions o;
    o.instance_extensions = {"VK_KHR_no_such_extension"};
    try {
        (void)gpu::Context::create(o);
        ADD_FAILURE() << "an unknown instance extension was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("VK_KHR_no_such_extension"), std::string::npos) << e.what();
    }
    // A headless context: no presentation; queue_present refuses.
    gpu::Context ctx = gpu::Context::create({});
    EXPECT_FALSE(ctx.presentation_enabled());
    VkPresentInfoKHR info{};
    info.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR;
    EXPECT_THROW(ctx.queue_present(info), Error);
    // Presentation with a family filter that refuses everything: no device qualifies.
    gpu::ContextOptions none;
    none.presentation = true;
    none.can_present = [](VkInstance, VkPhysicalDevice, std::uint32_t) { return false; };
    EXPECT_THROW((void)gpu::Context::create(none), Error);
    // Presentation with the surface extension (offered by the loader on any desktop Linux) and no filter.
    gpu::ContextOptions surface;
    surface.instance_extensions = {"VK_KHR_surface"};
    surface.presentation = true;
    gpu::Context pc = gpu::Context::create(surface);
    EXPECT_TRUE(pc.presentation_enabled());
    EXPECT_EQ(pc.validation_messages(), 0u);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
