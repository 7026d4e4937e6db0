// renderer/camera/scene_navigation.cpp - similarity transform of the scene driven by wand and mouse.
#include "renderer/camera/scene_navigation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace tridex::renderer {
namespace {

std::string num(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

bool finite(const Quat& q) {
    return std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}

Quat unit_or_throw(const Quat& q, const char* what) {
    const double n = glm::length(q);
    if (!finite(q) || !(n > 0.0)) throw Error(std::string(what) + ": rotation quaternion must be finite and non-zero");
    return q / n;
}

void require_finite(const Vec3& v, const char* what) {
    if (!is_finite(v)) throw Error(std::string(what) + " must be finite (m)");
}

}  // namespace

SceneNavigation::SceneNavigation(const Pose& start, double start_scale, double min_scale, double max_scale)
    : start_(start), start_scale_(start_scale), min_scale_(min_scale), max_scale_(max_scale) {
    require_finite(start.position, "SceneNavigation: start position");
    start_.orientation = unit_or_throw(start.orientation, "SceneNavigation: start");
    const bool ok = std::isfinite(min_scale) && std::isfinite(max_scale) && std::isfinite(start_scale) &&
                    min_scale > 0.0 && min_scale <= max_scale && start_scale >= min_scale && start_scale <= max_scale;
    if (!ok)
        throw Error("SceneNavigation: need finite 0 < min_scale <= start_scale <= max_scale (got " + num(min_scale) +
                    ", " + num(start_scale) + ", " + num(max_scale) + ")");
    reset();
}

Mat4 SceneNavigation::world_from_scene() const {
    Mat4 m = glm::mat4_cast(rotation_) * scale_;  // scales the rotation columns (and [3][3], fixed below)
    m[3] = glm::dvec4(translation_, 1.0);
    return m;
}

Mat4 SceneNavigation::scene_from_world() const {
    const Quat inv = glm::conjugate(rotation_);
    Mat4 m = glm::mat4_cast(inv) * (1.0 / scale_);
    m[3] = glm::dvec4((inv * -translation_) / scale_, 1.0);
    return m;
}

Vec3 SceneNavigation::to_world(const Vec3& p_scene) const { return rotation_ * (scale_ * p_scene) + translation_; }

Vec3 SceneNavigation::to_scene(const Vec3& p_world) const {
    return (glm::conjugate(rotation_) * (p_world - translation_)) / scale_;
}

void SceneNavigation::translate(const Vec3& d_world_m) {
    require_finite(d_world_m, "SceneNavigation::translate: d_world_m");
    translation_ += d_world_m;
}

void SceneNavigation::rotate(const Quat& rotation, const Vec3& pivot_world_m) {
    const Quat q = unit_or_throw(rotation, "SceneNavigation::rotate");
    require_finite(pivot_world_m, "SceneNavigation::rotate: pivot_world_m");
    // p' = q (p - pivot) + pivot applied after the current transform.
    rotation_ = glm::normalize(q * rotation_);
    translation_ = q * (translation_ - pivot_world_m) + pivot_world_m;
}

void SceneNavigation::rotate(const Vec3& axis, double angle_rad, const Vec3& pivot_world_m) {
    const double n = glm::length(axis);
    if (!is_finite(axis) || !(n > 0.0)) throw Error("SceneNavigation::rotate: axis must be finite and non-zero");
    if (!std::isfinite(angle_rad)) throw Error("SceneNavigation::rotate: angle_rad must be finite");
    rotate(glm::angleAxis(angle_rad, axis / n), pivot_world_m);
}

double SceneNavigation::scale(double factor, const Vec3& pivot_world_m) {
    if (!std::isfinite(factor) || !(factor > 0.0))
        throw Error("SceneNavigation::scale: factor must be finite and > 0 (got " + num(factor) + ")");
    require_finite(pivot_world_m, "SceneNavigation::scale: pivot_world_m");
    const double target = std::clamp(scale_ * factor, min_scale_, max_scale_);
    const double applied = target / scale_;
    // p' = f (p - pivot) + pivot applied after the current transform.
    translation_ = applied * (translation_ - pivot_world_m) + pivot_world_m;
    scale_ = target;
    return applied;
}

void SceneNavigation::wand_drag(const Pose& wand_before, const Pose& wand_after) {
    require_finite(wand_before.position, "SceneNavigation::wand_drag: wand_before position");
    require_finite(wand_after.position, "SceneNavigation::wand_drag: wand_after position");
    const Quat qb = unit_or_throw(wand_before.orientation, "SceneNavigation::wand_drag: wand_before");
    const Quat qa = unit_or_throw(wand_after.orientation, "SceneNavigation::wand_drag: wand_after");
    // D = after * before^-1: rotation qa qb^-1, translation pa - (qa qb^-1) pb.
    const Quat qd = glm::normalize(qa * glm::conjugate(qb));
    const Vec3 td = wand_after.position - qd * wand_before.position;
    rotation_ = glm::normalize(qd * rotation_);
    translation_ = qd * translation_ + td;
}

void SceneNavigation::reset() {
    translation_ = start_.position;
    rotation_ = start_.orientation;
    scale_ = start_scale_;
}

MouseNavigation MouseNavigation::for_screen(const Screen& screen, int width_px) {
    if (width_px < 1) throw Error("MouseNavigation::for_screen: width_px must be >= 1");
    const Vec3 right = screen.lower_right - screen.lower_left, up = screen.upper_left - screen.lower_left;
    if (!is_finite(right) || !is_finite(up) || !(glm::length(right) > 0.0) || !(glm::length(up) > 0.0))
        throw Error("MouseNavigation::for_screen: the screen corners are degenerate or not finite");
    MouseNavigation m;
    m.right_axis = glm::normalize(right);
    m.up_axis = glm::normalize(up);
    m.pivot_m = screen.lower_left + 0.5 * right + 0.5 * up;
    m.metres_per_pixel = glm::length(right) / width_px;
    return m;
}

void mouse_pan(SceneNavigation& nav, const MouseNavigation& mouse, double dx_px, double dy_px) {
    if (!std::isfinite(dx_px) || !std::isfinite(dy_px)) throw Error("mouse_pan: deltas must be finite (pixels)");
    nav.translate(mouse.metres_per_pixel * (dx_px * mouse.right_axis - dy_px * mouse.up_axis));
}

void mouse_orbit(SceneNavigation& nav, const MouseNavigation& mouse, double dx_px, double dy_px) {
    if (!std::isfinite(dx_px) || !std::isfinite(dy_px)) throw Error("mouse_orbit: deltas must be finite (pixels)");
    if (dx_px != 0.0) nav.rotate(mouse.up_axis, dx_px * mouse.radians_per_pixel, mouse.pivot_m);
    if (dy_px != 0.0) nav.rotate(mouse.right_axis, dy_px * mouse.radians_per_pixel, mouse.pivot_m);
}

double mouse_zoom(SceneNavigation& nav, const MouseNavigation& mouse, double steps) {
    if (!std::isfinite(steps)) throw Error("mouse_zoom: steps must be finite");
    if (!std::isfinite(mouse.scale_per_step) || !(mouse.scale_per_step > 0.0))
        throw Error("mouse_zoom: scale_per_step must be finite and > 0");
    return nav.scale(std::pow(mouse.scale_per_step, steps), mouse.pivot_m);
}

}  // namespace tridex::renderer
