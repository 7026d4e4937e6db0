// app/session/run_mouse.hpp - the mouse stylus in a `tridex run` frame: cursor to device target, the chosen op to the
// loop, and the cursor-to-tool latency.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/input/cursor_script.hpp"
#include "app/input/mouse_stylus.hpp"
#include "app/session/session_runtime.hpp"
#include "devices/mouse_device.hpp"

namespace tridex::app {

/// Drives a MouseDevice from a MouseStylus once per frame (render thread): the stylus target (world m) goes to
/// the device frame through the loop's current workspace mapping (the workspace box's pose while modelling
/// runs; frozen while the stylus button is held or modelling is paused, when the box is not the mapping), and
/// the stylus's op to the haptic loop. It also measures the cursor-to-tool latency: from the frame whose input
/// moved the target to the end of the first later frame that drew the tool within 0.5 mm of it (so at least one
/// frame: the frame that sets a target draws the loop's view from before it).
class RunMouse {
public:
    using Clock = std::chrono::steady_clock;

    /// `device` and `runtime` must outlive this; `tool` (the session's) and aim_m (world m) as MouseStylus.
    RunMouse(devices::MouseDevice& device, SessionRuntime& runtime, const ToolShape& tool, const Vec3& aim_m);

    /// The stylus the window's input (RunInput::use_stylus) or a script drives.
    MouseStylus& stylus() { return stylus_; }
    /// Offscreen: applies the scripted cursor at device time t_dev_s (position and buttons), and the wheel steps of
    /// every point reached since the last call (once each).
    void apply_script(const CursorScript& script, double t_dev_s);
    /// Once per frame, before drawing: hands a changed op or tool size to the loop, then the target from the cursor's ray (`screen` and cyclopean `eye_m` in the
    /// model's frame, the eye image width_px x height_px) against `mesh`, handed to the device; `lv` is the
    /// view this frame draws; `now` the frame's start.
    void frame(const renderer::Screen& screen, const Vec3& eye_m, double width_px, double height_px,
               const MeshFrame& mesh, const haptics::LoopView& lv, Clock::time_point now);
    /// The same against `surface` (e.g. the GPU contour read back, when the sculpt thread publishes no CPU mesh).
    void frame(const renderer::Screen& screen, const Vec3& eye_m, double width_px, double height_px,
               const PickSurface& surface, const haptics::LoopView& lv, Clock::time_point now);
    /// After the frame that drew `lv` was shown (presented or read back) at `now`: matches it to the pending
    /// targets for the latency.
    void shown(const haptics::LoopView& lv, Clock::time_point now);
    /// report.json `mouse`: {targets, latency_ms {count, median, p99, max, mean}, superseded, rejected_targets,
    /// op, depth_m, tool {shape, radius_m, length_m}, tool_changes (sizes the loop took), workspace_moved_m (how far
    /// the workspace mapping's origin moved in the world during the session, m: the right button's workspace moves)}.
    nlohmann::json report_json() const;

private:
    struct Pending {
        Clock::time_point t;
        Vec3 hip_m;
        std::uint64_t frame = 0;  // the frame whose input set it
    };

    devices::MouseDevice& device_;
    SessionRuntime& runtime_;
    MouseStylus stylus_;
    Pose map_;            // device -> world rotation and offset in use
    Vec3 map_start_m_{0.0};  // map_.position at the start
    double scale_ = 1.0;  // workspace scale
    Vec3 centre_d_{0.0};  // device workspace centre, m
    ToolOp sent_op_ = ToolOp::kSubtract;
    ToolShape sent_tool_{};
    std::uint64_t tool_changes_ = 0;
    bool have_target_ = false;
    Vec3 last_target_{0.0};
    std::deque<Pending> pending_;
    std::vector<double> latency_ms_;
    std::uint64_t targets_ = 0, superseded_ = 0;
    std::uint64_t frame_ = 0;  // frames so far (frame() calls)
    std::size_t wheel_next_ = 0;  // the first scripted point whose wheel steps were not turned yet
};

}  // namespace tridex::app
