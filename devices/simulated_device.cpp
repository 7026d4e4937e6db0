// devices/simulated_device.cpp - semi-implicit Euler for the hand + device mass.
#include "devices/simulated_device.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "devices/rotation_vector.hpp"

namespace tridex::devices {

namespace {

void require(bool ok, const char* field, double value, const char* rule) {
    if (!ok) throw Error(std::string("SimulatedDevice: ") + field + " = " + std::to_string(value) + " " + rule);
}

}  // namespace

SimulatedDevice::SimulatedDevice(DeviceProfile profile, ScriptedPath path, SimulatedHandParams hand, double dt_s)
    : profile_(std::move(profile)), path_(std::move(path)), hand_(hand), dt_(dt_s) {
    require(std::isfinite(hand_.mass_kg) && hand_.mass_kg > 0.0, "hand.mass_kg", hand_.mass_kg, "must be > 0");
    require(std::isfinite(hand_.hand_stiffness_n_per_m) && hand_.hand_stiffness_n_per_m >= 0.0,
            "hand.hand_stiffness_n_per_m", hand_.hand_stiffness_n_per_m, "must be finite and >= 0");
    require(std::isfinite(hand_.hand_damping_n_s_per_m) && hand_.hand_damping_n_s_per_m >= 0.0,
            "hand.hand_damping_n_s_per_m", hand_.hand_damping_n_s_per_m, "must be finite and >= 0");
    require(std::isfinite(hand_.device_damping_n_s_per_m) && hand_.device_damping_n_s_per_m >= 0.0,
            "hand.device_damping_n_s_per_m", hand_.device_damping_n_s_per_m, "must be finite and >= 0");
    require(std::isfinite(hand_.inertia_kg_m2) && hand_.inertia_kg_m2 > 0.0, "hand.inertia_kg_m2", hand_.inertia_kg_m2,
            "must be > 0");
    require(std::isfinite(hand_.hand_torsion_stiffness_nm_per_rad) && hand_.hand_torsion_stiffness_nm_per_rad >= 0.0,
            "hand.hand_torsion_stiffness_nm_per_rad", hand_.hand_torsion_stiffness_nm_per_rad, "must be finite and >= 0");
    require(std::isfinite(hand_.hand_torsion_damping_nm_s_per_rad) && hand_.hand_torsion_damping_nm_s_per_rad >= 0.0,
            "hand.hand_torsion_damping_nm_s_per_rad", hand_.hand_torsion_damping_nm_s_per_rad, "must be finite and >= 0");
    require(std::isfinite(hand_.device_torsion_damping_nm_s_per_rad) && hand_.device_torsion_damping_nm_s_per_rad >= 0.0,
            "hand.device_torsion_damping_nm_s_per_rad", hand_.device_torsion_damping_nm_s_per_rad,
            "must be finite and >= 0");
    require(hand_.substeps >= 1 && hand_.substeps <= 1000, "hand.substeps", hand_.substeps, "must be in [1, 1000]");
    require(std::isfinite(dt_) && dt_ > 0.0 && dt_ <= 1.0, "dt_s", dt_, "must be in (0, 1] s");
    x_ = path_.position_at(0.0);
}

void SimulatedDevice::set_orientation_path(ScriptedOrientation path) {
    orientation_path_ = std::move(path);
    q_ = orientation_path_->orientation_at(t_);
    w_ = Vec3(0.0);
}

void SimulatedDevice::set_sensor(const SensorModel& sensor) {
    require(std::isfinite(sensor.quantum_m) && sensor.quantum_m >= 0.0, "sensor.quantum_m", sensor.quantum_m,
            "must be finite and >= 0");
    require(std::isfinite(sensor.noise_std_m) && sensor.noise_std_m >= 0.0, "sensor.noise_std_m", sensor.noise_std_m,
            "must be finite and >= 0");
    sensor_ = sensor;
    noise_rng_.seed(sensor.seed);
    noise_.reset();
    have_measured_ = false;
}

void SimulatedDevice::enable_trace(std::size_t capacity) {
    trace_.clear();
    trace_.reserve(capacity);
    trace_capacity_ = capacity;
}

bool SimulatedDevice::do_read(DeviceState& out) {
    ++reads_;
    if (vanished_) return false;
    if (faults_.vanish_after_reads > 0 && reads_ > faults_.vanish_after_reads) {
        vanished_ = true;
        return false;
    }
    const Vec3 target = path_.position_at(t_);
    const Quat target_q = target_orientation(t_);
    const double h = dt_ / hand_.substeps;
    Vec3 hand_force(0.0), hand_torque(0.0);
    for (int i = 0; i < hand_.substeps; ++i) {
        const double t = t_ + i * h;
        hand_force = hand_.hand_stiffness_n_per_m * (path_.position_at(t) - x_) +
                     hand_.hand_damping_n_s_per_m * (path_.velocity_at(t) - v_);
        v_ += (h / hand_.mass_kg) * (hand_force - hand_.device_damping_n_s_per_m * v_ + applied_force_);
        x_ += h * v_;
        // The wrist: the same semi-implicit step on (q, w); w in the device frame, so q turns on the left.
        const Vec3 w_target = orientation_path_ ? orientation_path_->angular_velocity_at(t) : Vec3(0.0);
        hand_torque = hand_.hand_torsion_stiffness_nm_per_rad * rotation_vector(target_orientation(t) * glm::conjugate(q_)) +
                      hand_.hand_torsion_damping_nm_s_per_rad * (w_target - w_);
        w_ += (h / hand_.inertia_kg_m2) *
              (hand_torque - hand_.device_torsion_damping_nm_s_per_rad * w_ + applied_torque_);
        q_ = glm::normalize(quat_from_rotation_vector(h * w_) * q_);
    }
    ++steps_;
    t_ = static_cast<double>(steps_) * dt_;  // no drift from summing dt
    if (trace_.size() < trace_capacity_)
        trace_.push_back({t_, x_, v_, target, applied_force_, hand_force, q_, w_, target_q, applied_torque_, hand_torque});

    out.t_s = t_;
    out.pose.position = x_;
    out.pose.orientation = q_;
    out.velocity_m_s = v_;
    if (sensor_.active()) {
        Vec3 m = x_;
        for (int a = 0; a < 3; ++a) {
            if (sensor_.noise_std_m > 0.0) m[a] += sensor_.noise_std_m * noise_(noise_rng_);
            if (sensor_.quantum_m > 0.0) m[a] = sensor_.quantum_m * std::round(m[a] / sensor_.quantum_m);
        }
        if (sensor_.differentiate_velocity) out.velocity_m_s = have_measured_ ? (m - prev_measured_) / dt_ : Vec3(0.0);
        prev_measured_ = m;
        have_measured_ = true;
        out.pose.position = m;
    }
    out.buttons = button_script_ ? button_script_->bits_at(t_) : buttons_.load(std::memory_order_relaxed);
    if (faults_.nan_first_read > 0 && reads_ >= faults_.nan_first_read &&
        reads_ - faults_.nan_first_read < faults_.nan_count)
        out.pose.position = Vec3(std::numeric_limits<double>::quiet_NaN());
    return true;
}

Quat SimulatedDevice::target_orientation(double t_s) const {
    return orientation_path_ ? orientation_path_->orientation_at(t_s) : Quat(1.0, 0.0, 0.0, 0.0);
}

double SimulatedDevice::energy_j() const {
    const Vec3 d = path_.position_at(t_) - x_;
    const Vec3 theta = rotation_vector(target_orientation(t_) * glm::conjugate(q_));
    return 0.5 * hand_.mass_kg * glm::dot(v_, v_) + 0.5 * hand_.hand_stiffness_n_per_m * glm::dot(d, d) +
           0.5 * hand_.inertia_kg_m2 * glm::dot(w_, w_) +
           0.5 * hand_.hand_torsion_stiffness_nm_per_rad * glm::dot(theta, theta);
}

void SimulatedDevice::do_write(const Vec3& force_n, const Vec3& torque_nm) {
    ++writes_;
    last_force_ = force_n;
    last_torque_ = torque_nm;
    applied_force_ = is_finite(force_n) ? force_n : Vec3(0.0);
    applied_torque_ = is_finite(torque_nm) ? torque_nm : Vec3(0.0);
}

}  // namespace tridex::devices
