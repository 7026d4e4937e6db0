// haptics/passivity_observer.hpp - time-domain passivity observer and controller (Hannaford & Ryu 2002).
#pragma once

#include "core/math.hpp"

namespace tridex::haptics {

/// Passivity observer / controller for the virtual environment seen as a one-port, after Hannaford &
/// Ryu, "Time-Domain Passivity Control of Haptic Interfaces" (IEEE Trans. Robotics and Automation,
/// 2002), sections II-III.
///
/// Sign convention: F is the force the device applies to the user's hand (N), x the stylus position
/// (m), v its velocity (m/s), all in one frame. The energy the virtual environment has absorbed from
/// the user is E = -(work done by F on the stylus) (J): pushing into a wall (F opposes the motion)
/// raises E, being pushed back out lowers it. A passive environment keeps E >= 0; E < 0 means the
/// environment (the sampled wall, its hold and delay) has created energy.
///
/// Books: the force sent at tick k-1 is held until tick k (zero-order hold), so the work it did is
/// exactly F(k-1).(x(k) - x(k-1)); book() adds -F(k-1).(x(k) - x(k-1)) to E. This is the
/// displacement form of Hannaford & Ryu's E(n) = -dt * sum F(k).v(k): the same quantity without the
/// velocity-sampling error, which at 1 kHz is as large as the energy being watched (an impact's
/// pre-contact velocity times the first contact force). Torque work is not counted (no angular
/// velocity is sensed).
///
/// Controller (when used): before a force F goes out, the books are predicted one tick ahead with the
/// sensed velocity, E_pre = E - dt * F.v; if E_pre < 0 and v != 0 the controller adds the damping
/// alpha = -E_pre / (v.v * dt) (capped at max_damping), i.e. sends F - alpha * v, which is predicted to
/// dissipate exactly the deficit during the hold (Hannaford & Ryu's variable damper, impedance case).
/// The caller clamps the result and books the force actually sent on the next tick.
/// All calls are allocation-free and O(1).
class PassivityObserver {
public:
    /// max_damping_n_s_per_m: cap on alpha, N*s/m (> 0; the caller validates).
    explicit PassivityObserver(double max_damping_n_s_per_m = 20.0) : max_alpha_(max_damping_n_s_per_m) {}

    /// The controller's force for this tick: force_n - alpha * velocity_m_s (N), alpha as above, or
    /// force_n unchanged when no correction is due (E_pre >= 0, v = 0, dt not > 0, non-finite input).
    /// Does not change the observer; last_alpha() gives alpha.
    Vec3 control(const Vec3& force_n, const Vec3& velocity_m_s, double dt_s);
    /// Books the work of a held force: E -= force_held_n . displacement_m (N, m -> J), with force_held_n
    /// the force sent at the previous tick and displacement_m the stylus motion since then.
    /// Non-finite inputs are ignored.
    void book(const Vec3& force_held_n, const Vec3& displacement_m);
    /// Forgets the energy (E = 0) and the extremes.
    void reset();

    /// E, J (see the sign convention).
    double energy_j() const { return energy_; }
    /// The lowest E seen since reset, J (<= 0).
    double min_energy_j() const { return min_energy_; }
    /// The damping the last control() call asked for, N*s/m (0 when none).
    double last_alpha() const { return last_alpha_; }

private:
    double max_alpha_;
    double energy_ = 0.0;
    double min_energy_ = 0.0;
    double last_alpha_ = 0.0;
};

}  // namespace tridex::haptics
