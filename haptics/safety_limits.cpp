// haptics/safety_limits.cpp - safety configuration checks, limits from a device profile, the ramp.
#include "haptics/safety_limits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "core/error.hpp"

namespace tridex::haptics {

namespace {

void require(bool ok, const std::string& field, double value, const char* rule) {
    if (!ok) throw Error(field + " = " + std::to_string(value) + " " + rule);
}

bool in_range(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

}  // namespace

void validate_safety(const SafetyConfig& c) {
    require(std::isfinite(c.max_velocity_m_s) && c.max_velocity_m_s > 0.0, "SafetyConfig.max_velocity_m_s",
            c.max_velocity_m_s, "must be finite and > 0 m/s");
    require(in_range(c.ramp_s, 0.0, 10.0), "SafetyConfig.ramp_s", c.ramp_s, "must be in [0, 10] s");
    require(std::isfinite(c.stale_timeout_s) && c.stale_timeout_s > 0.0 && c.stale_timeout_s <= 0.01,
            "SafetyConfig.stale_timeout_s", c.stale_timeout_s, "must be in (0, 0.01] s");
    require(in_range(c.stall_factor, 2.0, 10.0), "SafetyConfig.stall_factor", c.stall_factor, "must be in [2, 10]");
    require(in_range(c.rearm_s, 0.0, 1.0), "SafetyConfig.rearm_s", c.rearm_s, "must be in [0, 1] s");
    require(std::isfinite(c.max_passivity_damping_n_s_per_m) && c.max_passivity_damping_n_s_per_m > 0.0,
            "SafetyConfig.max_passivity_damping_n_s_per_m", c.max_passivity_damping_n_s_per_m,
            "must be finite and > 0 N*s/m");
}

SafetyLimits SafetyLimits::from(const devices::DeviceProfile& profile, const SafetyConfig& cfg) {
    validate_safety(cfg);
    require(std::isfinite(profile.max_force_n) && profile.max_force_n >= 0.0,
            "DeviceProfile '" + profile.name + "' max_force_n", profile.max_force_n, "must be finite and >= 0");
    require(std::isfinite(profile.max_torque_nm) && profile.max_torque_nm >= 0.0,
            "DeviceProfile '" + profile.name + "' max_torque_nm", profile.max_torque_nm, "must be finite and >= 0");
    return SafetyLimits{profile.max_force_n, profile.max_torque_nm, cfg.max_velocity_m_s};
}

bool SafetyLimits::over_speed(const Vec3& v) const {
    if (!is_finite(v)) return true;
    return glm::dot(v, v) > max_velocity_m_s * max_velocity_m_s;
}

double world_stiffness_cap_n_per_m(const devices::DeviceProfile& profile, double device_gain) {
    const double k = profile.max_stiffness_n_per_m;
    if (!(std::isfinite(k) && k > 0.0) || !(std::isfinite(device_gain) && device_gain > 0.0))
        return std::numeric_limits<double>::infinity();
    return k / device_gain;
}

bool cap_contact_stiffness(ContactParams& contact, double cap_n_per_m) {
    bool cut = false;
    if (contact.stiffness_n_per_m > cap_n_per_m) {
        contact.stiffness_n_per_m = cap_n_per_m;
        cut = true;
    }
    if (contact.materials) {
        bool table_cut = false;
        auto table = std::make_shared<MaterialTable>(*contact.materials);
        for (int id = 0; id < MaterialTable::kSize; ++id) {
            Material m = (*table)[static_cast<std::uint8_t>(id)];
            if (m.stiffness_n_per_m > cap_n_per_m) {
                m.stiffness_n_per_m = cap_n_per_m;
                table->set(id, m);
                table_cut = true;
            }
        }
        if (table_cut) contact.materials = std::move(table);
        cut = cut || table_cut;
    }
    return cut;
}

double ForceRamp::scale(double t_s) const {
    if (!started_ || !std::isfinite(t_s)) return 0.0;
    if (ramp_s_ <= 0.0) return 1.0;
    return std::clamp((t_s - t0_) / ramp_s_, 0.0, 1.0);
}

}  // namespace tridex::haptics
