// devices/scripted_path.cpp - cubic Hermite interpolation with Catmull-Rom tangents.
#include "devices/scripted_path.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tridex::devices {

ScriptedPath::ScriptedPath(std::vector<double> t_s, std::vector<Vec3> positions_m)
    : t_(std::move(t_s)), p_(std::move(positions_m)) {
    if (t_.empty()) throw Error("ScriptedPath: no waypoints (t_s is empty)");
    if (t_.size() != p_.size())
        throw Error("ScriptedPath: t_s has " + std::to_string(t_.size()) + " entries but positions_m has " +
                    std::to_string(p_.size()));
    for (std::size_t i = 0; i < t_.size(); ++i) {
        if (!std::isfinite(t_[i])) throw Error("ScriptedPath: t_s[" + std::to_string(i) + "] is not finite");
        if (!is_finite(p_[i])) throw Error("ScriptedPath: positions_m[" + std::to_string(i) + "] is not finite");
        if (i > 0 && !(t_[i] > t_[i - 1]))
            throw Error("ScriptedPath: t_s[" + std::to_string(i) + "] = " + std::to_string(t_[i]) +
                        " does not increase (previous " + std::to_string(t_[i - 1]) + ")");
    }
    const std::size_t n = t_.size();
    m_.assign(n, Vec3(0.0));
    for (std::size_t i = 1; i + 1 < n; ++i) m_[i] = (p_[i + 1] - p_[i - 1]) / (t_[i + 1] - t_[i - 1]);
}

ScriptedPath ScriptedPath::hold(const Vec3& position_m) { return ScriptedPath({0.0}, {position_m}); }

std::size_t ScriptedPath::segment(double t) const {
    // First waypoint strictly after t, minus one.
    const auto it = std::upper_bound(t_.begin(), t_.end(), t);
    return static_cast<std::size_t>(it - t_.begin()) - 1;
}

Vec3 ScriptedPath::position_at(double t) const {
    if (!(t > t_.front())) return p_.front();  // also catches NaN
    if (t >= t_.back()) return p_.back();
    const std::size_t i = segment(t);
    const double h = t_[i + 1] - t_[i];
    const double s = (t - t_[i]) / h;
    const double s2 = s * s, s3 = s2 * s;
    // Cubic Hermite basis functions.
    const double h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    const double h10 = s3 - 2.0 * s2 + s;
    const double h01 = -2.0 * s3 + 3.0 * s2;
    const double h11 = s3 - s2;
    return h00 * p_[i] + (h10 * h) * m_[i] + h01 * p_[i + 1] + (h11 * h) * m_[i + 1];
}

Vec3 ScriptedPath::velocity_at(double t) const {
    if (!(t > t_.front()) || t >= t_.back()) return Vec3(0.0);
    const std::size_t i = segment(t);
    const double h = t_[i + 1] - t_[i];
    const double s = (t - t_[i]) / h;
    const double s2 = s * s;
    // Derivatives of the basis functions with respect to s; d/dt = (d/ds) / h.
    const double d00 = 6.0 * s2 - 6.0 * s;
    const double d10 = 3.0 * s2 - 4.0 * s + 1.0;
    const double d01 = -6.0 * s2 + 6.0 * s;
    const double d11 = 3.0 * s2 - 2.0 * s;
    return (d00 / h) * p_[i] + d10 * m_[i] + (d01 / h) * p_[i + 1] + d11 * m_[i + 1];
}

}  // namespace tridex::devices
