// devices/replay_device.hpp - a HapticDevice that plays recorded device samples back, one per read().
#pragma once

#include <atomic>
#include <cstddef>
#include <vector>

#include "devices/haptic_device.hpp"
#include "devices/recording.hpp"

namespace tridex::devices {

/// Plays a recording's device samples back in order, one per read(), exactly as recorded (bit for bit,
/// including samples with NaN that the live loop flagged invalid, so the replayed loop takes the same
/// branches). read() returns false after the last sample, and on every later call: the device
/// "vanishes" and the haptic loop ends the replayed session by itself. Samples are not paced in time:
/// the loop's own period paces them, and the device time t_s of each sample is the recorded one.
/// write() stores what the loop sent, for comparison with the live session; it never changes what is
/// played (a replay is open-loop). Storage for forces/torques is reserved in the constructor
/// (samples + kExtraWrites), so read() and write() never allocate; writes beyond that are counted but
/// not stored. Drive it from one thread; played() and writes() may be read from any thread, the vectors
/// only after the driving thread stopped.
class ReplayDevice : public HapticDevice {
public:
    /// Writes stored beyond one per sample (the loop's final zero-force writes).
    static constexpr std::size_t kExtraWrites = 16;

    /// `profile` is the device the session was recorded with (the caller looks it up, e.g. from
    /// RecordingHeader::device_name); `samples` are played in the given order. An empty list vanishes
    /// on the first read. Never throws for any sample values.
    ReplayDevice(DeviceProfile profile, std::vector<DeviceState> samples);

    const DeviceProfile& profile() const override { return profile_; }

protected:
    /// Copies the next recorded sample into out and returns true; false once all were played.
    bool do_read(DeviceState& out) override;
    /// Stores force_n (N) and torque_nm (N*m) as given (device frame), while capacity lasts.
    void do_write(const Vec3& force_n, const Vec3& torque_nm) override;

public:
    /// Samples handed out by read() so far (0 .. samples().size()).
    std::size_t played() const { return played_.load(std::memory_order_acquire); }
    /// True once a read() found no sample left.
    bool finished() const { return finished_.load(std::memory_order_acquire); }
    /// Number of write() calls, stored or not.
    std::size_t writes() const { return writes_.load(std::memory_order_acquire); }
    /// The forces written, in call order (N, device frame), at most samples().size() + kExtraWrites.
    const std::vector<Vec3>& forces_written() const { return forces_; }
    /// The torques written, in call order (N*m, device frame), same length as forces_written().
    const std::vector<Vec3>& torques_written() const { return torques_; }
    /// The samples being played.
    const std::vector<DeviceState>& samples() const { return samples_; }

private:
    DeviceProfile profile_;
    std::vector<DeviceState> samples_;
    std::vector<Vec3> forces_, torques_;
    std::size_t capacity_ = 0;  // forces/torques stored at most (reserved up front)
    std::atomic<std::size_t> played_{0};
    std::atomic<std::size_t> writes_{0};
    std::atomic<bool> finished_{false};
};

/// The device samples of a recording, in order (RecordedTick::device of every tick): the input of a
/// ReplayDevice.
std::vector<DeviceState> device_states(const Recording& recording);

}  // namespace tridex::devices
