// tests/haptics/loop_fixture.hpp - helpers for running the haptic loop against a simulated device.
#pragma once

#include <chrono>
#include <utility>
#include <thread>

#include "core/active_surface.hpp"
#include "core/triple_buffer.hpp"
#include "devices/simulated_device.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::test {

/// Publishes a copy of `s` as the newest snapshot of `buffer`.
inline void publish(TripleBuffer<ActiveSurface>& buffer, const ActiveSurface& s) {
    buffer.back() = s;
    buffer.publish();
}

/// Waits up to timeout_s for the loop to end by itself; true when it did.
inline bool wait_until_stopped(const haptics::HapticLoop& loop, double timeout_s) {
    const auto t0 = std::chrono::steady_clock::now();
    while (loop.running()) {
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout_s) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
}

/// A SimulatedDevice behind faults of its clock, for the watchdog tests (read numbers are 1-based):
/// - freeze: reads freeze_from .. freeze_from + freeze_count - 1 return a copy of the last sample before
///   them (a frozen driver: same time stamp, same pose) while the simulation keeps stepping;
/// - stall: read stall_at first steps the simulation stall_steps extra times (the loop missed those
///   samples: the device ran on the force last written), so its time stamp jumps by (stall_steps+1)*dt.
class ClockFaultDevice : public devices::HapticDevice {
public:
    explicit ClockFaultDevice(devices::SimulatedDevice& inner) : inner_(inner) {}
    const devices::DeviceProfile& profile() const override { return inner_.profile(); }
    bool read(devices::DeviceState& out) override {
        ++reads_;
        if (stall_at > 0 && reads_ == stall_at)
            for (std::size_t i = 0; i < stall_steps; ++i)
                if (!inner_.read(out)) return false;
        devices::DeviceState fresh;
        if (!inner_.read(fresh)) return false;
        const bool frozen = freeze_from > 0 && reads_ >= freeze_from && reads_ < freeze_from + freeze_count;
        if (!frozen) last_ = fresh;
        out = last_;
        return true;
    }
    void write(const Vec3& force_n, const Vec3& torque_nm) override { inner_.write(force_n, torque_nm); }

    std::size_t freeze_from = 0, freeze_count = 0;  ///< stale-data fault (0 = off)
    std::size_t stall_at = 0, stall_steps = 0;      ///< stall fault (0 = off)

private:
    devices::SimulatedDevice& inner_;
    devices::DeviceState last_;
    std::size_t reads_ = 0;
};

/// A device whose sample the test sets directly (position, velocity, buttons); each read advances its
/// time stamp by dt_s. Records every write. No dynamics: the written force moves nothing.
class PoseDevice : public devices::HapticDevice {
public:
    explicit PoseDevice(devices::DeviceProfile profile, double dt_s = 1e-3) : profile_(std::move(profile)), dt_(dt_s) {}
    const devices::DeviceProfile& profile() const override { return profile_; }
    bool read(devices::DeviceState& out) override {
        ++reads_;
        state.t_s = static_cast<double>(reads_) * dt_;
        out = state;
        return true;
    }
    void write(const Vec3& force_n, const Vec3& torque_nm) override {
        force = force_n;
        torque = torque_nm;
        ++writes;
    }

    devices::DeviceState state;  ///< the next sample (t_s is overwritten by read())
    Vec3 force{0.0};             ///< last force written, N
    Vec3 torque{0.0};            ///< last torque written, N*m
    std::size_t writes = 0;      ///< number of writes

private:
    devices::DeviceProfile profile_;
    double dt_;
    std::size_t reads_ = 0;
};

/// A stylus mass held by a virtual hand (a spring k_h to a fixed target and a damper b to the ground:
/// b is the device's physical damping of Colgate & Schenkel's model) under the force the loop writes,
/// integrated with `substeps` semi-implicit Euler steps per read while the written force is held: a
/// continuous plant sampled at the loop rate through a zero-order hold. (SimulatedDevice takes one
/// Euler step per read, which is symplectic for a sampled spring and so cannot show the energy the
/// hold creates.) Time stamps advance by dt per read; orientation is identity.
class ContinuousHandDevice : public devices::HapticDevice {
public:
    ContinuousHandDevice(devices::DeviceProfile profile, const Vec3& start_m, const Vec3& target_m, double mass_kg,
                         double hand_stiffness_n_per_m, double damping_n_s_per_m, double dt_s, int substeps)
        : profile_(std::move(profile)), x_(start_m), target_(target_m), m_(mass_kg), k_(hand_stiffness_n_per_m),
          b_(damping_n_s_per_m), dt_(dt_s), n_(substeps) {}
    const devices::DeviceProfile& profile() const override { return profile_; }
    bool read(devices::DeviceState& out) override {
        const double h = dt_ / n_;
        for (int i = 0; i < n_; ++i) {
            v_ += (h / m_) * (k_ * (target_ - x_) - b_ * v_ + force_);
            x_ += h * v_;
        }
        ++steps_;
        out.t_s = static_cast<double>(steps_) * dt_;
        out.pose.position = x_;
        out.velocity_m_s = v_;
        return true;
    }
    void write(const Vec3& force_n, const Vec3&) override { force_ = is_finite(force_n) ? force_n : Vec3(0.0); }

    const Vec3& position_m() const { return x_; }
    const Vec3& velocity_m_s() const { return v_; }
    /// Kinetic + hand-spring energy, J (add the wall's own spring energy yourself).
    double energy_j() const { return 0.5 * m_ * glm::dot(v_, v_) + 0.5 * k_ * glm::dot(target_ - x_, target_ - x_); }

private:
    devices::DeviceProfile profile_;
    Vec3 x_, v_{0.0}, target_, force_{0.0};
    double m_, k_, b_, dt_;
    int n_;
    std::size_t steps_ = 0;
};

}  // namespace tridex::test
