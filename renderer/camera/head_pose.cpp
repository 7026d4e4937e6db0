// renderer/camera/head_pose.cpp - fixed, scripted, tracked and keyboard/mouse head pose providers.
#include "renderer/camera/head_pose.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"

namespace tridex::renderer {
namespace {

void require_pose(const Pose& p, const std::string& what) {
    if (!is_finite(p.position)) throw Error(what + ": position must be finite (m)");
    if (!is_unit(p.orientation)) throw Error(what + ": orientation must be a unit quaternion");
}

std::string num(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

/// Linear position, shortest-arc slerp orientation between a (u = 0) and b (u = 1).
Pose interpolate(const Pose& a, const Pose& b, double u) {
    Quat qb = b.orientation;
    if (glm::dot(a.orientation, qb) < 0.0) qb = -qb;
    return Pose{a.position + u * (b.position - a.position), glm::normalize(glm::slerp(a.orientation, qb, u))};
}

}  // namespace

FixedHead::FixedHead(const Pose& pose) : pose_(pose) { require_pose(pose, "FixedHead"); }

Pose FixedHead::head_at(double) { return pose_; }

ScriptedHead::ScriptedHead(std::vector<HeadWaypoint> waypoints, bool loop)
    : waypoints_(std::move(waypoints)), loop_(loop) {
    if (waypoints_.empty()) throw Error("ScriptedHead: needs at least one waypoint");
    if (loop_ && waypoints_.size() < 2) throw Error("ScriptedHead: a looping script needs at least two waypoints");
    for (std::size_t i = 0; i < waypoints_.size(); ++i) {
        const std::string what = "ScriptedHead: waypoint " + std::to_string(i);
        if (!std::isfinite(waypoints_[i].t_s)) throw Error(what + ": t_s must be finite");
        require_pose(waypoints_[i].pose, what);
        if (i > 0 && !(waypoints_[i].t_s > waypoints_[i - 1].t_s))
            throw Error(what + ": t_s = " + num(waypoints_[i].t_s) + " s does not come after the previous waypoint (" +
                        num(waypoints_[i - 1].t_s) + " s)");
    }
}

Pose ScriptedHead::head_at(double t_s) {
    const double t0 = waypoints_.front().t_s, t1 = waypoints_.back().t_s;
    double t = t_s;
    if (loop_) {
        const double period = t1 - t0;
        t = t0 + (t - t0) - period * std::floor((t - t0) / period);
    }
    if (!(t > t0)) return waypoints_.front().pose;  // also NaN
    if (t >= t1) return waypoints_.back().pose;
    // First waypoint strictly after t; the segment is [k - 1, k].
    const auto it = std::upper_bound(waypoints_.begin(), waypoints_.end(), t,
                                     [](double v, const HeadWaypoint& w) { return v < w.t_s; });
    const HeadWaypoint& b = *it;
    const HeadWaypoint& a = *(it - 1);
    return interpolate(a.pose, b.pose, (t - a.t_s) / (b.t_s - a.t_s));
}

TrackerHead::TrackerHead(const Pose& fallback, double timeout_s) : fallback_(fallback), timeout_s_(timeout_s) {
    require_pose(fallback, "TrackerHead fallback");
    if (!std::isfinite(timeout_s) || !(timeout_s > 0.0))
        throw Error("TrackerHead: timeout_s must be finite and > 0 (got " + num(timeout_s) + ")");
    status_.age_s = std::numeric_limits<double>::infinity();
    status_.note = "no tracker sample yet; using the fallback head pose";
}

void TrackerHead::push(const Pose& pose, double t_s) {
    const double n = glm::length(pose.orientation);
    if (!is_finite(pose.position) || !std::isfinite(t_s) || !std::isfinite(n) || !(n > 0.0)) {
        rejected_.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    Sample& s = slot_.back();
    s.pose = Pose{pose.position, pose.orientation / n};
    s.t_s = t_s;
    s.valid = true;
    slot_.publish();
}

Pose TrackerHead::head_at(double t_s) {
    const Sample& s = slot_.latest();
    const bool was_tracked = status_.tracked;
    if (!s.valid) {
        status_.tracked = false;
        status_.age_s = std::numeric_limits<double>::infinity();
        status_.note = "no tracker sample yet; using the fallback head pose";
        return fallback_;
    }
    const double age = t_s - s.t_s;  // NaN for a NaN t_s: treated as stale
    status_.age_s = age < 0.0 ? 0.0 : age;
    if (status_.age_s <= timeout_s_) {
        status_.tracked = true;
        status_.note = "tracked";
        return s.pose;
    }
    status_.tracked = false;
    if (was_tracked) ++status_.fallbacks;
    status_.note = "tracker sample is " + num(status_.age_s) + " s old (timeout " + num(timeout_s_) +
                   " s); using the fallback head pose";
    return fallback_;
}

KeyboardMouseHead::KeyboardMouseHead(const Pose& home, double speed_m_per_s, double radians_per_pixel,
                                     const Aabb& limits_m)
    : home_(home), speed_(speed_m_per_s), rad_per_px_(radians_per_pixel), limits_(limits_m) {
    require_pose(home, "KeyboardMouseHead home");
    if (!std::isfinite(speed_m_per_s) || !(speed_m_per_s > 0.0))
        throw Error("KeyboardMouseHead: speed_m_per_s must be finite and > 0 (got " + num(speed_m_per_s) + ")");
    if (!std::isfinite(radians_per_pixel) || !(radians_per_pixel > 0.0))
        throw Error("KeyboardMouseHead: radians_per_pixel must be finite and > 0 (got " + num(radians_per_pixel) + ")");
    if (!limits_.empty() && !limits_.contains(home.position))
        throw Error("KeyboardMouseHead: the home position lies outside the limits box");
    // Yaw and pitch of the home gaze direction (-z of the head); any roll is dropped.
    const Vec3 f = home.orientation * Vec3(0.0, 0.0, -1.0);
    home_yaw_ = std::atan2(-f.x, -f.z);
    home_pitch_ = std::asin(std::clamp(f.y, -1.0, 1.0));
    reset();
}

void KeyboardMouseHead::key(MoveKey key, bool pressed) { held_[static_cast<int>(key)] = pressed; }

void KeyboardMouseHead::mouse_turn(double dx_px, double dy_px) {
    if (!std::isfinite(dx_px) || !std::isfinite(dy_px)) return;
    const double limit = 89.0 * std::acos(-1.0) / 180.0;
    yaw_ -= dx_px * rad_per_px_;
    pitch_ = std::clamp(pitch_ - dy_px * rad_per_px_, -limit, limit);
}

void KeyboardMouseHead::reset() {
    position_ = home_.position;
    yaw_ = home_yaw_;
    pitch_ = home_pitch_;
    std::fill(std::begin(held_), std::end(held_), false);
}

Pose KeyboardMouseHead::current() const {
    const Quat q = glm::angleAxis(yaw_, Vec3(0.0, 1.0, 0.0)) * glm::angleAxis(pitch_, Vec3(1.0, 0.0, 0.0));
    return Pose{position_, q};
}

Pose KeyboardMouseHead::head_at(double t_s) {
    double dt = 0.0;
    if (started_ && std::isfinite(t_s)) dt = std::max(0.0, t_s - last_t_);
    if (std::isfinite(t_s)) {
        last_t_ = t_s;
        started_ = true;
    }
    const Quat turn = glm::angleAxis(yaw_, Vec3(0.0, 1.0, 0.0));
    const Vec3 right = turn * Vec3(1.0, 0.0, 0.0), forward = turn * Vec3(0.0, 0.0, -1.0), up(0.0, 1.0, 0.0);
    const auto axis = [&](MoveKey plus, MoveKey minus) {
        return (held_[static_cast<int>(plus)] ? 1.0 : 0.0) - (held_[static_cast<int>(minus)] ? 1.0 : 0.0);
    };
    const Vec3 dir = axis(MoveKey::kRight, MoveKey::kLeft) * right + axis(MoveKey::kUp, MoveKey::kDown) * up +
                     axis(MoveKey::kForward, MoveKey::kBack) * forward;
    const double len = glm::length(dir);
    if (len > 0.0 && dt > 0.0) {
        position_ += (speed_ * dt / len) * dir;
        if (!limits_.empty()) position_ = glm::clamp(position_, limits_.lo, limits_.hi);
    }
    return current();
}

}  // namespace tridex::renderer
