// devices/falcon/falcon_device.hpp - the Novint Falcon driver: a HapticDevice over a FalconTransport (libusb-1.0 for
// the real unit, the emulator for tests and `tridex demo --device falcon-emulator`).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "devices/falcon/falcon_kinematics.hpp"
#include "devices/falcon/falcon_protocol.hpp"
#include "devices/falcon/falcon_transport.hpp"
#include "devices/haptic_device.hpp"

namespace tridex::devices::falcon {

/// Driver settings (SI units).
struct FalconDeviceOptions {
    /// The firmware file from the user's own installation; "" = none (open() then needs firmware already running,
    /// or `firmware_image`).
    std::string firmware_path;
    /// An image to load instead of the file (the emulator's dummy image); empty = use firmware_path.
    std::vector<std::uint8_t> firmware_image;
    int firmware_attempts = 3;       ///< whole firmware-load attempts
    double period_s = 1e-3;          ///< the haptic loop period: device time per exchange, s
    int exchange_timeout_us = 900;   ///< how long one exchange waits for its state frame, us
    double ramp_s = 0.5;             ///< after homing (and after any fault) the force ramps from 0 to 1 over this, s
    double homing_timeout_s = 30.0;  ///< home() gives up after this much device time, s
    /// A stall this long (consecutive exchanges without a state frame, in device time) counts as a vanished device.
    double stall_vanish_s = 0.25;
    /// The monotonic clock the velocity estimate measures intervals with, s; empty = std::chrono::steady_clock.
    /// Tests inject one to model a loop that ran late.
    std::function<double()> clock_s;
};

/// What the driver measured on its link.
struct FalconLinkStats {
    std::uint64_t exchanges = 0;         ///< exchanges in the 1 kHz loop (after homing)
    std::uint64_t missed_frames = 0;     ///< exchanges that brought no well-formed state frame (stalls, torn frames)
    std::uint64_t malformed_frames = 0;  ///< frames with bad framing bytes or payload
    std::uint64_t line_errors = 0;       ///< IN packets whose FTDI line status reported an error
    std::uint64_t zeroed_ticks = 0;      ///< ticks whose command was forced to zero by a fault
    std::uint64_t clamped_commands = 0;  ///< commands scaled down to the motor command limit
    double exchange_mean_s = 0.0;        ///< exchange time (submit to state frame), mean and max, s
    double exchange_max_s = 0.0;
    double homed_at_s = -1.0;   ///< device time (s) from open() at which homing finished; -1 = not homed
    int homing_exchanges = 0;   ///< exchanges home() took
    int firmware_attempts = 0;  ///< firmware-load attempts at open() (0 = firmware was already running)
};

/// The Falcon driver.
///
/// Lifecycle: open() opens the transport, puts its FTDI bridge in normal mode, checks whether firmware answers and,
/// when not, loads it (the user's file, or the given image); without one it throws firmware_missing_message(). home()
/// turns the red LED on and sets the firmware's homing bit, then exchanges frames until all three encoders report
/// homed (the user pulls the grip all the way out, then pushes it in; the emulator does it by a scripted pull); the
/// homing bit then stays set in every command until close(), as libnifalcon's FalconFirmware.h documents (without
/// it the Falcon does not stay homed): no force flows until then (the base class gates
/// write(), and the driver sends zero motor commands in every state but enabled). The blue LED shows homed, the
/// green LED enabled. After enable() the force ramps in linearly over ramp_s.
///
/// read() makes one exchange: it sends the last command frame and takes the newest well-formed state frame of the
/// IN packet, turning encoder counts into the grip position by forward kinematics (Newton from the last position).
/// A missed or malformed frame, a stall or a line error raises kFaultIo and forces the next command to zero (the
/// ramp restarts when frames come back): the Falcon gets zero force within one tick. An unplug (kNoDevice, the
/// hotplug signal) or a stall over stall_vanish_s makes read() return false (kFaultVanished). write() turns the
/// force (N, already bounded by the profile) into motor torques through the Jacobian transpose and into motor
/// commands (falcon_kinematics.hpp), scaled together to the command limit (never an unbounded command).
/// Single-threaded like every device: drive it from the haptic thread; read stats() after the loop stopped.
class FalconDevice : public HapticDevice {
public:
    FalconDevice(std::unique_ptr<FalconTransport> transport, FalconDeviceOptions options);
    ~FalconDevice() override;

    const DeviceProfile& profile() const override { return profile_; }
    const FalconLinkStats& stats() const { return stats_; }
    DeviceLinkStats link_stats() const override;
    /// The transport (tests reach the emulator through it).
    FalconTransport& transport() { return *transport_; }
    /// The last command frame sent or queued.
    const FalconCommand& command() const { return cmd_; }

protected:
    void on_open() override;
    void on_home() override;
    void on_enable() override;
    void on_disable() noexcept override;
    void on_close() noexcept override;
    bool do_read(DeviceState& out) override;
    void do_write(const Vec3& force_n, const Vec3& torque_nm) override;

private:
    // One exchange of cmd_; returns the transfer status and sets `state` when a well-formed frame arrived.
    TransferStatus exchange(std::optional<FalconState>& state);
    void send_zero() noexcept;

    DeviceProfile profile_;
    std::unique_ptr<FalconTransport> transport_;
    FalconDeviceOptions opt_;
    FalconKinematics kin_;
    StateFramer framer_;
    FalconCommand cmd_{};
    std::uint8_t leds_ = kLedRed;
    bool homing_mode_ = false;  // set in every command from home() on (libnifalcon: else the Falcon does not stay homed)
    FalconLinkStats stats_;
    Vec3 pos_{0.0}, vel_{0.0};
    bool have_pos_ = false;
    std::uint64_t pos_tick_ = 0;     // ticks_ when pos_ was measured
    double pos_clock_s_ = 0.0;       // the clock when pos_ was measured, s
    std::uint8_t grip_ = 0;
    std::uint64_t ticks_ = 0;       // exchanges since open (device time = ticks_ * period)
    std::uint64_t missed_run_ = 0;  // consecutive exchanges without a frame
    bool fault_tick_ = false;       // this tick's frame was missed or malformed: the next command is zero
    std::uint64_t ramp_ticks_ = 0;  // enabled ticks since the ramp (re)started
    bool vanished_ = false;
};

}  // namespace tridex::devices::falcon
