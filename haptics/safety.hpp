// haptics/safety.hpp - the safety stage between the force filter and device.write().
#pragma once

#include "core/math.hpp"
#include "haptics/passivity_observer.hpp"
#include "haptics/safety_limits.hpp"

namespace tridex::haptics {

/// What the safety stage sends for one tick (the frame of its inputs, SI units).
struct SafetyOutput {
    Vec3 force_n{0.0};        ///< force to write, N: |F| <= max_force_n
    Vec3 torque_nm{0.0};      ///< torque to write, N*m: |tau| <= max_torque_nm
    bool enabled = false;     ///< false: the watchdog or the velocity limit held the output at zero
    bool over_speed = false;  ///< the stylus was faster than max_velocity_m_s
    double ramp = 0.0;        ///< ramp-in factor applied, [0, 1]
    double alpha = 0.0;       ///< damping the passivity controller added, N*s/m (0 when off or not needed)
};

/// The safety chain of the haptic loop, in order:
/// 1. clamp |F| to max_force_n and |tau| to max_torque_nm (clamp_magnitude: non-finite -> zero);
/// 2. gate: zero output when the watchdog forbids force or |v| > max_velocity_m_s (either one marks
///    the ramp for a restart);
/// 3. ramp-in: on the first allowed tick after a gated one (and on the session's first tick) the
///    ForceRamp restarts at that tick's device time; F and tau are scaled by its factor;
/// 4. passivity controller (when enabled and the output is allowed): F - alpha * v, clamped again
///    (Hannaford & Ryu 2002, see PassivityObserver);
/// 5. passivity observer: books the work of the force sent on the previous tick over the stylus
///    displacement since then, E -= F(k-1).(x(k) - x(k-1)), then remembers this tick's force (or, when
///    the caller reports it with sent(), the force the device really got after DOF mapping).
/// F, tau, x and v must be in one frame with physical (unscaled) lengths: the loop uses the device's
/// own position and velocity rotated into world axes (work is frame-independent).
/// apply() is allocation-free and O(1).
class SafetyStage {
public:
    /// limits: from SafetyLimits::from (already checked); cfg: the validated SafetyConfig (ramp and
    /// controller cap); passivity_control: enable step 4.
    SafetyStage(const SafetyLimits& limits, const SafetyConfig& cfg, bool passivity_control);

    /// One tick: the filtered force (N) and torque (N*m), the stylus position (m) and velocity (m/s),
    /// the sample's device time (s) and time step dt_s (s), and the watchdog's verdict.
    SafetyOutput apply(const Vec3& force_n, const Vec3& torque_nm, const Vec3& position_m, const Vec3& velocity_m_s,
                       double device_t_s, double dt_s, bool watchdog_allows);
    /// Tells the books what the device was actually sent this tick, in the frame of apply() (N): the force
    /// after the device profile's DOF mapping and per-axis limits (map_to_device), rotated back. Call after
    /// apply() on the same tick; the next tick books this force's work instead of apply()'s output.
    /// A non-finite force counts as zero (map_to_device sends zero then).
    void sent(const Vec3& force_n) { prev_force_ = is_finite(force_n) ? force_n : Vec3(0.0); }
    /// Marks a tick on which zero was sent without a valid sample: the ramp restarts afterwards and the
    /// books restart from the next valid position (the hold interval before this tick is not booked).
    void hold() {
        ramp_pending_ = true;
        have_prev_ = false;
    }
    /// New session: ramp pending, energy books at zero.
    void reset();

    /// The energy books.
    const PassivityObserver& passivity() const { return passivity_; }
    /// The limits in force.
    const SafetyLimits& limits() const { return limits_; }

private:
    SafetyLimits limits_;
    bool control_;
    ForceRamp ramp_;
    PassivityObserver passivity_;
    bool ramp_pending_ = true;
    bool have_prev_ = false;   // prev_force_/prev_position_ are valid
    Vec3 prev_force_{0.0};     // force sent on the previous tick, N
    Vec3 prev_position_{0.0};  // stylus position on the previous tick, m
};

}  // namespace tridex::haptics
