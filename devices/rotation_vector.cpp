// devices/rotation_vector.cpp - quaternion log and exp maps with small-angle care.
#include "devices/rotation_vector.hpp"

#include <cmath>

namespace tridex::devices {

Vec3 rotation_vector(const Quat& q_in) {
    const Quat q = q_in.w < 0.0 ? -q_in : q_in;  // shortest arc: w >= 0, angle in [0, pi]
    const Vec3 u(q.x, q.y, q.z);
    const double s = glm::length(u);
    if (s == 0.0) return Vec3(0.0);
    const double angle = 2.0 * std::atan2(s, q.w);
    return (angle / s) * u;
}

Quat quat_from_rotation_vector(const Vec3& v) {
    const double angle = glm::length(v);
    if (angle == 0.0) return Quat(1.0, 0.0, 0.0, 0.0);
    const double half = 0.5 * angle;
    const Vec3 u = (std::sin(half) / angle) * v;
    return Quat(std::cos(half), u.x, u.y, u.z);
}

}  // namespace tridex::devices
