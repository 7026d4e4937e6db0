// devices/net/net_device.hpp - the `net` driver: a haptic device on another machine, served by
// `tridex device-server`, used through a DatagramLink (ENet, or the in-process shim of the link bench).
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "devices/haptic_device.hpp"
#include "devices/net/datagram_link.hpp"
#include "devices/net/link_wire.hpp"

namespace tridex::devices::net {

/// How the net driver talks to its server.
struct NetDeviceOptions {
    RenderingMode mode = RenderingMode::kDistributed;  ///< where the contact loop runs
    double period_s = 1e-3;   ///< the session's haptic loop period, s
    double watchdog_s = 0.010;  ///< no device state for this long: the link counts as down, no force is sent, s
    double give_up_s = 10.0;  ///< no device state for this long: read() reports the device gone, s
    std::function<double()> clock;  ///< seconds, non-decreasing; empty = std::chrono::steady_clock
    std::uint16_t version = kLinkVersion;  ///< link version spoken (tests set another to see the refusal)
    /// Local mode: at most one snapshot per this interval, the newest (a sculpting session publishes far more often
    /// than a link can carry ~100 KB snapshots reliably), s (>= 0; 0 = every new one).
    double snapshot_interval_s = 0.02;
    /// Run the link thread (service() every 2 ms, at once when a snapshot is offered). Off: the owner calls service()
    /// itself (tests and benchmarks on a simulated clock, whose time only their own thread may read).
    bool link_thread = true;
};

/// Client end of a device server (Popescu, Burdea, Bouzit section 2: local and distributed haptic rendering).
///
/// Handshake: on connection it sends kHello (mode, period); the server answers kWelcome with the device's profile
/// (or kRefuse with one line, e.g. another link version). In distributed mode every write() sends the force as an
/// unreliable kForce; in local mode writes are not sent (the server's own god-object loop drives the device):
/// the contact parameters (set_contact) go reliably after each kWelcome and the newest snapshot offered to
/// observe_surface() goes reliably as a kSurface, with a kHeartbeat per tick for the server's watchdog.
///
/// Threads: the haptic thread's read() and write() pump the link and send the small datagrams (state in, force or
/// heartbeat out) and never wait: they take the link with a try-lock, and on the rare tick the link thread holds it
/// they return the previous state and send nothing (counted in missed_frames). The link thread (service()) does the
/// rest, so the 1 kHz path neither encodes, allocates nor sends a snapshot: it sends the newest offered snapshot
/// when due, and while the haptic loop is not running (between the handshake and enable(), when a session spends
/// seconds loading its workpiece, and after disable()) it pumps the link, so the transport keeps acknowledging and
/// the server does not time the session out.
/// read() returns the newest device state the server sent (its time stamps continue across a server restart);
/// when no state arrived for watchdog_s the link is down: kFaultIo is raised, nothing but zero force would reach
/// the device (the server's own watchdog zeroes it too), and since the sample's time stamp stops advancing the
/// haptic loop's watchdog sends zero force; a state arriving again brings it back (the loop ramps the force in).
/// After give_up_s without a state read() returns false (the device is gone).
/// Construct, handshake and set_contact on the owning thread before the loop starts; read()/write() from the loop
/// thread; observe_surface() from one publishing thread (the sculpt thread).
class NetDevice final : public HapticDevice {
public:
    /// Takes the link and sends nothing yet (handshake() does). Throws tridex::Error when a period or time-out is
    /// not positive and finite.
    NetDevice(std::unique_ptr<DatagramLink> link, NetDeviceOptions options);
    ~NetDevice() override;

    /// Pumps the link once (non-blocking) and returns true once the server has welcomed this session and its first
    /// device state has arrived (so read() has a sample). Throws tridex::Error with the server's line when it
    /// refused, and "net: the device server at HOST:PORT: the handshake failed: ..." before the first welcome when
    /// the link's handshake failed (DatagramLink::handshake_failure: different keys, or a sealed link facing an
    /// unsealed one) or a server it reached sends datagrams this session cannot read (a sealed server).
    bool handshake();
    /// handshake() until welcomed or timeout_s of the real clock passed; throws tridex::Error "net: no device
    /// server answered at HOST:PORT within T s (is `tridex device-server` running there?)", "net: the device server
    /// at HOST:PORT accepted the connection but did not complete the handshake within T s (...)", or the refusal.
    void wait_for_server(double timeout_s);
    /// Local mode: the contact parameters and workspace mapping the server's loop uses (sent after each
    /// welcome, and when the loop starts if they changed since).
    void set_contact(const ContactMsg& contact);

    /// The served device's profile (from kWelcome); a placeholder named "net (not connected)" before.
    const DeviceProfile& profile() const override { return profile_; }
    /// Link measurements (exchanges = states received, missed_frames = reads without a new state,
    /// malformed_frames = datagrams dropped here, zeroed_ticks = reads with the link down) and the `link` fields.
    DeviceLinkStats link_stats() const override;
    /// Local mode: encodes a snapshot whose sequence differs from the last one offered as the next one to send; the
    /// link thread sends the newest at most once per snapshot_interval_s, and again after a server welcomed the
    /// session anew. Called by the thread that publishes snapshots, never the haptic thread (it allocates and locks).
    /// Distributed mode: nothing.
    void observe_surface(const ActiveSurface& surface) override;
    /// Local mode: the tool sample the server's god-object loop computed with the newest state (what the session
    /// sculpts with), marked stale when the last read() brought no new state (the link stalled or is down); false
    /// in distributed mode or before the contact parameters reached the server. Haptic thread, after read().
    bool remote_tool(RemoteToolSample& out) const override;
    /// Local mode: the tool was resized to `scale` times the contact points set_contact() gave (haptic thread: one
    /// atomic store); the link thread sends the scaled contact parameters. Distributed mode: nothing.
    void observe_tool_scale(double scale) override;
    /// One round of the link thread's work: pumps the link while the haptic loop is not running, and sends the newest
    /// offered snapshot when due. Any thread except the haptic loop's; blocks on the link for at most one send.
    void service();
    /// Drops by reason, for messages.
    const DropCounts& drops() const { return drops_; }
    /// True while the link is down (no state for watchdog_s).
    bool link_down() const { return down_; }
    /// The rendering mode.
    RenderingMode mode() const { return opt_.mode; }

protected:
    /// The loop starts: the silence watchdog counts from now (the server rests its device while a session that
    /// connected is still loading).
    void on_enable() override;
    /// The loop stopped: the link thread pumps the link again.
    void on_disable() noexcept override;
    /// Starts the link thread again after a close().
    void on_open() override;
    /// Stops the link thread (the connection then times out at the server).
    void on_close() noexcept override;
    bool do_read(DeviceState& out) override;
    void do_write(const Vec3& force_n, const Vec3& torque_nm) override;

private:
    void pump();
    void handle(const std::vector<std::uint8_t>& d);
    void send_hello();
    Header header(std::uint32_t seq);
    std::uint64_t now_us() const;
    void note(const std::string& event);
    void start_link_thread();
    void stop_link_thread() noexcept;
    void link_thread_main();

    std::unique_ptr<DatagramLink> link_;
    NetDeviceOptions opt_;
    DeviceProfile profile_;
    bool welcomed_ = false;      // the current connection got its kWelcome
    bool ever_welcomed_ = false;
    bool reached_ = false;       // the link reported a connection (the transport reached a server)
    std::string refusal_;
    LinkEvent ev_;
    std::vector<std::uint8_t> out_;
    std::uint32_t tx_seq_ = 0, hello_seq_ = 0;  // tx_seq_: the unreliable stream (force, heartbeat) whose gaps count as lost
    std::uint32_t reliable_seq_ = 0;              // contact sets and snapshots (delivered by the transport)
    std::uint64_t peer_sent_us_ = 0;  // newest sent_us from the server (echoed back)
    // The newest state and what it took to get it.
    DeviceState state_;
    bool have_state_ = false, fresh_state_ = false;
    bool read_fresh_ = false;  // the last read() returned a state that arrived since the read before (haptic thread)
    bool have_tool_ = false;  // state_ came with the server loop's tool sample tool_
    RemoteToolSample tool_;
    std::uint32_t state_seq_ = 0;
    bool state_seq_valid_ = false;
    double t_offset_s_ = 0.0;     // added to server times so they continue across a server restart
    bool rebase_time_ = false;    // the next state re-bases t_offset_s_
    double last_state_rx_s_ = 0.0, first_state_rx_s_ = -1.0;
    bool down_ = false;
    StateMsg server_;              // the server's counters, as last reported
    std::uint64_t server_lost_base_ = 0, server_trips_base_ = 0, server_stale_base_ = 0;  // totals of earlier servers
    // Local mode.
    ContactMsg contact_;
    ContactMsg contact_base_;                 // as set_contact() gave it, before any tool scale
    std::atomic<double> tool_scale_{1.0};     // the newest tool scale (haptic thread -> link thread)
    double sent_scale_ = 1.0;                 // the scale contact_ carries (under link_mutex_)
    bool have_contact_ = false;
    bool contact_pending_ = false;  // set_contact() since the last send
    // Threads. link_mutex_ guards the link and everything pump() and handle() touch; the haptic thread only
    // try-locks it. snap_mutex_ guards the offered snapshot.
    mutable std::mutex link_mutex_;
    bool loop_on_ = false;        // the haptic loop runs (enable .. disable): only it pumps the link
    bool resend_surface_ = false;  // a (new) server welcomed the session: send the newest snapshot again
    std::mutex snap_mutex_;
    std::condition_variable snap_cv_;
    std::vector<std::uint8_t> offered_;  // the newest offered snapshot, encoded (header filled when sent)
    std::uint64_t offered_seq_ = 0;
    bool stop_thread_ = false;
    std::thread link_thread_;
    std::vector<std::uint8_t> sent_;   // link thread: the snapshot sent last, kept for a resend
    std::uint64_t sent_surface_seq_ = 0;
    double sent_surface_s_ = -1e300;
    // Counters.
    DropCounts drops_;
    std::uint64_t states_ = 0, missed_ = 0, zeroed_ = 0, lost_ = 0, outages_ = 0, stale_tool_ = 0;
    std::uint64_t snapshots_sent_ = 0;
    std::uint64_t states_at_enable_ = 0;  // states received before the loop started (not in rate_hz)
    static constexpr std::size_t kRttSamples = 8192;
    std::array<float, kRttSamples> rtt_us_{};
    std::size_t rtt_count_ = 0;
    std::string events_;
};

}  // namespace tridex::devices::net
