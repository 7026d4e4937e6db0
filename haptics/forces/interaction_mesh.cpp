// haptics/forces/interaction_mesh.cpp - point force with the unit step, displayed force with the 1/cos(q) gain.
#include "haptics/forces/interaction_mesh.hpp"

#include <algorithm>
#include <cmath>

namespace tridex::haptics {

Vec3 mesh_point_force(double stiffness_n_per_m, double depth_m, const Vec3& inward_normal) {
    if (!(std::isfinite(stiffness_n_per_m) && std::isfinite(depth_m) && is_finite(inward_normal))) return Vec3(0.0);
    if (!(depth_m > 0.0)) return Vec3(0.0);  // unit step u(d_m)
    return (stiffness_n_per_m * depth_m) * inward_normal;
}

MeshForce display_mesh_force(const Vec3& sum_n, const Vec3& contact_normal) {
    MeshForce m;
    if (!is_finite(sum_n) || !is_finite(contact_normal)) return m;
    const double s = glm::length(sum_n);
    const double c = glm::length(contact_normal);
    if (!(s > 0.0) || !(c > 0.0) || !std::isfinite(s) || !std::isfinite(c)) return m;
    m.cos_q = glm::dot(sum_n / s, contact_normal / c);
    if (!(m.cos_q > 0.0)) return m;  // the sum points into the material: display nothing
    m.gain = 1.0 / std::max(m.cos_q, kMinCosQ);
    m.displayed_n = m.gain * sum_n;
    return m;
}

}  // namespace tridex::haptics
