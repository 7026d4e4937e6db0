// app/input/dtrack_head.hpp - the viewer's head from ART DTrack: a tracked body through the display's calibration into
// the off-axis eyes, with TrackerHead's fallback and the numbers report.json shows.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/duration_histogram.hpp"
#include "core/pose.hpp"
#include "devices/tracking/dtrack_receiver.hpp"
#include "renderer/camera/head_pose.hpp"

namespace tridex::app {

/// Where the DTrack head comes from and how it reaches the eyes.
struct DTrackHeadSettings {
    int port = 5000;                        ///< UDP port DTrack sends to, 1..65535 (0: any free port, for tests)
    int body = 0;                           ///< DTrack id of the head's standard body, 0..kDTrackKeptBodies-1
    std::string bind_address = "0.0.0.0";  ///< local IPv4 address to listen on
    Pose tracker_to_wall;                   ///< tracker -> screen-corner coordinates (DisplayConfig)
    Pose head_to_eyes;                      ///< head body -> eye head frame (DisplayConfig)
    Pose fallback;                          ///< the head pose while the body is untracked or stale (wall, m)
    double timeout_s = 0.1;                 ///< a sample older than this is stale, s (> 0)
};

/// A HeadPoseProvider fed by a DTrackReceiver. Each head_at() (the render thread, once per frame) takes the
/// newest sample of the body: a tracked one (quality >= 0) becomes head = tracker_to_wall * body * head_to_eyes
/// and is pushed into a TrackerHead stamped with its receipt time on the session clock; an untracked one
/// (quality -1) is not used, so the last tracked pose holds until it is timeout_s old and the fallback pose
/// follows, exactly as TrackerHead falls back when samples stop. note() says which pose is used and why.
class DTrackHead final : public renderer::HeadPoseProvider {
public:
    /// Opens the UDP receiver (or uses `shared`, e.g. the wand's). Throws tridex::Error for a body outside 0..kDTrackKeptBodies-1, a bad fallback
    /// pose or timeout (TrackerHead's rules), or a port that cannot be bound (DTrackReceiver's message).
    explicit DTrackHead(const DTrackHeadSettings& settings, std::shared_ptr<devices::DTrackReceiver> shared = nullptr);
    /// The receiver, to share with a wand on the same port (one reader thread: the render thread).
    std::shared_ptr<devices::DTrackReceiver> receiver() const { return receiver_; }
    /// Session time 0 (head_at's t_s is seconds since then); default: construction time.
    void set_session_origin(std::chrono::steady_clock::time_point origin);
    /// The head pose (wall coordinates, m) for the frame at session time t_s (s).
    Pose head_at(double t_s) override;

    int port() const { return receiver_->port(); }  ///< the bound UDP port
    int body() const { return settings_.body; }  ///< the DTrack body id the head follows
    std::uint64_t frames_tracked() const { return frames_tracked_; }  ///< head_at() calls that used a fresh sample
    std::uint64_t frames_stale() const { return frames_stale_; }      ///< head_at() calls that used the fallback
    /// The last tracked position of the body in tracker coordinates (m, before calibration); none before one.
    const std::optional<Vec3>& last_position_m() const { return last_position_m_; }
    /// Per sample used: steady time from the datagram's receipt to the head_at() that first used it, ms, in
    /// 0.25 ms bins (DurationHistogram::latency).
    const DurationHistogram& latency_ms() const { return latency_ms_; }
    /// Receiver counters (datagrams, rejects by reason).
    devices::DTrackReceiverStats receiver_stats() const { return receiver_->stats(); }
    /// One line: which pose the last head_at() used and why.
    std::string note() const;
    /// report.json `head` for this provider: {provider, port, body, frames_tracked, frames_stale, last_position_m
    /// (tracker m or null), latency_ms {median, p99, max, count}, datagrams, accepted, rejected,
    /// rejected_by_reason {reason: count}, note}.
    nlohmann::json report_json() const;

private:
    DTrackHeadSettings settings_;
    std::shared_ptr<devices::DTrackReceiver> receiver_;
    renderer::TrackerHead tracker_;
    std::int64_t origin_ns_ = 0;
    std::uint64_t last_datagram_ = 0;  // the newest datagram of the body already taken
    bool pending_latency_ = false;     // a tracked sample pushed, not yet used by a tracked frame
    std::int64_t pending_receipt_ns_ = 0;
    bool untracked_ = false;           // the newest sample said quality -1
    std::uint64_t frames_tracked_ = 0, frames_stale_ = 0;
    std::optional<Vec3> last_position_m_;
    DurationHistogram latency_ms_ = DurationHistogram::latency();  // bounded memory however long the session
};

/// Parses "PORT[:ID]" (`text`, what follows a prefix such as "dtrack:"): PORT, a whole number 1..65535, into
/// `port`; an ID, when given, a whole number 0..id_count-1, into `id` (kept when absent). Throws tridex::Error
/// "<option>: the DTrack UDP port must be ..." or "<option>: the <id_name> must be ..." followed by `usage`.
void parse_port_and_id(std::string_view text, const std::string& option, const std::string& id_name, int id_count,
                       const std::string& usage, int& port, int& id);

/// Parses `--head dtrack:PORT[:BODY]` (PORT 1..65535, BODY 0..kDTrackKeptBodies-1; a missing BODY keeps
/// `body`). Throws tridex::Error "--head: ..." naming what is wrong.
void parse_dtrack_head_option(const std::string& value, int& port, int& body);

}  // namespace tridex::app
