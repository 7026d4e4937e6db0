// devices/mouse_device.cpp - the mouse stylus: a speed-limited glide toward the newest hand target.
#include "devices/mouse_device.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace tridex::devices {

MouseDevice::MouseDevice(DeviceProfile profile, const Vec3& start_m, double dt_s, MouseFollowParams follow)
    : profile_(std::move(profile)), dt_(dt_s), follow_(follow), last_target_(start_m), x_(start_m) {
    if (!(std::isfinite(dt_) && dt_ > 0.0 && dt_ <= 1.0))
        throw Error("MouseDevice: dt_s = " + std::to_string(dt_s) + " must be in (0, 1] s");
    if (!is_finite(start_m)) throw Error("MouseDevice: the start position must be finite");
    if (!(std::isfinite(follow_.max_speed_m_s) && follow_.max_speed_m_s > 0.0))
        throw Error("MouseDevice: max_speed_m_s = " + std::to_string(follow_.max_speed_m_s) + " must be > 0");
}

void MouseDevice::set_hand(const Vec3& target_m, std::uint32_t buttons, const Quat& orientation) {
    Hand& h = hand_.back();
    const double qn = std::sqrt(orientation.w * orientation.w + orientation.x * orientation.x +
                                orientation.y * orientation.y + orientation.z * orientation.z);
    h.orientation = is_unit(orientation) ? orientation / qn : Quat(1.0, 0.0, 0.0, 0.0);
    if (is_finite(target_m)) {
        last_target_ = target_m;
    } else {
        rejected_.fetch_add(1, std::memory_order_relaxed);
    }
    h.target_m = last_target_;
    h.buttons = buttons;
    h.set = true;
    hand_.publish();
}

bool MouseDevice::do_read(DeviceState& out) {
    const Hand& h = hand_.latest();
    const Vec3 before = x_;
    if (h.set) {
        const Vec3 d = h.target_m - x_;
        const double n = glm::length(d);
        const double step = follow_.max_speed_m_s * dt_;
        x_ = n <= step ? h.target_m : x_ + d * (step / n);
    }
    ++steps_;
    t_ = static_cast<double>(steps_) * dt_;  // no drift from summing dt
    out.t_s = t_;
    out.pose.position = x_;
    out.pose.orientation = h.set ? h.orientation : Quat(1.0, 0.0, 0.0, 0.0);
    out.velocity_m_s = (x_ - before) / dt_;
    out.buttons = h.buttons;
    return true;
}

void MouseDevice::do_write(const Vec3& force_n, const Vec3& /*torque_nm*/) { last_force_ = force_n; }

}  // namespace tridex::devices
