// haptics/wrench_output.cpp - device output limits and the world -> device wrench map with clamping.
#include "haptics/wrench_output.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "devices/device_profiles.hpp"

namespace tridex::haptics {

namespace {

bool finite_quat(const Quat& q) {
    return std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}

// Zeroes the components of v whose axis limit is not > 0, then scales v by one factor so that every
// |v_i| <= axis[i] and |v| <= max_norm. Inputs are finite.
Vec3 limit(Vec3 v, const Vec3& axis, double max_norm) {
    double s = 1.0;
    for (int i = 0; i < 3; ++i) {
        if (!(axis[i] > 0.0)) {
            v[i] = 0.0;
            continue;
        }
        const double a = std::abs(v[i]);
        if (a > axis[i]) s = std::min(s, axis[i] / a);
    }
    if (!(max_norm > 0.0)) return Vec3(0.0);
    const double n = glm::length(v);
    if (n > max_norm) s = std::min(s, max_norm / n);
    return s * v;
}

}  // namespace

OutputLimits output_limits(const devices::DeviceProfile& profile) {
    OutputLimits l;
    switch (profile.dof_out) {
        case 3: l.dof = OutputDof::k3; break;
        case 5: l.dof = OutputDof::k5; break;
        case 6: l.dof = OutputDof::k6; break;
        default:
            throw Error("DeviceProfile.dof_out = " + std::to_string(profile.dof_out) + " must be 3, 5 or 6 (" +
                        profile.name + ")");
    }
    const devices::AxisLimits a = devices::axis_limits(profile);  // checks the limits
    l.max_force_axis_n = a.max_force_n;
    l.max_force_n = profile.max_force_n;
    if (l.dof != OutputDof::k3) {
        l.max_torque_axis_nm = a.max_torque_nm;
        l.max_torque_nm = profile.max_torque_nm;
    }
    return l;
}

Wrench map_to_device(const Wrench& world, const Quat& world_to_device, const OutputLimits& limits) {
    const bool finite = is_finite(world.force_n) && is_finite(world.torque_nm) && finite_quat(world_to_device) &&
                        is_finite(limits.max_force_axis_n) && std::isfinite(limits.max_force_n) &&
                        is_finite(limits.max_torque_axis_nm) && std::isfinite(limits.max_torque_nm);
    if (!finite) return Wrench{};
    Wrench d;
    d.force_n = limit(world_to_device * world.force_n, limits.max_force_axis_n, limits.max_force_n);
    if (limits.dof == OutputDof::k3) return d;
    Vec3 torque_axis = limits.max_torque_axis_nm;
    if (limits.dof == OutputDof::k5) torque_axis.y = 0.0;  // the wand's roll axis is not actuated
    d.torque_nm = limit(world_to_device * world.torque_nm, torque_axis, limits.max_torque_nm);
    return d;
}

}  // namespace tridex::haptics
