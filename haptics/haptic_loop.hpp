// haptics/haptic_loop.hpp - the 1 kHz haptic thread: device -> god-object -> filter -> clamp -> device.
#pragma once

#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

#include "core/active_surface.hpp"
#include "core/pose.hpp"
#include "core/spsc_ring.hpp"
#include "core/tool_sample.hpp"
#include "core/triple_buffer.hpp"
#include "devices/haptic_device.hpp"
#include "haptics/ewma_filter.hpp"
#include "haptics/god_object.hpp"

namespace tridex::haptics {

/// Settings of the haptic loop (SI units).
struct HapticLoopConfig {
    double period_s = 1e-3;        ///< tick period, s (1 kHz), in [1e-5, 0.1]
    ContactParams contact;         ///< god-object stiffness, damping, tool radius
    double ewma_alpha = 0.9;       ///< force filter weight a, [0, 1) (Peng et al.)
    Pose device_to_world;          ///< device frame -> world frame (unit quaternion)
    double workspace_scale = 1.0;  ///< world = device_to_world.apply(workspace_scale * device position), > 0
    ToolOp op = ToolOp::kSubtract; ///< Boolean carried by every ToolSample
    std::size_t max_ticks = 0;     ///< TickRecords preallocated (recording stops when full); 0 = none
};

/// What one tick did (world frame), for telemetry and tests.
struct TickRecord {
    double t_s = 0.0;          ///< tick start on the loop clock, s since start()
    Vec3 hip_m{0.0};           ///< HIP (tool centre) in the world, m; the last valid HIP on an invalid sample
    Vec3 proxy_m{0.0};         ///< god-object position, m
    Vec3 force_n{0.0};         ///< force sent to the device (after filter and clamp), world frame, N
    bool contact = false;      ///< the god-object was in contact
    float period_us = 0.0f;    ///< time since the previous tick's start, us (0 on the first tick)
    float compute_us = 0.0f;   ///< time from this tick's start to the end of its work, us
    bool valid_sample = true;  ///< false when the device sample had a non-finite value (zero force sent)
};

/// Counters of the loop; readable while it runs.
struct LoopStats {
    std::size_t ticks = 0;            ///< ticks that got a sample from the device
    std::size_t overruns = 0;         ///< ticks that ended after the next deadline (missed deadlines skipped)
    std::size_t samples_dropped = 0;  ///< ToolSamples not pushed because the ring was full
    std::size_t invalid_samples = 0;  ///< device samples with a non-finite value (zero force sent)
    bool device_lost = false;         ///< device.read() returned false (or threw) and the loop ended
};

/// The 1 kHz haptic thread (DESIGN.md, "three threads"). It ticks on absolute deadlines
/// (clock_nanosleep with TIMER_ABSTIME on CLOCK_MONOTONIC, the thread's timer slack set to 1 ns) and
/// measures its own period and compute time. Each tick:
///   device.read() -> validate (a non-finite time, pose or velocity sends zero force and is counted)
///   -> map device -> world (world = device_to_world.apply(scale * p)) -> newest ActiveSurface
///   (TripleBuffer::latest) -> GodObject (its damping dt is the step of the device's clock, t_s, or
///   period_s when that does not advance) -> clamp -> EwmaFilter (reset when non-finite) -> clamp to the profile's max force
///   -> device.write(conj(device_to_world.orientation) * F_world, zero torque)
///   -> push a ToolSample (device time, HIP, tool orientation, radius, op, buttons) to the ring
///   (when full, count a drop and go on: the next successful push just makes a longer segment)
///   -> store a TickRecord into the preallocated array (until it is full).
/// Inside the loop nothing allocates, locks or waits on another thread. When device.read() returns
/// false (or read/write throws), the loop writes zero force and ends by itself (device_lost). On every
/// exit it writes zero force last. The loop is the only reader of `surface`, the only producer of
/// `samples` and the only user of `device` while it runs; all three must outlive it.
class HapticLoop {
public:
    /// Checks the configuration; throws tridex::Error naming the HapticLoopConfig field at fault.
    /// Preallocates (and touches) cfg.max_ticks TickRecords.
    HapticLoop(devices::HapticDevice& device, TripleBuffer<ActiveSurface>& surface, SpscRing<ToolSample>& samples,
               HapticLoopConfig cfg);
    /// Stops the thread if it runs.
    ~HapticLoop();
    HapticLoop(const HapticLoop&) = delete;
    HapticLoop& operator=(const HapticLoop&) = delete;

    /// Starts the thread; a second call while it runs does nothing. A restart after stop() clears the
    /// records, the counters, the filter and the god-object.
    void start();
    /// Asks the thread to finish its tick, send zero force and exit, then joins. Idempotent.
    void stop();
    /// True from start() until the thread has exited (after stop(), or by itself on device loss).
    bool running() const { return running_.load(std::memory_order_acquire); }
    /// One record per tick, in order (at most max_ticks). Valid only after stop().
    const std::vector<TickRecord>& records() const { return records_; }
    /// The counters so far (each is read atomically; the set is not one snapshot while running).
    LoopStats stats() const;
    /// The configuration.
    const HapticLoopConfig& config() const { return cfg_; }

private:
    void run() noexcept;
    // One tick's work after a valid read (dt_s: contact damping time step); returns the record.
    TickRecord tick(const devices::DeviceState& state, double dt_s);

    devices::HapticDevice& device_;
    TripleBuffer<ActiveSurface>& surface_;
    SpscRing<ToolSample>& samples_;
    HapticLoopConfig cfg_;
    double max_force_n_;
    GodObject god_;
    EwmaFilter filter_;
    Quat world_to_device_;
    Vec3 last_hip_{0.0};
    std::vector<TickRecord> records_;
    std::size_t recorded_ = 0;
    std::thread thread_;
    std::atomic<bool> stop_requested_{false};
    std::atomic<bool> running_{false};
    std::atomic<std::size_t> ticks_{0}, overruns_{0}, dropped_{0}, invalid_{0};
    std::atomic<bool> device_lost_{false};
};

}  // namespace tridex::haptics
