// haptics/forces/cutting_force.cpp - chip area of a ball tool and the specific-cutting-force reaction.
#include "haptics/forces/cutting_force.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tridex::haptics {

double chip_area_m2(double radius_m, double depth_m) {
    if (!(radius_m > 0.0) || !(depth_m > 0.0) || !std::isfinite(radius_m)) return 0.0;
    if (depth_m >= 2.0 * radius_m) return std::numbers::pi * radius_m * radius_m;
    const double c = radius_m - depth_m;  // distance from the ball's centre to the surface
    const double half_chord = std::sqrt(std::max(0.0, 2.0 * radius_m * depth_m - depth_m * depth_m));
    return radius_m * radius_m * std::acos(std::clamp(c / radius_m, -1.0, 1.0)) - c * half_chord;
}

Vec3 cutting_force(double k_c_n_per_m2, double radius_m, double depth_m, const Vec3& velocity_m_s,
                   const Vec3& normal, double fade_speed_m_s) {
    if (!std::isfinite(k_c_n_per_m2) || !std::isfinite(depth_m) || !is_finite(velocity_m_s) || !is_finite(normal) ||
        !(fade_speed_m_s > 0.0))
        return Vec3(0.0);
    const double speed = glm::length(velocity_m_s);
    if (!(speed > 0.0) || glm::dot(velocity_m_s, normal) > 0.0) return Vec3(0.0);
    const double area = chip_area_m2(radius_m, depth_m);
    const double fade = std::min(1.0, speed / fade_speed_m_s);
    return velocity_m_s * (-k_c_n_per_m2 * area * fade / speed);
}

}  // namespace tridex::haptics
