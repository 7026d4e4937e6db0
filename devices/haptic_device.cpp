// devices/haptic_device.cpp - the device lifecycle and force gate, the Omni profile.
#include "devices/haptic_device.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/units.hpp"

namespace tridex::devices {

namespace {

// A force within this relative margin of the limit is not counted as cut (rounding in the loop's own clamp).
constexpr double kLimitSlack = 1e-9;

// v cut to magnitude `limit` (>= 0); `cut` set when it was longer.
Vec3 bounded(const Vec3& v, double limit, bool& cut) {
    const double n = glm::length(v);
    if (n <= limit * (1.0 + kLimitSlack)) return v;
    cut = true;
    return limit > 0.0 ? v * (limit / n) : Vec3(0.0);
}

}  // namespace

const char* to_string(DeviceLifecycle state) {
    switch (state) {
        case DeviceLifecycle::kClosed: return "closed";
        case DeviceLifecycle::kOpen: return "open";
        case DeviceLifecycle::kHomed: return "homed";
        case DeviceLifecycle::kEnabled: return "enabled";
    }
    return "unknown";
}

std::string fault_names(std::uint32_t faults) {
    static const std::pair<std::uint32_t, const char*> kNames[] = {
        {kFaultNotHomed, "not_homed"}, {kFaultOverTemperature, "over_temperature"}, {kFaultForceLimit, "force_limit"},
        {kFaultVanished, "vanished"},  {kFaultNonFinite, "non_finite_force"},       {kFaultIo, "io_error"}};
    std::string out;
    for (const auto& [bit, name] : kNames) {
        if (!(faults & bit)) continue;
        if (!out.empty()) out += ", ";
        out += name;
    }
    return out.empty() ? "none" : out;
}

HapticDevice::~HapticDevice() = default;

void HapticDevice::open() {
    if (state() != DeviceLifecycle::kClosed) return;
    on_open();
    set_state(DeviceLifecycle::kOpen);
}

void HapticDevice::home() {
    if (state() == DeviceLifecycle::kHomed || state() == DeviceLifecycle::kEnabled) return;
    open();
    on_home();
    set_state(DeviceLifecycle::kHomed);
}

void HapticDevice::enable() {
    const DeviceLifecycle s = state();
    if (s == DeviceLifecycle::kEnabled) return;
    if (s != DeviceLifecycle::kHomed) {
        raise_fault(kFaultNotHomed);
        throw Error(profile().name + ": cannot enable forces on a device that is " + to_string(s) +
                    " (not homed): home it first");
    }
    on_enable();
    set_state(DeviceLifecycle::kEnabled);
}

void HapticDevice::disable() noexcept {
    if (state() != DeviceLifecycle::kEnabled) return;
    try {
        do_write(Vec3(0.0), Vec3(0.0));
    } catch (...) {
        raise_fault(kFaultIo);
    }
    set_state(DeviceLifecycle::kHomed);
    on_disable();
}

void HapticDevice::close() noexcept {
    disable();
    if (state() == DeviceLifecycle::kClosed) return;
    on_close();
    set_state(DeviceLifecycle::kClosed);
}

void HapticDevice::bring_up() {
    home();
    enable();
}

bool HapticDevice::read(DeviceState& out) {
    if (do_read(out)) return true;
    raise_fault(kFaultVanished);
    return false;
}

void HapticDevice::write(const Vec3& force_n, const Vec3& torque_nm) {
    writes_.fetch_add(1, std::memory_order_relaxed);
    if (state() != DeviceLifecycle::kEnabled) {
        if (force_n != Vec3(0.0) || torque_nm != Vec3(0.0)) suppressed_.fetch_add(1, std::memory_order_relaxed);
        do_write(Vec3(0.0), Vec3(0.0));
        return;
    }
    const DeviceProfile& p = profile();
    if (!is_finite(force_n) || !is_finite(torque_nm)) {
        raise_fault(kFaultNonFinite);
        clamped_.fetch_add(1, std::memory_order_relaxed);
        do_write(Vec3(0.0), Vec3(0.0));
        return;
    }
    bool cut = false;
    const Vec3 f = bounded(force_n, p.max_force_n, cut);
    const Vec3 t = bounded(torque_nm, p.max_torque_nm, cut);
    if (cut) {
        raise_fault(kFaultForceLimit);
        clamped_.fetch_add(1, std::memory_order_relaxed);
    }
    do_write(f, t);
}

DeviceStatus HapticDevice::status() const {
    DeviceStatus s;
    s.state = state();
    s.faults = faults_.load(std::memory_order_acquire);
    s.writes = writes_.load(std::memory_order_relaxed);
    s.writes_suppressed = suppressed_.load(std::memory_order_relaxed);
    s.writes_clamped = clamped_.load(std::memory_order_relaxed);
    return s;
}

DeviceProfile DeviceProfile::phantom_omni() {
    DeviceProfile p;
    p.name = "PHANTOM Omni";
    const Vec3 half = 0.5 * Vec3(units::inch(6.4), units::inch(4.8), units::inch(2.8));
    p.workspace_m = Aabb{-half, half};
    p.max_force_n = 0.88;
    p.max_torque_nm = 0.0;
    p.max_stiffness_n_per_m = units::n_per_mm(0.7);
    p.dof_in = 6;
    p.dof_out = 3;
    return p;
}

}  // namespace tridex::devices
