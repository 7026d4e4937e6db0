// app/session/run/run_mouse.cpp - the mouse stylus's per-frame work in a run.
#include "app/session/run/run_mouse.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

namespace tridex::app {

namespace {
constexpr double kShownTolM = 5e-4;     // the tool is "there" within 0.5 mm of the target
constexpr double kMovedTolM = 1e-4;     // a target that moves less is not a new event
constexpr std::size_t kMaxPending = 256;
constexpr std::chrono::microseconds kAwaitStep{200};  // await_hand's polling step
}  // namespace

RunMouse::RunMouse(devices::MouseDevice& device, SessionRuntime& runtime, const ToolShape& tool, const Vec3& aim_m)
    : device_(device), runtime_(runtime), stylus_(tool, aim_m), map_(runtime.config().device_to_world),
      scale_(runtime.config().workspace_scale), centre_d_(runtime.profile().workspace_m.centre()), sent_tool_(tool) {
    map_start_m_ = map_.position;
    sent_op_ = runtime.config().op == ToolOp::kNone ? ToolOp::kSubtract : runtime.config().op;
    stylus_.set_op(sent_op_);
}

void RunMouse::apply_script(const CursorScript& script, double t_dev_s) {
    if (script.empty() || !std::isfinite(t_dev_s)) return;
    for (; wheel_next_ < script.points.size() && script.points[wheel_next_].t_s <= t_dev_s; ++wheel_next_)
        if (script.points[wheel_next_].wheel != 0.0) stylus_.wheel(script.points[wheel_next_].wheel);
    const CursorPoint p = script.at(t_dev_s);
    stylus_.set_cursor(p.x_px, p.y_px);
    stylus_.set_left((p.buttons & cursor_buttons::kLeft) != 0);
    stylus_.set_right((p.buttons & cursor_buttons::kRight) != 0);
}

void RunMouse::frame(const renderer::Screen& screen, const Vec3& eye_m, double width_px, double height_px,
                     const MeshFrame& mesh, const haptics::LoopView& lv, Clock::time_point now) {
    PickSurface surface;
    surface.tiles = mesh.tiles;
    surface.groups = mesh.groups;
    if (!mesh.tiled && !mesh.mesh.triangles.empty()) surface.whole = std::make_shared<const TriMesh>(mesh.mesh);
    surface.workpiece_pose = lv.workpiece_pose;
    frame(screen, eye_m, width_px, height_px, surface, lv, now);
}

void RunMouse::frame(const renderer::Screen& screen, const Vec3& eye_m, double width_px, double height_px,
                     const PickSurface& surface, const haptics::LoopView& lv, Clock::time_point now) {
    ++frame_;
    if (stylus_.op() != sent_op_) {
        sent_op_ = stylus_.op();
        runtime_.set_tool_op(sent_op_);
    }
    const ToolShape& tool = stylus_.tool();
    if (tool.radius_m != sent_tool_.radius_m || tool.length_m != sent_tool_.length_m) {
        sent_tool_ = tool;
        if (runtime_.set_tool(tool)) ++tool_changes_;
    }
    // The workspace box is the mapping while modelling runs (its centre is R (s c_d) + offset); while the
    // stylus button is held the box moves on its own, so the last mapping stays.
    if (lv.tick > 0 && !lv.modelling_paused && !stylus_.right() && is_finite(lv.box.position)) {
        map_.orientation = lv.box.orientation;
        map_.position = lv.box.position - lv.box.orientation * (scale_ * centre_d_);
    }
    std::optional<PickSurface> with_placed;  // the workpiece and the reference objects
    if (!placed_.empty()) {
        with_placed = surface;
        with_placed->placed = placed_;
    }
    const StylusTarget target = stylus_.update(screen, eye_m, width_px, height_px, with_placed ? *with_placed : surface);
    const Vec3 device_m = glm::conjugate(map_.orientation) * (target.hip_m - map_.position) / scale_;
    device_.set_hand(device_m, target.buttons, glm::conjugate(map_.orientation) * target.orientation);
    if (!have_target_ || glm::length(target.hip_m - last_target_) > kMovedTolM) {
        have_target_ = true;
        last_target_ = target.hip_m;
        ++targets_;
        if (pending_.size() >= kMaxPending) {
            pending_.pop_front();
            ++superseded_;
        }
        pending_.push_back({now, target.hip_m, lv.tick, frame_});
        target_new_ = lv.tick > 0;
    }
}

std::chrono::microseconds RunMouse::await_hand(std::chrono::microseconds limit) {
    if (!target_new_ || pending_.empty()) return std::chrono::microseconds(0);
    target_new_ = false;
    const auto start = Clock::now();
    const std::uint64_t set_tick = pending_.back().tick;
    const Vec3 target = pending_.back().hip_m;
    const double limit_s = std::chrono::duration<double>(limit).count();
    double last_gap = 0.0, last_t = 0.0;
    std::uint64_t last_tick = 0;
    for (;;) {
        const double waited_s = std::chrono::duration<double>(Clock::now() - start).count();
        const haptics::LoopView& lv = runtime_.latest_view();
        if (lv.tick >= set_tick + 2 && lv.tick != last_tick) {  // a view the loop made after it took the target
            const double gap = glm::length(lv.tool_world.position - target);
            if (gap <= kShownTolM) break;
            if (last_tick != 0) {
                // The tool's closing speed over loop time: stop once it holds (in contact, or the target refused)
                // or cannot reach the target within the limit at that speed.
                const double closing = (last_gap - gap) / (lv.t_s - last_t);
                if (!(closing > 0.0) || waited_s + (gap - kShownTolM) / closing > limit_s) break;
            }
            last_gap = gap;
            last_t = lv.t_s;
            last_tick = lv.tick;
        }
        if (waited_s >= limit_s) break;
        std::this_thread::sleep_for(std::min(kAwaitStep, std::chrono::duration_cast<std::chrono::microseconds>(
                                                             std::chrono::duration<double>(limit_s - waited_s))));
    }
    const auto waited = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start);
    waited_ms_.add(1e-3 * static_cast<double>(waited.count()));
    return waited;
}

void RunMouse::shown(const haptics::LoopView& lv, Clock::time_point now) {
    if (lv.tick == 0) return;
    const Vec3 tool = lv.tool_world.position;
    // The newest pending target the tool reached; the older ones were passed by.
    for (std::size_t i = pending_.size(); i-- > 0;) {
        if (lv.tick < pending_[i].tick + 2 || glm::length(tool - pending_[i].hip_m) > kShownTolM) continue;
        latency_ms_.add(std::chrono::duration<double, std::milli>(now - pending_[i].t).count());
        if (pending_[i].frame == frame_) ++same_frame_;
        superseded_ += i;
        pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(i) + 1);
        break;
    }
}

nlohmann::json RunMouse::report_json() const {
    const DurationHistogram& s = latency_ms_;
    const DurationHistogram& w = waited_ms_;
    const char* op = tool_op_name(sent_op_);
    return nlohmann::json{
        {"targets", targets_},
        {"latency_ms",
         {{"count", s.count()},
          {"median", s.percentile_ms(0.5)},
          {"p99", s.percentile_ms(0.99)},
          {"max", s.max_ms()},
          {"mean", s.mean_ms()}}},
        {"hand_wait_ms",
         {{"count", w.count()}, {"median", w.percentile_ms(0.5)}, {"p99", w.percentile_ms(0.99)}, {"max", w.max_ms()}}},
        {"same_frame", same_frame_},
        {"superseded", superseded_},
        {"unmatched", pending_.size()},
        {"rejected_targets", device_.rejected_targets()},
        {"op", op},
        {"depth_m", stylus_.depth_m()},
        {"tool",
         {{"shape", to_string(sent_tool_.kind)}, {"radius_m", sent_tool_.radius_m}, {"length_m", sent_tool_.length_m}}},
        {"tool_changes", tool_changes_},
        {"workspace_moved_m", glm::length(map_.position - map_start_m_)}};
}

}  // namespace tridex::app
