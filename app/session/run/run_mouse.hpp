// app/session/run/run_mouse.hpp - the mouse stylus in a `tridex run` frame: cursor to device target, the chosen op to the
// loop, and the cursor-to-tool latency.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/input/cursor_script.hpp"
#include "app/input/mouse_stylus.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "core/duration_histogram.hpp"
#include "devices/mouse_device.hpp"

namespace tridex::app {

/// Drives a MouseDevice from a MouseStylus once per frame (render thread): the stylus target (world m) goes to
/// the device frame through the loop's current workspace mapping (the workspace box's pose while modelling
/// runs; frozen while the stylus button is held or modelling is paused, when the box is not the mapping), and
/// the stylus's op to the haptic loop. await_hand() then lets the loop take the new target before the frame reads
/// the view it draws, so the frame that moves the cursor can already draw the tool there. It also measures the
/// cursor-to-tool latency: from the start of the frame whose input moved the target to the end of the first frame
/// that drew a view the loop made after taking the target, with the tool within 0.5 mm of it.
class RunMouse {
public:
    using Clock = std::chrono::steady_clock;

    /// `device` and `runtime` must outlive this; `tool` (the session's) and aim_m (world m) as MouseStylus.
    RunMouse(devices::MouseDevice& device, SessionRuntime& runtime, const ToolShape& tool, const Vec3& aim_m);

    /// Meshes placed in the scene (its reference objects) that the cursor's ray picks beside the workpiece, so the
    /// tool rides on them too; the meshes must outlive this.
    void set_placed(std::vector<PlacedMesh> placed) { placed_ = std::move(placed); }
    /// The stylus the window's input (RunInput::use_stylus) or a script drives.
    MouseStylus& stylus() { return stylus_; }
    /// Offscreen: applies the scripted cursor at device time t_dev_s (position and buttons), and the wheel steps of
    /// every point reached since the last call (once each). A non-finite t_dev_s (a tick without a valid sample)
    /// changes nothing.
    void apply_script(const CursorScript& script, double t_dev_s);
    /// Once per frame, before drawing: hands a changed op or tool size to the loop, then the target from the
    /// cursor's ray (`screen` and cyclopean `eye_m` in the model's frame, the eye image width_px x height_px)
    /// against `mesh`, handed to the device; `lv` is the loop's newest view now (its workspace mapping and tick; the
    /// frame draws a later one, after await_hand()); `now` the frame's start.
    void frame(const renderer::Screen& screen, const Vec3& eye_m, double width_px, double height_px,
               const MeshFrame& mesh, const haptics::LoopView& lv, Clock::time_point now);
    /// The same against `surface` (e.g. the GPU contour read back, when the sculpt thread publishes no CPU mesh).
    void frame(const renderer::Screen& screen, const Vec3& eye_m, double width_px, double height_px,
               const PickSurface& surface, const haptics::LoopView& lv, Clock::time_point now);
    /// After frame(), before the frame reads the view it draws: while the target frame() set is new, sleeps in steps
    /// of 0.2 ms until a view the loop made after taking it (two ticks on) has the tool within 0.5 mm of it, or the
    /// tool stops closing in (held by material, or the target refused), or at its closing speed (the device glides
    /// at a bounded speed) it cannot get there within `limit`, or `limit` has passed: a stalled loop never holds
    /// the frame longer. Reads the runtime's latest_view(), so a view reference taken before this call must not be
    /// used after it. Returns the time waited (0 without a new target).
    std::chrono::microseconds await_hand(std::chrono::microseconds limit);
    /// After the frame that drew `lv` was shown (presented or read back) at `now`: matches it to the pending
    /// targets for the latency.
    void shown(const haptics::LoopView& lv, Clock::time_point now);
    /// report.json `mouse`: {targets, latency_ms {count, median, p99, max, mean}, hand_wait_ms {count, median, p99,
    /// max} (await_hand's waits for a new target), same_frame (targets drawn by the frame whose input set them),
    /// superseded, rejected_targets, op, depth_m, tool {shape, radius_m, length_m}, tool_changes (sizes the loop took), workspace_moved_m (how far
    /// the workspace mapping's origin moved in the world during the session, m: the right button's workspace moves)}.
    nlohmann::json report_json() const;

private:
    struct Pending {
        Clock::time_point t;
        Vec3 hip_m;
        std::uint64_t tick = 0;   // the loop's newest view when it was set: a view two ticks on was made after it
        std::uint64_t frame = 0;  // the frame whose input set it
    };

    devices::MouseDevice& device_;
    SessionRuntime& runtime_;
    MouseStylus stylus_;
    std::vector<PlacedMesh> placed_;  // the reference objects the ray also picks
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
    // Fixed-bin histograms, so a session of any length keeps bounded memory.
    DurationHistogram latency_ms_ = DurationHistogram::latency();  // per matched target, ms
    DurationHistogram waited_ms_ = DurationHistogram::fine();      // per await_hand() with a new target, ms
    std::uint64_t targets_ = 0, superseded_ = 0;
    std::uint64_t same_frame_ = 0;  // targets drawn by the frame whose input set them
    std::uint64_t frame_ = 0;  // frames so far (frame() calls)
    bool target_new_ = false;  // frame() set a new target that await_hand() has not seen reached yet
    std::size_t wheel_next_ = 0;  // the first scripted point whose wheel steps were not turned yet
};

}  // namespace tridex::app
