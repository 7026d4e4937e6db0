// haptics/safety.cpp - clamps, gate, ramp-in and passivity, in that order.
#include "haptics/safety.hpp"

#include "haptics/forces/force_clamp.hpp"

namespace tridex::haptics {

SafetyStage::SafetyStage(const SafetyLimits& limits, const SafetyConfig& cfg, bool passivity_control)
    : limits_(limits),
      control_(passivity_control),
      ramp_(cfg.ramp_s),
      passivity_(cfg.max_passivity_damping_n_s_per_m) {}

void SafetyStage::reset() {
    ramp_.reset();
    passivity_.reset();
    ramp_pending_ = true;
    have_prev_ = false;
}

SafetyOutput SafetyStage::apply(const Vec3& force_n, const Vec3& torque_nm, const Vec3& x, const Vec3& v,
                                double device_t_s, double dt_s, bool watchdog_allows) {
    if (have_prev_) passivity_.book(prev_force_, x - prev_position_);
    SafetyOutput out;
    out.over_speed = limits_.over_speed(v);
    out.enabled = watchdog_allows && !out.over_speed;
    if (out.enabled) {
        if (ramp_pending_) {
            ramp_.restart(device_t_s);
            ramp_pending_ = false;
        }
        out.ramp = ramp_.scale(device_t_s);
        out.force_n = out.ramp * clamp_magnitude(force_n, limits_.max_force_n);
        out.torque_nm = out.ramp * clamp_magnitude(torque_nm, limits_.max_torque_nm);
        if (control_) {
            out.force_n = clamp_magnitude(passivity_.control(out.force_n, v, dt_s), limits_.max_force_n);
            out.alpha = passivity_.last_alpha();
        }
    } else {
        ramp_pending_ = true;
    }
    prev_force_ = out.force_n;
    prev_position_ = x;
    have_prev_ = is_finite(x);
    return out;
}

}  // namespace tridex::haptics
