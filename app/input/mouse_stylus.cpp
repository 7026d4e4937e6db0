// app/input/mouse_stylus.cpp - cursor to tool target: pick, rest on the surface, press in while held.
#include "app/input/mouse_stylus.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/format.hpp"
#include "devices/mouse_device.hpp"

namespace tridex::app {

namespace {
ToolShape ball(double radius_m) {
    ToolShape t;
    t.kind = ToolKind::kBall;
    t.radius_m = radius_m;
    return t;
}
}  // namespace

MouseStylus::MouseStylus(double tool_radius_m, const Vec3& aim_m) : MouseStylus(ball(tool_radius_m), aim_m) {}

MouseStylus::MouseStylus(const ToolShape& tool, const Vec3& aim_m)
    : base_(tool), tool_(tool), radius_m_(tool.radius_m), depth_step_m_(0.1 * tool.radius_m),
      aim_m_(aim_m), last_hip_m_(aim_m) {
    if (!(std::isfinite(tool.radius_m) && tool.radius_m > 0.0))
        throw Error("MouseStylus: the tool radius must be finite and > 0, got " + format_number(tool.radius_m));
    validate_tool(tool, "MouseStylus: tool");
    if (!is_finite(aim_m)) throw Error("MouseStylus: the aim point must be finite");
}

double MouseStylus::rest_height_m(const Vec3& normal) const {
    if (tool_.kind != ToolKind::kFlatEnd) return radius_m_;  // a ball; a mesh tool: its bounding radius
    // The flat end's support distance toward -normal: its end disc (radius r about the +y axis) and its shank
    // (length L up the axis).
    const Vec3 n = glm::length(normal) > 0.0 ? glm::normalize(normal) : Vec3(0.0, 0.0, 1.0);
    const double c = std::clamp(-n.y, -1.0, 1.0);  // cos of the angle between the axis and -normal
    return std::max(0.0, tool_.length_m * c) + radius_m_ * std::sqrt(std::max(0.0, 1.0 - c * c));
}

bool MouseStylus::resize(int steps) {
    if (base_.kind == ToolKind::kMesh || steps == 0) return false;
    const int k = std::clamp(size_steps_ + steps, -kMaxSizeSteps, kMaxSizeSteps);
    if (k == size_steps_) return false;
    const double f = std::pow(kSizeStep, k);
    tool_.radius_m = base_.radius_m * f;
    if (base_.kind == ToolKind::kFlatEnd) tool_.length_m = base_.length_m * f;
    radius_m_ = tool_.radius_m;
    depth_step_m_ = 0.1 * radius_m_;  // the depth keeps its wheel steps, so its share of the radius
    size_steps_ = k;
    return true;
}

void MouseStylus::set_cursor(double x_px, double y_px) {
    if (!std::isfinite(x_px) || !std::isfinite(y_px)) return;
    x_px_ = x_px;
    y_px_ = y_px;
    have_cursor_ = true;
}

void MouseStylus::wheel(double steps) {
    if (!std::isfinite(steps)) return;
    const double total = wheel_rest_ + std::clamp(steps, -4.0 * kMaxDepthSteps, 4.0 * kMaxDepthSteps);
    const double whole = std::trunc(total);
    wheel_rest_ = total - whole;
    if (op_ == ToolOp::kPlace) {  // turns the held workpiece; a wheel with nothing held does nothing
        if (left_) turn_steps_ = (turn_steps_ + static_cast<int>(whole)) % static_cast<int>(360.0 / kTurnStepDeg);
        return;
    }
    depth_steps_ = std::clamp(depth_steps_ + static_cast<int>(whole), -kMaxDepthSteps, kMaxDepthSteps);
}

int MouseStylus::default_depth_steps(ToolOp op) {
    switch (op) {
    case ToolOp::kPaint: return 3;
    case ToolOp::kPush:
    case ToolOp::kSmooth:
    case ToolOp::kPull:
    case ToolOp::kGrab: return 5;
    case ToolOp::kPlace: return 0;  // held where it touches: the workpiece follows, nothing is pressed
    default: return 10;
    }
}

void MouseStylus::set_op(ToolOp op) {
    if (op == ToolOp::kNone || op == op_) return;
    op_ = op;
    depth_steps_ = default_depth_steps(op);
    wheel_rest_ = 0.0;
    grip_distance_m_ = -1.0;
    turn_steps_ = 0;
}

StylusTarget MouseStylus::update(const renderer::Screen& screen, const Vec3& eye_m, double width_px, double height_px,
                                 const PickSurface& live) {
    StylusTarget out;
    out.buttons = (left_ ? devices::mouse_buttons::kEngage : 0u) | (right_ ? devices::mouse_buttons::kStylus : 0u);
    if (left_ && !pressed_) pressed_ = live;  // the groove follows the surface as it was at the press
    if (!left_) {
        pressed_.reset();
        grip_distance_m_ = -1.0;
        turn_steps_ = 0;
    }
    out.hip_m = last_hip_m_;
    if (!have_cursor_) {
        out.hip_m = aim_m_;
        return out;
    }
    // A cursor past one eye's image (side-by-side or top-bottom windows) points into the other eye's copy.
    const double x = width_px > 0.0 && x_px_ >= width_px ? std::fmod(x_px_, width_px) : x_px_;
    const double y = height_px > 0.0 && y_px_ >= height_px ? std::fmod(y_px_, height_px) : y_px_;
    const std::optional<Ray> ray = cursor_ray(screen, eye_m, x, y, width_px, height_px);
    if (!ray) return out;
    if (op_ == ToolOp::kPlace && left_) {  // the workpiece follows: drag across the view at the grip's distance
        if (grip_distance_m_ < 0.0) grip_distance_m_ = glm::length(last_hip_m_ - ray->origin_m);
        const Vec3 hip = ray->origin_m + grip_distance_m_ * ray->dir;
        if (is_finite(hip)) last_hip_m_ = hip;
        out.hip_m = last_hip_m_;
        out.orientation = glm::angleAxis(glm::radians(kTurnStepDeg * turn_steps_), Vec3(0.0, 1.0, 0.0));
        return out;
    }
    const std::optional<SurfaceHit> hit = pick_surface(pressed_ ? *pressed_ : live, *ray);
    Vec3 hip;
    if (hit) {
        const double d = left_ ? depth_m() : 0.0;
        hip = hit->point_m + (rest_height_m(hit->normal) - d) * hit->normal;
        last_distance_m_ = hit->distance_m;
        out.on_surface = true;
    } else {
        // Off the model: hover at the last hit's distance (or the aim point's) along the new ray, a radius back.
        const double dist = last_distance_m_ > 0.0 ? last_distance_m_ : glm::length(aim_m_ - ray->origin_m);
        hip = ray->origin_m + std::max(0.0, dist - rest_height_m(-ray->dir)) * ray->dir;
    }
    if (is_finite(hip)) last_hip_m_ = hip;
    out.hip_m = last_hip_m_;
    return out;
}

std::string MouseStylus::status() const {
    const char* name = tool_op_name(op_);
    const std::string size = tool_.kind == ToolKind::kMesh
                                 ? "mesh tool (fixed size)"
                                 : std::string(to_string(tool_.kind)) + " r " + format_mm(radius_m_) + " ([ ])";
    return std::string("mouse stylus: ") + name + " (1/2/3/4/5/6/7/8), " + size + ", depth " + format_mm(depth_m()) +
           " (wheel)" + (left_ ? ", engaged" : "") + (right_ ? ", stylus button" : "");
}

}  // namespace tridex::app
