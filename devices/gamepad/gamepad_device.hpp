// devices/gamepad/gamepad_device.hpp - a game controller as the tool: rate control from two sticks and triggers.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>

#include "core/triple_buffer.hpp"
#include "devices/gamepad/gamepad_source.hpp"
#include "devices/haptic_device.hpp"

namespace tridex::devices {

/// How a GamepadDevice turns deflection into motion (SI units).
struct GamepadParams {
    double max_speed_m_s = 0.1;   ///< tip speed at full deflection of a stick or trigger, m/s, (0, 2]
    double max_rate_rad_s = 1.5;  ///< angular rate at full deflection of the right stick or a bumper, rad/s, (0, 20]
    /// Fraction of full deflection below which an axis reads as zero (sticks drift a few per cent at rest), [0, 0.9];
    /// above it the output is rescaled to start from zero, so it is continuous at the edge.
    double dead_zone = 0.15;
};

/// DeviceState::buttons bits a GamepadDevice reports.
namespace gamepad_device_buttons {
inline constexpr std::uint32_t kStylus = 1u << 0;  ///< A: the stylus button (the workspace techniques read it)
inline constexpr std::uint32_t kSecond = 1u << 1;  ///< B: the second stylus button
inline constexpr std::uint32_t kNextOp = 1u << 2;  ///< Y: switch to the next operation (a session reads it)
}  // namespace gamepad_device_buttons

/// A HapticDevice reading a game controller (GamepadSource) by rate control, like a 3D mouse. Mapping, device frame
/// (x right, y up, z toward the viewer): left stick x -> +x; left stick y (down = +1) -> +z, so pushing the stick
/// away moves the tool into the scene; right trigger -> +y, left trigger -> -y (each by its pressed fraction);
/// right stick x -> turn about +y, right stick y -> turn about +x, right bumper / left bumper -> turn about +z / -z.
/// Each read() (one loop period dt) moves the tip by max_speed_m_s * dt * the shaped deflection and clamps it to the
/// profile's workspace. Buttons: A -> bit 0 (stylus), B -> bit 1, Y -> bit 2 (next operation); see
/// gamepad_device_buttons. The source is polled by poll_on_main_thread() (the window's thread) and handed to read()
/// (the haptic thread) through a triple buffer: neither side locks. An axis that is not finite or beyond +-1 counts
/// as malformed and reads as zero. A controller that disconnects raises kFaultVanished: the pose is held, the
/// buttons released, and read() goes on returning it. Forces are ignored (a gamepad renders none).
class GamepadDevice : public HapticDevice {
public:
    /// `profile`: the limits the loop applies (workspace, forces); `start_m`: the tip before any motion, device
    /// frame, m; dt_s: the loop period, s. Throws tridex::Error naming the parameter when dt_s is not in (0, 1],
    /// start_m is not finite, a GamepadParams field is out of its range, or `source` is null.
    GamepadDevice(DeviceProfile profile, const Vec3& start_m, double dt_s, GamepadParams params,
                  std::unique_ptr<GamepadSource> source);

    const DeviceProfile& profile() const override { return profile_; }
    /// exchanges = reads, missed_frames = reads after the controller vanished, malformed_frames = bad axis values.
    DeviceLinkStats link_stats() const override;
    /// Polls the source and publishes its state to read(). Call on the window's thread (GLFW's main thread).
    void poll_on_main_thread() noexcept override;

protected:
    /// Polls the source once (on the opening thread, the session's main thread); throws tridex::Error "gamepad: no
    /// game controller found (SOURCE): plug one in ..." when none answers.
    void on_open() override;
    /// Integrates one step of dt from the newest published state; true while opened.
    bool do_read(DeviceState& out) override;
    void do_write(const Vec3& force_n, const Vec3& torque_nm) override;

private:
    double shaped(float axis) const;
    double trigger(float axis) const;

    DeviceProfile profile_;
    double dt_;
    GamepadParams params_;
    std::unique_ptr<GamepadSource> source_;
    TripleBuffer<GamepadState> published_;
    std::atomic<std::uint64_t> malformed_{0};
    bool seen_ = false;     // haptic thread: a connected state was read
    bool vanished_ = false;  // haptic thread
    Pose pose_;
    std::uint64_t steps_ = 0;
    std::uint64_t exchanges_ = 0, missed_ = 0;
};

}  // namespace tridex::devices
