// devices/mouse_device.hpp - the desk mouse as a virtual stylus: a device whose hand position the app sets.
#pragma once

#include <atomic>
#include <cstdint>

#include "core/triple_buffer.hpp"
#include "devices/haptic_device.hpp"

namespace tridex::devices {

/// Button bits a MouseDevice reports (DeviceState::buttons).
namespace mouse_buttons {
/// The right mouse button: the stylus button (bit 0, what the workspace techniques read: Peng's moving, clutch).
inline constexpr std::uint32_t kStylus = 1u << 0;
/// The left mouse button: the tool is engaged (pressed in); a loop with HapticLoopConfig::engage_mask = kEngage
/// carves only while it is held.
inline constexpr std::uint32_t kEngage = 1u << 1;
}  // namespace mouse_buttons

/// How the reported stylus follows the hand target the app sets (SI units).
struct MouseFollowParams {
    /// Fastest the stylus moves toward a new target, m/s (> 0): a cursor jump becomes a straight glide, so
    /// the loop's velocity limit (1.5 m/s by default) never cuts a stroke into pieces.
    double max_speed_m_s = 0.75;
};

/// A HapticDevice driven by the desk mouse: the render thread turns the cursor into a stylus target (device
/// frame, m) and button bits each frame (set_hand); the haptic loop's reads glide the stylus toward the newest
/// target at no more than max_speed_m_s and report its position, velocity and buttons, one device-time step of
/// dt per read (so the watchdog sees a steady clock). The hand-off is a latest-value triple buffer: the render
/// thread never waits for the loop and the loop never waits for it. Forces are ignored (a mouse renders none),
/// but write() still gates and bounds them (the base class); last_force_n() shows what would have been sent.
/// Orientation: as set_hand gives it (identity unless the app turns the hand). A non-finite target is ignored (the
/// stylus stays where it was, counted).
class MouseDevice : public HapticDevice {
public:
    /// `profile`: the limits the loop applies (the simulated device's, e.g. phantom_omni(), named "mouse (...)"
    /// by the registry); `start_m`: where the stylus rests before the first target, device frame, m; dt_s: the
    /// loop period, s. Throws tridex::Error when dt_s is not in (0, 1], start_m is not finite or
    /// follow.max_speed_m_s is not > 0.
    MouseDevice(DeviceProfile profile, const Vec3& start_m, double dt_s, MouseFollowParams follow = {});

    const DeviceProfile& profile() const override { return profile_; }

    /// Render thread (one writer): the newest hand target, device frame (m), button bits (mouse_buttons) and the
    /// stylus orientation (device frame; reported as given from the next read). Lock-free, never blocks. A non-finite
    /// target keeps the previous one (the buttons still change); a non-finite or non-unit orientation is identity.
    void set_hand(const Vec3& target_m, std::uint32_t buttons, const Quat& orientation = Quat(1.0, 0.0, 0.0, 0.0));
    /// Targets refused as non-finite so far (any thread).
    std::uint64_t rejected_targets() const { return rejected_.load(std::memory_order_relaxed); }
    /// The last force written (N, device frame, after the base class's gate and bound); loop thread, or after it stopped.
    const Vec3& last_force_n() const { return last_force_; }
    /// The current stylus position, device frame, m (loop thread, or after it stopped).
    const Vec3& position_m() const { return x_; }

protected:
    /// Glides one step of dt toward the newest target; never fails.
    bool do_read(DeviceState& out) override;
    /// Keeps the force for last_force_n(); nothing is rendered.
    void do_write(const Vec3& force_n, const Vec3& torque_nm) override;

private:
    struct Hand {
        Vec3 target_m{0.0};
        std::uint32_t buttons = 0;
        Quat orientation{1.0, 0.0, 0.0, 0.0};
        bool set = false;
    };

    DeviceProfile profile_;
    double dt_;
    MouseFollowParams follow_;
    TripleBuffer<Hand> hand_;
    std::atomic<std::uint64_t> rejected_{0};
    Vec3 last_target_{0.0};  // writer side: the previous accepted target
    double t_ = 0.0;
    std::uint64_t steps_ = 0;
    Vec3 x_{0.0};
    Vec3 last_force_{0.0};
};

}  // namespace tridex::devices
