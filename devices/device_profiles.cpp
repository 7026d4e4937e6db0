// devices/device_profiles.cpp - the Quanser 5-DOF wand and generic 6-DOF profiles, per-axis limits.
#include "devices/device_profiles.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/units.hpp"

namespace tridex::devices {

namespace {

constexpr const char* kWandName = "Quanser 5-DOF Haptic Wand";
const Vec3 kWandForceN(2.3, 2.1, 3.0);
const Vec3 kWandTorqueNm(0.230, 0.0, 0.250);  // 230 and 250 N*mm; y = roll, unactuated

void require_limit(const DeviceProfile& p, double v, const std::string& field) {
    if (!(std::isfinite(v) && v >= 0.0))
        throw Error("DeviceProfile '" + p.name + "'." + field + " = " + std::to_string(v) + " must be finite and >= 0");
}

Vec3 checked_axes(const DeviceProfile& p, const Vec3& v, const char* field) {
    for (int i = 0; i < 3; ++i) require_limit(p, v[i], std::string(field) + "[" + std::to_string(i) + "]");
    return v;
}

}  // namespace

DeviceProfile quanser_wand_5dof() {
    DeviceProfile p;
    p.name = kWandName;
    p.workspace_m = Aabb{Vec3(-0.240, 0.085, -0.215), Vec3(0.240, 0.335, 0.235)};  // Singapogu Table 1
    p.max_force_n = glm::length(kWandForceN);
    p.max_torque_nm = glm::length(kWandTorqueNm);
    p.max_stiffness_n_per_m = units::n_per_mm(0.7);
    p.dof_in = 5;
    p.dof_out = 5;
    p.max_force_axis_n = kWandForceN;
    p.max_torque_axis_nm = kWandTorqueNm;
    return p;
}

DeviceProfile generic_6dof() {
    DeviceProfile p;
    p.name = "Generic 6-DOF";
    p.workspace_m = Aabb{Vec3(-0.1), Vec3(0.1)};
    p.max_force_n = 3.0;
    p.max_torque_nm = 0.3;
    p.max_stiffness_n_per_m = 1000.0;
    p.dof_in = 6;
    p.dof_out = 6;
    return p;
}

DeviceProfile novint_falcon() {
    DeviceProfile p;
    p.name = "Novint Falcon";
    p.workspace_m = Aabb{Vec3(-0.04, -0.04, 0.075), Vec3(0.04, 0.04, 0.155)};
    p.max_force_n = 8.9;
    p.max_torque_nm = 0.0;
    p.max_stiffness_n_per_m = 1000.0;
    p.dof_in = 3;
    p.dof_out = 3;
    return p;
}

DeviceProfile tracked_tool_profile() {
    DeviceProfile p;
    p.name = "Tracked tool";
    p.workspace_m = Aabb{Vec3(-3.0, -0.5, -1.0), Vec3(3.0, 3.0, 4.0)};
    p.max_force_n = 0.0;
    p.max_torque_nm = 0.0;
    p.max_stiffness_n_per_m = 0.0;
    p.dof_in = 6;
    p.dof_out = 3;  // the loop's force path, bounded to 0 N: nothing reaches a stick without motors
    return p;
}

Vec3 home_position_m(const DeviceProfile& profile) {
    return profile.workspace_m.empty() ? Vec3(0.0) : profile.workspace_m.centre();
}

AxisLimits axis_limits(const DeviceProfile& profile) {
    require_limit(profile, profile.max_force_n, "max_force_n");
    require_limit(profile, profile.max_torque_nm, "max_torque_nm");
    AxisLimits a;
    a.max_force_n = profile.max_force_axis_n ? checked_axes(profile, *profile.max_force_axis_n, "max_force_axis_n")
                                             : Vec3(profile.max_force_n);
    const double t = profile.max_torque_nm;
    a.max_torque_nm = profile.max_torque_axis_nm
                          ? checked_axes(profile, *profile.max_torque_axis_nm, "max_torque_axis_nm")
                          : profile.dof_out >= 6 ? Vec3(t) : profile.dof_out == 5 ? Vec3(t, 0.0, t) : Vec3(0.0);
    return a;
}

}  // namespace tridex::devices
