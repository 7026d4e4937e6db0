// devices/scripted_orientation.cpp - slerp through timed unit quaternions.
#include "devices/scripted_orientation.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "devices/rotation_vector.hpp"

namespace tridex::devices {

namespace {

bool finite(const Quat& q) { return std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z); }

}  // namespace

ScriptedOrientation::ScriptedOrientation(std::vector<double> t_s, std::vector<Quat> orientations)
    : t_(std::move(t_s)), q_(std::move(orientations)) {
    if (t_.empty()) throw Error("ScriptedOrientation: no waypoints (t_s is empty)");
    if (t_.size() != q_.size())
        throw Error("ScriptedOrientation: t_s has " + std::to_string(t_.size()) + " entries but orientations has " +
                    std::to_string(q_.size()));
    for (std::size_t i = 0; i < t_.size(); ++i) {
        const std::string at = "[" + std::to_string(i) + "]";
        if (!std::isfinite(t_[i])) throw Error("ScriptedOrientation: t_s" + at + " is not finite");
        if (i > 0 && !(t_[i] > t_[i - 1]))
            throw Error("ScriptedOrientation: t_s" + at + " = " + std::to_string(t_[i]) + " does not increase (previous " +
                        std::to_string(t_[i - 1]) + ")");
        if (!finite(q_[i])) throw Error("ScriptedOrientation: orientations" + at + " is not finite");
        const double n = glm::length(q_[i]);
        if (!(std::abs(n - 1.0) <= 1e-6))
            throw Error("ScriptedOrientation: orientations" + at + " has |q| = " + std::to_string(n) + ", not 1");
        q_[i] = q_[i] / n;
        if (i > 0 && glm::dot(q_[i], q_[i - 1]) < 0.0) q_[i] = -q_[i];
    }
    w_.assign(t_.size(), Vec3(0.0));
    for (std::size_t i = 0; i + 1 < t_.size(); ++i) w_[i] = rotation_vector(q_[i + 1] * glm::conjugate(q_[i]));
}

ScriptedOrientation ScriptedOrientation::hold(const Quat& orientation) {
    return ScriptedOrientation({0.0}, {orientation});
}

std::size_t ScriptedOrientation::segment(double t) const {
    const auto it = std::upper_bound(t_.begin(), t_.end(), t);
    return static_cast<std::size_t>(it - t_.begin()) - 1;
}

Quat ScriptedOrientation::orientation_at(double t) const {
    if (!(t > t_.front())) return q_.front();  // also catches NaN
    if (t >= t_.back()) return q_.back();
    const std::size_t i = segment(t);
    const double s = (t - t_[i]) / (t_[i + 1] - t_[i]);
    return glm::normalize(quat_from_rotation_vector(s * w_[i]) * q_[i]);
}

Vec3 ScriptedOrientation::angular_velocity_at(double t) const {
    if (!(t > t_.front()) || t >= t_.back()) return Vec3(0.0);
    const std::size_t i = segment(t);
    return w_[i] / (t_[i + 1] - t_[i]);
}

}  // namespace tridex::devices
