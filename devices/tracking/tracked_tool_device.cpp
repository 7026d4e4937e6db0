// devices/tracking/tracked_tool_device.cpp - a DTrack-tracked Flystick or body as the tool.
#include "devices/tracking/tracked_tool_device.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace tridex::devices {

std::uint32_t tracked_tool_button_bits(std::uint64_t flystick_buttons) {
    std::uint32_t bits = (flystick_buttons & 1u) ? tracked_tool_buttons::kEngage : 0u;
    for (int i = 1; i <= 30; ++i)
        if (flystick_buttons & (std::uint64_t{1} << i)) bits |= 1u << (i + 1);
    return bits;
}

TrackedToolDevice::TrackedToolDevice(DeviceProfile profile, std::shared_ptr<DTrackReceiver> receiver,
                                     TrackedToolParams params, double dt_s)
    : profile_(std::move(profile)), receiver_(std::move(receiver)), params_(params), dt_(dt_s) {
    if (!receiver_) throw Error("tracked tool: no DTrack receiver");
    const int kept = params_.flystick ? kDTrackKeptFlysticks : kDTrackKeptBodies;
    if (params_.id < 0 || params_.id >= kept)
        throw Error(std::string("tracked tool: DTrack ") + (params_.flystick ? "Flystick" : "body") + " id " +
                    std::to_string(params_.id) + " is not in 0.." + std::to_string(kept - 1));
    if (!(std::isfinite(params_.timeout_s) && params_.timeout_s > 0.0))
        throw Error("tracked tool: timeout_s must be finite and > 0");
    if (!(std::isfinite(params_.max_speed_m_s) && params_.max_speed_m_s > 0.0))
        throw Error("tracked tool: max_speed_m_s must be finite and > 0");
    if (!(std::isfinite(dt_) && dt_ > 0.0 && dt_ <= 1.0))
        throw Error("tracked tool: dt_s = " + std::to_string(dt_s) + " must be in (0, 1] s");
    x_ = profile_.workspace_m.empty() ? Vec3(0.0) : profile_.workspace_m.centre();
}

bool TrackedToolDevice::do_read(DeviceState& out) {
    const DTrackBodyTable& table = receiver_->latest(DTrackReader::kDevice);
    bool seen = false;
    std::int64_t receipt_ns = 0;
    DTrackBody body;
    std::uint64_t buttons = 0;
    double joystick_y = 0.0;
    if (params_.flystick) {
        const DTrackFlystickSample& f = table.flysticks[static_cast<std::size_t>(params_.id)];
        seen = f.seen;
        receipt_ns = f.receipt_ns;
        body = f.flystick.body;
        buttons = f.flystick.buttons;
        if (f.flystick.controller_count >= 2) joystick_y = f.flystick.controllers[1];  // DTrack's y is controller 1
    } else {
        const DTrackBodySample& b = table.bodies[static_cast<std::size_t>(params_.id)];
        seen = b.seen;
        receipt_ns = b.receipt_ns;
        body = b.body;
    }
    const bool fresh = seen && body.tracked() &&
                       static_cast<double>(dtrack_clock_ns() - receipt_ns) * 1e-9 <= params_.timeout_s;
    const Pose& t = params_.tracker_to_device;
    const Pose p = body.pose();
    const Vec3 target = t.orientation * p.position + t.position;
    Vec3 velocity(0.0);
    std::uint32_t bits = 0;
    double joy = 0.0;  // only a tracked Flystick's joystick counts (a stale one reads 0, as its buttons are released)
    if (!fresh) {
        ++stats_.missed_frames;
        acquired_ = false;
    } else if (!is_finite(target)) {
        ++stats_.malformed_frames;
        acquired_ = false;
    } else if (!acquired_) {  // (re)acquired: jump there, disengaged and at rest for this tick (no cut along it)
        x_ = target;
        q_ = glm::normalize(t.orientation * p.orientation);
        acquired_ = true;
    } else {  // tracked: glide toward the newest position
        const Vec3 before = x_, d = target - x_;
        const double n = glm::length(d), step = params_.max_speed_m_s * dt_;
        x_ = n <= step ? target : x_ + d * (step / n);
        q_ = glm::normalize(t.orientation * p.orientation);
        velocity = (x_ - before) / dt_;
        bits = params_.flystick ? tracked_tool_button_bits(buttons) : tracked_tool_buttons::kEngage;
        if (std::isfinite(joystick_y)) joy = std::clamp(joystick_y, -1.0, 1.0);
    }
    ++stats_.exchanges;
    ++steps_;
    out.t_s = static_cast<double>(steps_) * dt_;
    out.pose.position = x_;
    out.pose.orientation = q_;
    out.velocity_m_s = velocity;
    out.buttons = bits;
    out.joystick_y = joy;
    return true;
}

void TrackedToolDevice::do_write(const Vec3& /*force_n*/, const Vec3& /*torque_nm*/) {}

}  // namespace tridex::devices
