// A game controller in a session, through the registry's capabilities: the frame loop's per-frame poll reaches the
// driver on the calling thread, the sticks move the tool in the running haptic loop, and the driver's operation
// button, bound to op.next by the driver's capabilities (its default bindings), switches the tool's operation, one
// operation per press.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>
#include <vector>

#include "app/actions/bindings.hpp"
#include "app/commands/demo/demo.hpp"
#include "app/session/run/run_actions.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "app/scene/workpiece_source.hpp"
#include "devices/device_profiles.hpp"
#include "devices/gamepad/gamepad_device.hpp"

namespace tridex::app {
namespace {

devices::GamepadState reading(float left_x, bool y) {
    devices::GamepadState s;
    s.axes = {left_x, 0.0f, 0.0f, 0.0f, -1.0f, -1.0f};
    s.buttons = y ? 1u << devices::gamepad_button::kY : 0u;
    return s;
}

TEST(GamepadSession, SticksMoveTheToolAndTheOperationButtonSwitchesOps) {
    SessionSpec s;
    s.mesh_path = default_mesh_path();
    s.resolution = 48;
    s.device_driver = "gamepad";
    s.device = "omni";
    s.workspace_mode = "scaling";
    const devices::DeviceProfile profile = devices::profile_by_name(s.device);
    const Vec3 home = devices::home_position_m(profile);
    s.device_origin_m = s.workpiece_centre_m + Vec3(0.0, 0.0, 0.2) - home;  // the hand well in front of the bunny
    Workpiece wp = prepare_session_workpiece(s);
    // Frames 0..9 at rest, 10..39 right at full speed with Y pressed twice (frames 15-17 and 25-27).
    std::vector<devices::GamepadState> script{reading(0.0f, false)};  // the probe at open
    for (int f = 0; f < 40; ++f) {
        const bool y = (f >= 15 && f < 18) || (f >= 25 && f < 28);
        script.push_back(reading(f < 10 ? 0.0f : 1.0f, y));
    }
    auto device = std::make_unique<devices::GamepadDevice>(
        profile, home, s.period_s, devices::GamepadParams{},
        std::make_unique<devices::ScriptedGamepadSource>(script));
    RuntimeOptions ro;
    ro.sculpt.cpu = true;
    SessionRuntime rt(s, std::move(wp), std::move(device), s.device_origin_m + home, ro);
    rt.start();
    renderer::SceneNavigation nav;
    bool swap = false, ao = true;
    RunActions acts(&rt, nullptr, nav, nullptr, swap, ao, s.tool);
    HandControls hands(default_bindings("gamepad", driver_caps("gamepad")));
    std::vector<ToolOp> switched;
    Vec3 at_rest(0.0);
    for (int f = 0; f < 40; ++f) {
        rt.poll_device_frame();
        const ToolOp before = rt.tool_op();
        HandsFrame h;
        h.tool_fresh = rt.latest_view().tick > 0;
        h.tool_buttons = rt.latest_view().buttons;
        hands.frame(h, {}, acts);
        if (rt.tool_op() != before) switched.push_back(rt.tool_op());
        // Let the haptic loop read this frame's state a few times (and publish its view) before the next frame.
        for (const std::uint64_t t0 = rt.latest_view().tick; rt.latest_view().tick < t0 + 5;)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        if (f == 9) at_rest = rt.latest_view().tool_world.position;
    }
    const Vec3 moved = rt.latest_view().tool_world.position;
    rt.stop();
    // Two presses: subtract -> union -> paint, each press once however many frames it was held.
    ASSERT_EQ(switched.size(), 2u);
    EXPECT_EQ(switched[0], ToolOp::kUnion);
    EXPECT_EQ(switched[1], ToolOp::kPaint);
    // Thirty frames of full deflection moved the tool right (+x), at most at the maximum speed.
    EXPECT_GT(moved.x - at_rest.x, 0.001);
    EXPECT_LT(std::abs(moved.y - at_rest.y), 1e-6);
    EXPECT_EQ(rt.device_status().faults & devices::kFaultVanished, 0u);
}

}  // namespace
}  // namespace tridex::app
