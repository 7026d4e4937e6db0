// app/input/dtrack_wand.hpp - the Wand from ART DTrack: a Flystick's pose (through the display's calibration), buttons
// and joystick, checked for staleness, as WandSamples, with the numbers report.json shows.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "app/input/wand_navigation.hpp"
#include "core/pose.hpp"
#include "devices/registry/device_registry.hpp"
#include "devices/tracking/dtrack_receiver.hpp"

namespace tridex::app {

/// Where the DTrack wand comes from.
struct DTrackWandSettings {
    int port = 5000;                        ///< UDP port DTrack sends to, 1..65535 (0: any free port, for tests)
    int flystick = 0;                       ///< DTrack Flystick id (`6df2`), 0..kDTrackKeptFlysticks-1
    std::string bind_address = "0.0.0.0";  ///< local IPv4 address to listen on
    Pose tracker_to_wall;                   ///< tracker -> wall coordinates (DisplayConfig), as for the head
    double timeout_s = 0.1;                 ///< a sample older than this is stale, s (> 0)
};

/// Reads a Flystick from a DTrackReceiver (its own, or the head's when they share the UDP port). sample() (the
/// render thread, once per frame) returns the newest Flystick sample as a WandSample: pose = tracker_to_wall *
/// flystick pose (ART's `6df2`: position mm -> m, rotation columns b0..b8), buttons, joystick y (controller 1;
/// 0 when the Flystick has fewer than two). It is fresh only when DTrack tracked it (quality >= 0) and it
/// arrived less than timeout_s ago; otherwise navigation stops.
class DTrackWand {
public:
    /// Uses `shared` when given (the same port as the head), else opens its own receiver. Throws tridex::Error for
    /// a Flystick id outside 0..kDTrackKeptFlysticks-1, a timeout not finite and > 0, or a port that cannot be
    /// bound (DTrackReceiver's message).
    explicit DTrackWand(const DTrackWandSettings& settings,
                        std::shared_ptr<devices::DTrackReceiver> shared = nullptr);
    /// This frame's wand (reads the receiver's newest table; the receiver's one reader thread).
    WandSample sample();

    int port() const { return receiver_->port(); }  ///< the bound UDP port
    /// The receiver it reads (its kView reader), to share with a tracked tool on the same port.
    std::shared_ptr<devices::DTrackReceiver> receiver() const { return receiver_; }
    /// The receiver's counters (any thread).
    devices::DTrackReceiverStats receiver_stats() const { return receiver_->stats(); }
    std::uint64_t frames_tracked() const { return frames_tracked_; }  ///< sample() calls that were fresh
    std::uint64_t frames_stale() const { return frames_stale_; }      ///< sample() calls that were not
    /// One line: whether the last sample() was fresh and, if not, why.
    std::string note() const;
    /// report.json `wand` (provider part): {provider, port, flystick, frames_tracked, frames_stale, shared_receiver,
    /// note}; the caller adds the navigation's numbers.
    nlohmann::json report_json() const;

private:
    DTrackWandSettings settings_;
    std::shared_ptr<devices::DTrackReceiver> receiver_;
    bool shared_ = false;
    std::uint64_t frames_tracked_ = 0, frames_stale_ = 0;
    std::string why_ = "no sample() yet";
};

/// report.json `wand`: the provider's report_json plus the navigation's {grabs, grabs_dropped, resets,
/// nav_frames_tracked, nav_frames_lost, scaled_by, final_scale, final_position_m}.
nlohmann::json wand_report_json(const DTrackWand& wand, const WandNavigator& nav_input,
                                const renderer::SceneNavigation& nav);

/// Parses `--wand dtrack:PORT:FLYSTICK` (PORT 1..65535, FLYSTICK 0..kDTrackKeptFlysticks-1; a missing FLYSTICK
/// keeps `flystick`). Throws tridex::Error "--wand: ..." naming what is wrong.
void parse_dtrack_wand_option(const std::string& value, int& port, int& flystick);

/// Parses the ADDRESS of `--device NAME:ADDRESS` for a tracked driver (DriverCapabilities: PORT[:ID], PORT
/// 1..65535, ID 0..target_ids-1 of the driver's kind of target): sets `port` and, when given, `id`; an empty address
/// sets nothing. Throws tridex::Error "--device: ..." for a bad port or id.
void parse_tracked_tool_address(const devices::DriverInfo& driver, const std::string& address, int& port, int& id);

}  // namespace tridex::app
