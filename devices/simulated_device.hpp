// devices/simulated_device.hpp - a closed-loop virtual hand pushing a device mass along a scripted path.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "devices/button_script.hpp"
#include "devices/haptic_device.hpp"
#include "devices/scripted_orientation.hpp"
#include "devices/scripted_path.hpp"

namespace tridex::devices {

/// The virtual hand that holds the simulated stylus (SI units, documented defaults).
struct SimulatedHandParams {
    double mass_kg = 0.05;                 ///< moving mass of stylus + linkage, kg (> 0)
    double hand_stiffness_n_per_m = 300.0; ///< spring between the hand's target and the stylus, N/m (>= 0)
    double hand_damping_n_s_per_m = 4.0;   ///< damper on the target-minus-stylus velocity, N*s/m (>= 0)
    /// The device's own viscous friction to the ground, N*s/m (>= 0): the physical damping b of Colgate and
    /// Schenkel's sampled-wall analysis (a wall of stiffness K is passive when b > K*T/2).
    double device_damping_n_s_per_m = 0.0;
    /// Integration steps per read (1..1000), the written force held over all of them (zero-order hold).
    /// 1 = one semi-implicit Euler step per loop period, which is symplectic for a sampled spring and so
    /// hides the energy a sampled wall creates; 20-50 approximate the continuous plant.
    int substeps = 1;
    /// Rotational inertia of the stylus, kg*m^2 (> 0), isotropic (so no gyroscopic term), about the tip
    /// (the orientation is decoupled from the position). 1e-4: a pen-sized stylus of about 20 g and 0.12 m
    /// (m L^2 / 3 = 1e-4) with its share of the wrist linkage.
    double inertia_kg_m2 = 1e-4;
    /// Torsional spring of the grip pulling the stylus toward the hand's target orientation, N*m/rad (>= 0).
    /// 0.5: a 0.25 N*m torque (the wand's largest) turns a held stylus by 0.5 rad.
    double hand_torsion_stiffness_nm_per_rad = 0.5;
    /// Torsional damper on the target-minus-stylus angular velocity, N*m*s/rad (>= 0); 0.01 with the
    /// defaults above is a damping ratio of 0.71 (natural frequency 70.7 rad/s).
    double hand_torsion_damping_nm_s_per_rad = 0.01;
    /// The device's own rotational viscous friction to the ground, N*m*s/rad (>= 0).
    double device_torsion_damping_nm_s_per_rad = 0.0;
};

/// Faults a test can inject into a SimulatedDevice; 0 disables each one.
struct SimulatedFaults {
    std::size_t vanish_after_reads = 0;  ///< reads 1..N succeed, every later read returns false
    std::size_t nan_first_read = 0;      ///< the sample of this read (1-based) has a NaN position ...
    std::size_t nan_count = 1;           ///< ... and so do the next nan_count - 1 reads
};

/// What the simulated device's position sensor does to the true stylus position (Peng et al. section 5, Fig. 7: the
/// chattering the EWMA force filter removes comes from such measurement noise). Off by default (exact values).
struct SensorModel {
    /// Encoder step, m (> 0 quantises each axis to multiples of it; 0 = off). A PHANTOM Omni's specification sheet
    /// gives a nominal position resolution of more than 450 dpi, about 0.055 mm.
    double quantum_m = 0.0;
    double noise_std_m = 0.0;  ///< standard deviation of white Gaussian noise added per axis before quantising, m (>= 0)
    std::uint32_t seed = 1;    ///< seed of the noise (the same seed gives the same samples)
    /// true: the reported velocity is the finite difference of successive measured positions (as a device without
    /// a tachometer reports it); false: the true velocity. Only used when quantum_m or noise_std_m is set.
    bool differentiate_velocity = true;
    /// True when the model changes anything.
    bool active() const { return quantum_m > 0.0 || noise_std_m > 0.0; }
};

/// One step of the simulation, kept when tracing is enabled.
struct SimulatedTraceEntry {
    double t_s = 0.0;           ///< device time at the end of the step, s
    Vec3 position_m{0.0};       ///< stylus position after the step, m
    Vec3 velocity_m_s{0.0};     ///< stylus velocity after the step, m/s
    Vec3 target_m{0.0};         ///< hand target at the start of the step, m
    Vec3 device_force_n{0.0};   ///< force the device applied during the step (last write), N
    Vec3 hand_force_n{0.0};     ///< force the hand applied during the step (its last sub-step), N
    Quat orientation{1.0, 0.0, 0.0, 0.0};  ///< stylus orientation after the step (stylus -> device frame)
    Vec3 angular_velocity_rad_s{0.0};      ///< stylus angular velocity after the step, rad/s, device frame
    Quat target_orientation{1.0, 0.0, 0.0, 0.0};  ///< hand's target orientation at the start of the step
    Vec3 device_torque_nm{0.0};            ///< torque the device applied during the step (last write), N*m
    Vec3 hand_torque_nm{0.0};              ///< torque the hand applied during the step (its last sub-step), N*m
};

/// A virtual hand follows a ScriptedPath through a spring-damper (hand stiffness/damping) and pushes
/// a device mass m; forces written by the haptic loop act on that same mass, so the loop is closed:
///   m dv/dt = k_h (p_target(t) - x) + b_h (v_target(t) - v) - b_d v + F_written.
/// The stylus also turns: the hand holds it toward a target orientation (identity, or a
/// ScriptedOrientation set with set_orientation_path) through a torsional spring-damper, and the
/// written torque (device frame) acts on the same rotational inertia I (isotropic):
///   I dw/dt = k_r rotvec(q_target(t) q^-1) + b_r (w_target(t) - w) - b_dr w + tau_written,  dq/dt = [w] q / 2,
/// with w the angular velocity in the device frame and rotvec the shortest-arc rotation vector. Every
/// torque written is applied, on every axis, whatever the profile actuates (the haptic loop already maps
/// its wrench to the device's DOF).
/// read() advances these dynamics by one period dt (the loop period) with the force and torque last
/// written, in hand.substeps semi-implicit Euler steps of h = dt / substeps (v += h a(x, v, t); x += h v;
/// w += h alpha(q, w, t); q = exp(h w) q, renormalised; t += h), and returns the new pose and
/// velocity, so a run is deterministic whatever the wall-clock timing. The stylus starts at rest on
/// the path's position at t = 0 with identity orientation; with no orientation path and zero torque it
/// stays exactly at identity. The position is not limited to the profile's workspace. A non-finite
/// written force or torque is applied as zero.
/// Buttons: set_buttons() (interactive), or a ButtonScript in device time that overrides it.
/// Not thread-safe except set_buttons(): drive it from one thread, inspect it after that thread stopped.
class SimulatedDevice : public HapticDevice {
public:
    /// Throws tridex::Error naming the field when mass_kg or inertia_kg_m2 <= 0, a stiffness or damping is negative or
    /// non-finite, or dt_s is not in (0, 1] s.
    SimulatedDevice(DeviceProfile profile, ScriptedPath path, SimulatedHandParams hand = {}, double dt_s = 1e-3);

    const DeviceProfile& profile() const override { return profile_; }

protected:
    /// Advances one step of dt and returns the new state; false once the injected vanish fault fired.
    bool do_read(DeviceState& out) override;
    /// Stores the force (N) and torque (N*m), device frame, applied during the following steps.
    void do_write(const Vec3& force_n, const Vec3& torque_nm) override;

public:
    /// Sets the position sensor's quantisation and noise (call before the loop starts). Throws tridex::Error naming
    /// the field when quantum_m or noise_std_m is negative or not finite.
    void set_sensor(const SensorModel& sensor);
    /// The sensor model.
    const SensorModel& sensor() const { return sensor_; }
    /// Replaces the injected faults (call before the loop starts).
    void set_faults(const SimulatedFaults& faults) { faults_ = faults; }
    /// Sets the button bits reported by later reads when no button script is set; safe from any thread.
    void set_buttons(std::uint32_t bits) { buttons_.store(bits, std::memory_order_relaxed); }
    /// Scripts the buttons in device time: each read reports script.bits_at(t) at its own device time t
    /// (the sample's t_s), overriding set_buttons(). Call before the loop starts (not thread-safe).
    void set_button_script(ButtonScript script) { button_script_ = std::move(script); }
    /// Removes the button script: set_buttons() decides again. Call while the loop is stopped.
    void clear_button_script() { button_script_.reset(); }
    /// The button script, if one is set.
    const std::optional<ButtonScript>& button_script() const { return button_script_; }
    /// Makes the hand turn the stylus toward `path` (device time) instead of holding it at identity; the
    /// stylus is put at rest on the path's orientation at the current device time. Call before the loop
    /// starts (not thread-safe).
    void set_orientation_path(ScriptedOrientation path);
    /// The hand's orientation target, if one is set (else the hand holds identity).
    const std::optional<ScriptedOrientation>& orientation_path() const { return orientation_path_; }
    /// Keeps the first `capacity` steps in trace() (storage reserved here, so read() never allocates).
    void enable_trace(std::size_t capacity);

    /// Steps taken so far (each successful read is one step).
    std::size_t steps() const { return steps_; }
    /// Number of read() calls, failed ones included.
    std::size_t reads() const { return reads_; }
    /// Number of write() calls.
    std::size_t writes() const { return writes_; }
    /// The last force written, N (as commanded, before any non-finite check).
    const Vec3& last_force_n() const { return last_force_; }
    /// The last torque written, N*m.
    const Vec3& last_torque_nm() const { return last_torque_; }
    /// Current device time, s.
    double time_s() const { return t_; }
    /// Current stylus position, m.
    const Vec3& position_m() const { return x_; }
    /// Current stylus velocity, m/s.
    const Vec3& velocity_m_s() const { return v_; }
    /// Current stylus orientation (stylus -> device frame), unit quaternion.
    const Quat& orientation() const { return q_; }
    /// Current stylus angular velocity, rad/s, device frame.
    const Vec3& angular_velocity_rad_s() const { return w_; }
    /// Kinetic energy (translation and rotation) plus the hand springs' energy toward the current targets
    /// (0.5 k_h |d|^2 + 0.5 k_r theta^2, theta the angle to the target orientation), J (a wall's own spring
    /// energy is the caller's to add).
    double energy_j() const;
    /// The hand's target path.
    const ScriptedPath& path() const { return path_; }
    /// The hand parameters.
    const SimulatedHandParams& hand() const { return hand_; }
    /// The recorded steps (see enable_trace).
    const std::vector<SimulatedTraceEntry>& trace() const { return trace_; }

private:
    // The hand's target orientation at device time t_s (identity without an orientation path).
    Quat target_orientation(double t_s) const;

    DeviceProfile profile_;
    ScriptedPath path_;
    SimulatedHandParams hand_;
    double dt_;
    SimulatedFaults faults_;
    std::atomic<std::uint32_t> buttons_{0};
    std::optional<ButtonScript> button_script_;
    double t_ = 0.0;
    Vec3 x_{0.0}, v_{0.0};
    Vec3 last_force_{0.0}, last_torque_{0.0};
    Vec3 applied_force_{0.0};
    std::optional<ScriptedOrientation> orientation_path_;
    Quat q_{1.0, 0.0, 0.0, 0.0};
    Vec3 w_{0.0};
    Vec3 applied_torque_{0.0};
    std::size_t steps_ = 0, reads_ = 0, writes_ = 0;
    bool vanished_ = false;
    std::vector<SimulatedTraceEntry> trace_;
    SensorModel sensor_;
    std::mt19937 noise_rng_{1};
    std::normal_distribution<double> noise_{0.0, 1.0};
    Vec3 prev_measured_{0.0};
    bool have_measured_ = false;
    std::size_t trace_capacity_ = 0;
};

}  // namespace tridex::devices
