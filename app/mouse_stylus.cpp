// app/mouse_stylus.cpp - cursor to tool target: pick, rest on the surface, press in while held.
#include "app/mouse_stylus.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/format.hpp"
#include "devices/mouse_device.hpp"

namespace tridex::app {

MouseStylus::MouseStylus(double tool_radius_m, const Vec3& aim_m)
    : radius_m_(tool_radius_m), depth_m_(tool_radius_m), depth_step_m_(0.1 * tool_radius_m), aim_m_(aim_m),
      last_hip_m_(aim_m) {
    if (!(std::isfinite(tool_radius_m) && tool_radius_m > 0.0))
        throw Error("MouseStylus: the tool radius must be finite and > 0, got " + format_number(tool_radius_m));
    if (!is_finite(aim_m)) throw Error("MouseStylus: the aim point must be finite");
}

void MouseStylus::set_cursor(double x_px, double y_px) {
    if (!std::isfinite(x_px) || !std::isfinite(y_px)) return;
    x_px_ = x_px;
    y_px_ = y_px;
    have_cursor_ = true;
}

void MouseStylus::wheel(double steps) {
    if (!std::isfinite(steps)) return;
    depth_m_ = std::clamp(depth_m_ + steps * depth_step_m_, 0.0, 2.0 * radius_m_);
}

void MouseStylus::set_op(ToolOp op) {
    if (op != ToolOp::kNone) op_ = op;
}

StylusTarget MouseStylus::update(const renderer::Screen& screen, const Vec3& eye_m, double width_px, double height_px,
                                 const PickSurface& live) {
    StylusTarget out;
    out.buttons = (left_ ? devices::mouse_buttons::kEngage : 0u) | (right_ ? devices::mouse_buttons::kStylus : 0u);
    if (left_ && !pressed_) pressed_ = live;  // the groove follows the surface as it was at the press
    if (!left_) pressed_.reset();
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
    const std::optional<SurfaceHit> hit = pick_surface(pressed_ ? *pressed_ : live, *ray);
    Vec3 hip;
    if (hit) {
        const double d = left_ ? depth_m_ : 0.0;
        hip = hit->point_m + (radius_m_ - d) * hit->normal;
        last_distance_m_ = hit->distance_m;
        out.on_surface = true;
    } else {
        // Off the model: hover at the last hit's distance (or the aim point's) along the new ray, a radius back.
        const double dist = last_distance_m_ > 0.0 ? last_distance_m_ : glm::length(aim_m_ - ray->origin_m);
        hip = ray->origin_m + std::max(0.0, dist - radius_m_) * ray->dir;
    }
    if (is_finite(hip)) last_hip_m_ = hip;
    out.hip_m = last_hip_m_;
    return out;
}

std::string MouseStylus::status() const {
    const char* name = tool_op_name(op_);
    return std::string("mouse stylus: ") + name + " (1/2/3/4/5), depth " + format_number(1e3 * depth_m_) +
           " mm (wheel), radius " + format_number(1e3 * radius_m_) + " mm" + (left_ ? ", engaged" : "") +
           (right_ ? ", stylus button" : "");
}

}  // namespace tridex::app
