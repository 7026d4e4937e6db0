// haptics/device_server.hpp - `tridex device-server`: owns a haptic device on one machine and serves it to a
// session elsewhere over a DatagramLink, in distributed or local haptic rendering (Popescu, Burdea, Bouzit,
// "Virtual Reality Simulation Modeling for a Haptic Glove", section 2).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/active_surface.hpp"
#include "core/spsc_ring.hpp"
#include "core/tool_sample.hpp"
#include "core/triple_buffer.hpp"
#include "devices/haptic_device.hpp"
#include "devices/net/datagram_link.hpp"
#include "devices/net/link_wire.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::haptics {

/// Settings of a device server (SI units).
struct DeviceServerConfig {
    double period_s = 1e-3;  ///< server tick, s (1 kHz): one device exchange and one state datagram per tick
    /// Silence (no datagram from the session) after which the force is held at zero, s. 9 ms plus at most one
    /// tick: the force is zero within 10 ms of the session's last datagram.
    double watchdog_s = 0.009;
    std::function<double()> clock;  ///< seconds, non-decreasing; empty = std::chrono::steady_clock
    std::uint16_t version = devices::net::kLinkVersion;  ///< link version spoken (tests set another)
    /// Called on the serving thread with one line per event (session connected, refused, link silent, ...).
    std::function<void(const std::string&)> on_event;
    bool request_realtime = false;  ///< start(): ask for SCHED_FIFO for the serving thread (refusal reported)
};

/// Counters of a device server (any thread).
struct DeviceServerStats {
    std::uint64_t ticks = 0;            ///< server ticks run
    std::uint64_t sessions = 0;         ///< sessions welcomed
    std::uint64_t refused = 0;          ///< sessions refused (another link version, ...)
    std::uint64_t malformed = 0;        ///< datagrams dropped as malformed or unexpected
    /// Datagrams from addresses other than the session's while it was connected, dropped by the link (LinkTraffic).
    std::uint64_t foreign = 0;
    std::uint64_t datagrams = 0;        ///< datagrams the link's socket received, whatever they held
    std::uint64_t lost = 0;             ///< datagrams from the session missing (sequence gaps)
    std::uint64_t watchdog_trips = 0;   ///< times a silent link made the server zero the force
    std::uint64_t zeroed_ticks = 0;     ///< ticks with the force held at zero by the watchdog or no session
    std::uint64_t stale_snapshots = 0;  ///< local mode: snapshots that arrived not covering the tool, or out of order
    std::uint64_t snapshots = 0;        ///< local mode: snapshots received
    /// Local mode: ticks whose loop rendered its force on a snapshot the tool had left (outside the region the
    /// newest snapshot covers): stale forces, logged as such (an event when it begins, at most one a second).
    std::uint64_t stale_force_ticks = 0;
    /// New force values that reached the device: kForce datagrams applied (distributed) or contact-loop ticks
    /// (local); per second of serving, the rate at which the device's force is updated.
    std::uint64_t force_updates = 0;
    bool device_lost = false;           ///< the device vanished (the server stopped serving)
    bool session = false;               ///< a session is connected and welcomed now
};

/// Serves one device to one session at a time.
///
/// Each tick (tick(), or the thread of start()): every pending datagram is read and checked (malformed ones are
/// counted by reason and dropped); a kHello of this link version is answered with kWelcome (the device's
/// profile), one of another version with kRefuse and one line naming both versions; then
/// - distributed: the device is read, the newest kForce (by sequence number) is written to it, and the state goes
///   back as an unreliable kState;
/// - local: the server runs a HapticLoop (god-object, EWMA filter, safety stages) next to the device, in step mode
///   on this thread, on the newest kSurface snapshot with the kContact parameters, and sends the device state with
///   the tool sample that loop computed (HIP pose, god-object proxy, rendered force, hold): the session sculpts
///   with these. Until the contact parameters arrive the device is read at zero force and states go without a tool.
///   A tick whose tool is outside the region the newest snapshot covers renders a stale force: counted
///   (stale_force_ticks) and logged as such through on_event when it begins (at most once a second).
/// When no datagram came from the session for watchdog_s, zero force is written and the device rests (is not
/// exchanged with, no states are sent) until the session speaks again; without a session likewise (zero force is
/// written once when a session ends). So a simulated device's clock runs only while a live session is served (a
/// session that connects, then spends seconds loading its workpiece, starts its stroke when its loop starts).
/// Nothing is
/// allocated per tick except by the link and on a new snapshot or contact set.
/// The device is brought up (open, home, enable) by the constructor's caller or by the first tick, and
/// disabled by stop() / the destructor.
class DeviceServer {
public:
    /// device and link must outlive the server. Throws tridex::Error naming the field when period_s or watchdog_s
    /// is not positive and finite.
    DeviceServer(devices::HapticDevice& device, devices::net::DatagramLink& link, DeviceServerConfig cfg);
    ~DeviceServer();
    DeviceServer(const DeviceServer&) = delete;
    DeviceServer& operator=(const DeviceServer&) = delete;

    /// One tick at now_s (the config's clock is used for the link's time stamps). Throws tridex::Error when the
    /// device cannot be brought up; returns false once the device is gone.
    bool tick(double now_s);
    /// Runs tick() every period on its own thread (absolute deadlines) until stop() or the device is gone.
    void start();
    /// Stops the thread, writes zero force and disables the device. Idempotent.
    void stop();
    /// True while the thread of start() runs.
    bool running() const { return running_.load(std::memory_order_acquire); }
    /// The counters so far.
    DeviceServerStats stats() const;
    /// Drops by reason so far (copy; any thread).
    devices::net::DropCounts drops() const;

private:
    void pump(double now_s);
    void handle(const std::vector<std::uint8_t>& d, double now_s);
    void drop(devices::net::DropReason r);
    void event(const std::string& line);
    void send_state(const devices::DeviceState& s, const Vec3& applied_device_n, bool zeroed,
                    const devices::RemoteToolSample* tool = nullptr);
    devices::net::Header header(std::uint32_t seq) const;
    void build_loop();
    void run() noexcept;

    devices::HapticDevice& device_;
    devices::net::DatagramLink& link_;
    DeviceServerConfig cfg_;
    devices::net::LinkEvent ev_;
    std::vector<std::uint8_t> out_;
    // Session.
    bool session_ = false;
    devices::net::RenderingMode mode_ = devices::net::RenderingMode::kDistributed;
    double last_rx_s_ = -1.0;
    bool silent_ = true;
    bool served_ = false;  // the device was exchanged with on the previous tick
    std::uint64_t peer_sent_us_ = 0;
    std::uint32_t rx_seq_ = 0;
    bool rx_seq_valid_ = false;
    std::uint32_t tx_seq_ = 0;
    devices::net::ForceMsg force_;
    // Local mode.
    devices::net::ContactMsg contact_;
    bool have_contact_ = false;
    std::unique_ptr<TripleBuffer<ActiveSurface>> surface_;
    std::unique_ptr<SpscRing<ToolSample>> samples_;
    std::unique_ptr<HapticLoop> loop_;
    std::uint64_t surface_seq_ = 0;
    Vec3 cover_centre_m_{0.0};   // the newest snapshot's centre, world m
    double cover_reach_m_ = -1.0;  // and the reach it covers per axis, m; < 0: no snapshot yet
    bool stale_forces_now_ = false;    // the previous tick rendered on a snapshot the tool had left
    double stale_logged_s_ = -1e300;   // when a stale-force event was last logged, s
    Vec3 tool_world_m_{0.0};
    double loop_time_s_ = 0.0;
    // Counters (read by stats() from any thread).
    std::atomic<std::uint64_t> ticks_{0}, sessions_{0}, refused_{0}, malformed_{0}, lost_{0}, trips_{0}, zeroed_{0},
        stale_{0}, snapshots_{0}, force_updates_{0}, stale_forces_{0};
    std::atomic<bool> device_lost_{false}, session_flag_{false};
    // The counters at the start of the session being served (serving thread only): what a session is told counts
    // from its own start, whatever earlier sessions saw.
    struct SessionBase {
        std::uint64_t lost = 0, malformed = 0, stale = 0, trips = 0;
    } session_base_;
    mutable std::mutex drops_mutex_;
    devices::net::DropCounts drops_;
    std::thread thread_;
    std::atomic<bool> stop_requested_{false}, running_{false};
};

}  // namespace tridex::haptics
