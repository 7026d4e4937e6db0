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

/// A loop that renders the contact as it is: a 2 mm ball at 700 N/m, no damping, no filter, no ramp-in, the
/// scaling workspace at gain 1 (the device frame is the world), no real-time request; carving subtracts.
inline haptics::HapticLoopConfig plain_plane_config() {
    haptics::HapticLoopConfig cfg;
    cfg.contact = haptics::ContactParams{700.0, 0.0, 0.002};
    cfg.op = ToolOp::kSubtract;
    cfg.workspace.mode = haptics::WorkspaceMode::kScaling;
    cfg.ewma_alpha = 0.0;     // no filter: the tick's force is the contact's
    cfg.safety.ramp_s = 0.0;  // full force from the first tick
    cfg.request_realtime = false;
    return cfg;
}

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

protected:
    void on_enable() override { inner_.bring_up(); }
    void on_disable() noexcept override { inner_.disable(); }
    bool do_read(devices::DeviceState& out) override {
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
    void do_write(const Vec3& force_n, const Vec3& torque_nm) override { inner_.write(force_n, torque_nm); }

public:
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

protected:
    bool do_read(devices::DeviceState& out) override {
        ++reads_;
        state.t_s = static_cast<double>(reads_) * dt_;
        out = state;
        return true;
    }
    void do_write(const Vec3& force_n, const Vec3& torque_nm) override {
        force = force_n;
        torque = torque_nm;
        ++writes;
    }

public:
    devices::DeviceState state;  ///< the next sample (t_s is overwritten by read())
    Vec3 force{0.0};             ///< last force written, N
    Vec3 torque{0.0};            ///< last torque written, N*m
    std::size_t writes = 0;      ///< number of writes

private:
    devices::DeviceProfile profile_;
    double dt_;
    std::size_t reads_ = 0;
};

}  // namespace tridex::test
