// devices/tracking/tracked_tool_device.hpp - a tracked Flystick or rigid body as the tool, when no haptic device
// is present: the pose from ART DTrack (through the display's calibration), its trigger as the engage button.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "core/pose.hpp"
#include "devices/haptic_device.hpp"
#include "devices/tracking/dtrack_receiver.hpp"

namespace tridex::devices {

/// Which DTrack target is the tool and how its samples are taken (SI units).
struct TrackedToolParams {
    /// true: a Flystick (`6df2`, id `id`), whose trigger (button 0) engages the tool and whose other buttons i
    /// become button bits i + 1; false: a standard body (`6d`, id `id`), which has no buttons, so the tool is
    /// always engaged (it carves wherever it goes into material, as a real mill would).
    bool flystick = true;
    int id = 0;                   ///< DTrack id: 0..kDTrackKeptFlysticks-1 (Flystick) or 0..kDTrackKeptBodies-1 (body)
    Pose tracker_to_device;       ///< tracker -> device frame (the display's tracker_to_wall when world = device)
    double timeout_s = 0.1;       ///< a sample older than this is stale, s (> 0)
    /// Fastest the reported tip moves toward a new tracked position, m/s (> 0): DTrack's 60..300 Hz steps become
    /// glides at the loop's 1 kHz, so a step never trips the loop's velocity limit.
    double max_speed_m_s = 1.0;
};

/// Button bits of a TrackedToolDevice's samples.
namespace tracked_tool_buttons {
/// The Flystick's trigger: the tool is engaged (a loop with engage_mask = kEngage carves only while it is held);
/// the same bit as the desk mouse's left button.
inline constexpr std::uint32_t kEngage = 1u << 1;
}  // namespace tracked_tool_buttons

/// A HapticDevice whose stylus is a tracked target: each read() takes the receiver's newest table (its kDevice
/// reader: this device is that reader's one thread, the haptic thread), and when the target is fresh (tracked,
/// quality >= 0, and received less than timeout_s ago) moves the reported tip toward tracker_to_device * its
/// position at most max_speed_m_s, with its orientation. A stale or lost target holds the last pose, reports
/// zero velocity and releases every button (the tool disengages: nothing is carved blind), and counts the read
/// in link_stats().missed_frames. Before the first fresh sample the tip rests at the profile's workspace centre;
/// the first fresh read after none or after a lost one jumps to the target at rest with no buttons, so the tool
/// never glides (or carves) along the way from where tracking was lost.
/// Forces are ignored (a tracked stick renders none; write() still gates and bounds them).
class TrackedToolDevice : public HapticDevice {
public:
    /// Reads `receiver` (kept alive by the device). `profile`: the limits the loop applies; dt_s: the loop
    /// period, s. Throws tridex::Error for a null receiver, an id out of range, a timeout or speed not finite
    /// and > 0, or dt_s not in (0, 1].
    TrackedToolDevice(DeviceProfile profile, std::shared_ptr<DTrackReceiver> receiver, TrackedToolParams params,
                      double dt_s);

    const DeviceProfile& profile() const override { return profile_; }
    /// exchanges = reads, missed_frames = reads without a fresh sample.
    DeviceLinkStats link_stats() const override { return stats_; }
    /// The receiver's UDP port.
    int port() const { return receiver_->port(); }

protected:
    bool do_read(DeviceState& out) override;
    void do_write(const Vec3& force_n, const Vec3& torque_nm) override;

private:
    DeviceProfile profile_;
    std::shared_ptr<DTrackReceiver> receiver_;
    TrackedToolParams params_;
    double dt_;
    Vec3 x_{0.0};
    Quat q_{1.0, 0.0, 0.0, 0.0};
    bool acquired_ = false;  // a fresh sample was read, and every read since was fresh
    std::uint64_t steps_ = 0;
    DeviceLinkStats stats_;
};

/// The buttons a TrackedToolDevice reports for a Flystick's `buttons` (bit i = DTrack button i): the trigger
/// (bit 0) -> kEngage, bit i >= 1 -> bit i + 1 (up to bit 31). Never sets bit 0 (the stylus button of the workspace
/// techniques: a tracked tool is mapped 1:1 and never moves the workspace).
std::uint32_t tracked_tool_button_bits(std::uint64_t flystick_buttons);

}  // namespace tridex::devices
