// devices/gamepad/gamepad_device.cpp - rate control from a game controller's sticks, triggers and bumpers.
#include "devices/gamepad/gamepad_device.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "devices/rotation_vector.hpp"

namespace tridex::devices {
namespace {

void check_range(double v, double lo, double hi, bool lo_open, const char* name) {
    if (!std::isfinite(v) || v > hi || (lo_open ? v <= lo : v < lo))
        throw Error(std::string("gamepad: ") + name + " must be in " + (lo_open ? "(" : "[") + std::to_string(lo) + ", " +
                    std::to_string(hi) + "], got " + std::to_string(v));
}

// A reading's axes with malformed values (not finite, beyond +-1 by more than rounding) set to their rest value.
int sanitise(GamepadState& s) {
    int bad = 0;
    for (std::size_t i = 0; i < s.axes.size(); ++i) {
        const float a = s.axes[i];
        if (!std::isfinite(a) || std::fabs(a) > 1.0001f) {
            const bool trigger = i == gamepad_axis::kLeftTrigger || i == gamepad_axis::kRightTrigger;
            s.axes[i] = trigger ? -1.0f : 0.0f;
            ++bad;
        }
    }
    s.buttons &= (1u << gamepad_button::kCount) - 1u;
    return bad;
}

}  // namespace

GamepadDevice::GamepadDevice(DeviceProfile profile, const Vec3& start_m, double dt_s, GamepadParams params,
                             std::unique_ptr<GamepadSource> source)
    : profile_(std::move(profile)), dt_(dt_s), params_(params), source_(std::move(source)) {
    if (!(dt_s > 0.0 && dt_s <= 1.0)) throw Error("gamepad: dt_s must be in (0, 1] s, got " + std::to_string(dt_s));
    if (!is_finite(start_m)) throw Error("gamepad: start_m must be finite");
    check_range(params.max_speed_m_s, 0.0, 2.0, true, "max_speed_m_s");
    check_range(params.max_rate_rad_s, 0.0, 20.0, true, "max_rate_rad_s");
    check_range(params.dead_zone, 0.0, 0.9, false, "dead_zone");
    if (!source_) throw Error("gamepad: no controller source");
    pose_.position = glm::clamp(start_m, profile_.workspace_m.lo, profile_.workspace_m.hi);
}

DeviceLinkStats GamepadDevice::link_stats() const {
    DeviceLinkStats s;
    s.exchanges = exchanges_;
    s.missed_frames = missed_;
    s.malformed_frames = malformed_.load(std::memory_order_relaxed);
    return s;
}

void GamepadDevice::poll_on_main_thread() noexcept {
    GamepadState& s = published_.back();
    s = GamepadState{};
    if (source_->poll(s)) {
        s.connected = true;
        if (const int bad = sanitise(s)) malformed_.fetch_add(static_cast<std::uint64_t>(bad), std::memory_order_relaxed);
    } else {
        s = GamepadState{};
    }
    published_.publish();
}

void GamepadDevice::on_open() {
    GamepadState probe;
    if (!source_->poll(probe))
        throw Error("gamepad: no game controller found (" + source_->describe() +
                    "): plug one in (GLFW reads controllers with a gamepad mapping: Xbox, PlayStation, ...)");
    seen_ = false;
    vanished_ = false;
}

double GamepadDevice::shaped(float axis) const {
    const double a = std::fabs(static_cast<double>(axis));
    if (a <= params_.dead_zone) return 0.0;
    const double v = std::min(1.0, (a - params_.dead_zone) / (1.0 - params_.dead_zone));
    return axis < 0.0f ? -v : v;
}

double GamepadDevice::trigger(float axis) const {
    return shaped(0.5f * (axis + 1.0f));  // -1 released .. +1 pressed -> the pressed fraction 0 .. 1
}

bool GamepadDevice::do_read(DeviceState& out) {
    ++exchanges_;
    const GamepadState& s = published_.latest();
    if (s.connected) {
        seen_ = true;
    } else if (seen_ && !vanished_) {
        vanished_ = true;
        raise_fault(kFaultVanished);
    }
    const Vec3 before = pose_.position;
    std::uint32_t buttons = 0;
    if (vanished_) {
        ++missed_;
    } else if (s.connected) {
        using namespace gamepad_axis;
        const Vec3 v(shaped(s.axes[kLeftX]), trigger(s.axes[kRightTrigger]) - trigger(s.axes[kLeftTrigger]),
                     shaped(s.axes[kLeftY]));
        const bool right = (s.buttons >> gamepad_button::kRightBumper) & 1u;
        const bool left = (s.buttons >> gamepad_button::kLeftBumper) & 1u;
        const double roll = (right ? 1.0 : 0.0) - (left ? 1.0 : 0.0);
        const Vec3 w(shaped(s.axes[kRightY]), shaped(s.axes[kRightX]), roll);
        pose_.position = glm::clamp(pose_.position + v * (params_.max_speed_m_s * dt_), profile_.workspace_m.lo,
                                    profile_.workspace_m.hi);
        if (w != Vec3(0.0))
            pose_.orientation =
                glm::normalize(quat_from_rotation_vector(w * (params_.max_rate_rad_s * dt_)) * pose_.orientation);
        if (s.buttons & (1u << gamepad_button::kA)) buttons |= gamepad_device_buttons::kStylus;
        if (s.buttons & (1u << gamepad_button::kB)) buttons |= gamepad_device_buttons::kSecond;
        if (s.buttons & (1u << gamepad_button::kY)) buttons |= gamepad_device_buttons::kNextOp;
    }
    ++steps_;
    out.t_s = static_cast<double>(steps_) * dt_;
    out.pose = pose_;
    out.velocity_m_s = (pose_.position - before) / dt_;
    out.buttons = buttons;
    return true;
}

void GamepadDevice::do_write(const Vec3& /*force_n*/, const Vec3& /*torque_nm*/) {}

}  // namespace tridex::devices
