// devices/replay_device.cpp - open-loop playback of recorded device samples.
#include "devices/replay_device.hpp"

#include <utility>

namespace tridex::devices {

ReplayDevice::ReplayDevice(DeviceProfile profile, std::vector<DeviceState> samples)
    : profile_(std::move(profile)), samples_(std::move(samples)) {
    capacity_ = samples_.size() + kExtraWrites;
    forces_.reserve(capacity_);
    torques_.reserve(capacity_);
}

bool ReplayDevice::do_read(DeviceState& out) {
    const std::size_t i = played_.load(std::memory_order_relaxed);
    if (i >= samples_.size()) {
        finished_.store(true, std::memory_order_release);
        return false;
    }
    out = samples_[i];
    played_.store(i + 1, std::memory_order_release);
    return true;
}

void ReplayDevice::do_write(const Vec3& force_n, const Vec3& torque_nm) {
    if (forces_.size() < capacity_) {
        forces_.push_back(force_n);
        torques_.push_back(torque_nm);
    }
    writes_.fetch_add(1, std::memory_order_acq_rel);
}

std::vector<DeviceState> device_states(const Recording& recording) {
    std::vector<DeviceState> out;
    out.reserve(recording.ticks.size());
    for (const RecordedTick& t : recording.ticks) out.push_back(t.device);
    return out;
}

}  // namespace tridex::devices
