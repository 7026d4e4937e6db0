// haptics/safety_limits.hpp - safety settings, per-profile force/torque/velocity limits and the force ramp-in.
#pragma once

#include "core/math.hpp"
#include "devices/haptic_device.hpp"
#include "haptics/god_object.hpp"

namespace tridex::haptics {

/// Safety settings of the haptic loop (SI units; defaults documented per field). Checked by
/// validate_safety(); the loop calls it at construction.
struct SafetyConfig {
    /// Stylus speed limit, m/s (> 0). Above it the force and torque are cut to zero for that tick and
    /// ramp in again once the speed is back under the limit: an impedance device cannot be slowed
    /// safely by pushing harder, and a stylus that is let go of or an unstable oscillation moves faster
    /// than deliberate sculpting (tens of mm/s) or brisk free-space moves (below 1 m/s). Default 1.5 m/s
    /// (a judgement, not a device specification).
    double max_velocity_m_s = 1.5;
    /// Force ramp-in time, s (>= 0; 0 = none): force and torque are scaled by min(1, (t - t0)/ramp_s)
    /// of device time from the session's first valid sample, and again from every watchdog re-arm and
    /// over-speed recovery, so a session that starts with the tool in contact does not kick the hand.
    /// Default 0.05 s (50 ticks at 1 kHz).
    double ramp_s = 0.05;
    /// Watchdog: device time stamps that stop advancing for longer than this (loop clock), s, trip it.
    /// In (0, 0.01]; default 0.005 s, so the force is zero within 6 ms of the last fresh sample at 1 kHz.
    double stale_timeout_s = 0.005;
    /// Watchdog: a tick whose device-clock step exceeds stall_factor * period_s trips it (the loop or the
    /// device stalled). In [2, 10]; default 5 (5 ms at 1 kHz).
    double stall_factor = 5.0;
    /// Watchdog: after a trip, the samples must stay healthy this long (device time), s, before force is
    /// allowed again (then it ramps in). In [0, 1]; default 0.01 s.
    double rearm_s = 0.01;
    /// Passivity controller: the largest damping alpha it may add, N*s/m (> 0). Caps alpha = -E/(v.v*dt)
    /// when v is tiny (Hannaford & Ryu 2002 note the controller's sensitivity at low velocity). Default
    /// 20 N*s/m (alpha*dt/m = 0.4 for a 50 g stylus at 1 kHz: well inside the explicit-damping bound 2).
    double max_passivity_damping_n_s_per_m = 20.0;
};

/// Checks every SafetyConfig field; throws tridex::Error ("SafetyConfig.<field> = <v> must ...").
void validate_safety(const SafetyConfig& cfg);

/// The three magnitude limits the loop enforces for one device (SI units).
struct SafetyLimits {
    double max_force_n = 0.0;        ///< |F| limit, N (DeviceProfile::max_force_n)
    double max_torque_nm = 0.0;      ///< |tau| limit, N*m (DeviceProfile::max_torque_nm; 0 = no torque output)
    double max_velocity_m_s = 0.0;   ///< stylus speed limit, m/s (SafetyConfig::max_velocity_m_s)

    /// The limits for `profile` under `cfg`. Throws tridex::Error naming the profile field when
    /// max_force_n or max_torque_nm is negative or not finite, or the SafetyConfig field (validate_safety).
    static SafetyLimits from(const devices::DeviceProfile& profile, const SafetyConfig& cfg);
    /// True when the speed |v| (m/s) exceeds max_velocity_m_s, or v is not finite.
    bool over_speed(const Vec3& velocity_m_s) const;
};

/// The device's stiffness limit as a world contact stiffness, N/m. The device feels a world stiffness k as
/// k * device_gain (device_gain = workspace_scale * the mapping's force scale: 1 in kScaling, where forces are divided
/// by the scale, and the scale itself in the other modes), so the cap is profile.max_stiffness_n_per_m / device_gain.
/// The profile's value is the highest wall stiffness that stays stable at 1 kHz (Colgate's passivity bound
/// b > K*T/2 + |B|, DESIGN.md). +infinity when the profile gives no limit (max_stiffness_n_per_m not finite and > 0)
/// or device_gain is not finite and > 0.
double world_stiffness_cap_n_per_m(const devices::DeviceProfile& profile, double device_gain);

/// Cuts contact.stiffness_n_per_m and the stiffness of every entry of contact.materials (a new table; the old one
/// is not modified) to at most cap_n_per_m (N/m). Returns true when anything was cut.
bool cap_contact_stiffness(ContactParams& contact, double cap_n_per_m);

/// Linear force ramp-in on the device clock: scale(t) = clamp((t - t0) / ramp_s, 0, 1) after
/// restart(t0); 1 when ramp_s == 0; 0 before the first restart. Allocation-free.
class ForceRamp {
public:
    /// ramp_s: ramp time, s (>= 0, finite; the caller validates).
    explicit ForceRamp(double ramp_s = 0.0) : ramp_s_(ramp_s) {}
    /// Starts the ramp at device time t0_s (s).
    void restart(double t0_s) {
        t0_ = t0_s;
        started_ = true;
    }
    /// Forgets the start: scale() is 0 until the next restart().
    void reset() { started_ = false; }
    /// The factor in [0, 1] at device time t_s (s); 0 for a non-finite t_s.
    double scale(double t_s) const;
    /// True once restart() was called (since the last reset()).
    bool started() const { return started_; }

private:
    double ramp_s_;
    double t0_ = 0.0;
    bool started_ = false;
};

}  // namespace tridex::haptics
