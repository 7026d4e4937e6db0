// devices/tracking/dtrack_receiver.hpp - a thread that receives DTrack ASCII datagrams over UDP and keeps the
// newest pose of every standard body and every Flystick (pose, buttons, controllers) with its receipt time.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>

#include "core/triple_buffer.hpp"
#include "devices/tracking/dtrack_parser.hpp"

namespace tridex::devices {

/// Bodies the receiver keeps (DTrack ids 0..kDTrackKeptBodies-1; higher ids are parsed, counted and dropped).
inline constexpr int kDTrackKeptBodies = 64;

/// A silence (ns) after which any frame counter is accepted again: DTrack restarted its counter. Within it, a
/// datagram whose frame counter (`fr`) is older than the newest accepted one is late or replayed and rejected
/// (DTrackReject::kReplayed): the newest pose wins. The newest frame's counter again is accepted (a frame sent in
/// several datagrams).
inline constexpr std::int64_t kDTrackRestartGapNs = 1'000'000'000;

/// The newest sample of one standard body.
struct DTrackBodySample {
    bool seen = false;                ///< false until a datagram carried this body
    DTrackBody body;                  ///< pose (tracker coordinates, m) and quality as DTrack sent it
    std::uint32_t frame_counter = 0;  ///< the datagram's `fr` (0 when absent)
    /// When the datagram arrived: std::chrono::steady_clock time since its epoch, ns.
    std::int64_t receipt_ns = 0;
    std::uint64_t datagram = 0;  ///< 1-based index of the accepted datagram that carried it
};

/// Flysticks the receiver keeps (DTrack Flystick ids 0..kDTrackKeptFlysticks-1; higher ids are counted, dropped).
inline constexpr int kDTrackKeptFlysticks = 16;

/// The newest sample of one Flystick (`6df2`): pose, quality, buttons and controllers as DTrack sent them.
struct DTrackFlystickSample {
    bool seen = false;                ///< false until a datagram carried this Flystick
    DTrackFlystick flystick;          ///< pose (tracker coordinates, m), quality -1 when untracked, buttons, joystick
    std::uint32_t frame_counter = 0;  ///< the datagram's `fr` (0 when absent)
    /// When the datagram arrived: std::chrono::steady_clock time since its epoch, ns.
    std::int64_t receipt_ns = 0;
    std::uint64_t datagram = 0;  ///< 1-based index of the accepted datagram that carried it
};

/// Every kept body's and Flystick's newest sample, as one snapshot.
struct DTrackBodyTable {
    std::array<DTrackBodySample, kDTrackKeptBodies> bodies{};
    std::array<DTrackFlystickSample, kDTrackKeptFlysticks> flysticks{};
    std::uint64_t accepted = 0;  ///< accepted datagrams so far
};

/// Counters of the receiver (any thread may read them).
struct DTrackReceiverStats {
    std::uint64_t datagrams = 0;  ///< datagrams received and parsed (accepted + rejected; counted after those)
    std::uint64_t accepted = 0;
    std::uint64_t rejected = 0;
    std::array<std::uint64_t, static_cast<std::size_t>(DTrackReject::kCount)> by_reason{};  ///< rejected, per reason
    std::uint64_t bytes = 0;                                                                ///< payload bytes received
    std::uint64_t bodies_dropped = 0;  ///< body samples with ids >= kDTrackKeptBodies
    std::uint64_t flysticks_dropped = 0;  ///< Flystick samples with ids >= kDTrackKeptFlysticks
    std::uint64_t socket_errors = 0;   ///< recv() failures other than "no data"
    /// Accepted datagrams in the newest published table (latest()); trails `accepted` until the drain that took
    /// them has published.
    std::uint64_t published = 0;
};

/// Now on the clock of the samples' receipt_ns: std::chrono::steady_clock time since its epoch, ns.
inline std::int64_t dtrack_clock_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

/// The receiver's readers: each is one thread. kView: the render thread (head, Wand navigation); kDevice: a
/// tracked tool's haptic thread (devices/tracking/flystick_device.hpp).
enum class DTrackReader : int { kView = 0, kDevice = 1 };

/// Receives DTrack's ASCII output on a UDP port with one POSIX datagram socket (no library: one socket does
/// not need one) and one thread. The thread waits in poll() (at most 20 ms, so stop() is prompt), then drains
/// the socket without blocking (MSG_DONTWAIT), stamps each datagram with steady_clock on arrival, parses it
/// (parse_dtrack_datagram), rejects a late or replayed frame counter (kDTrackRestartGapNs), counts rejects by reason, and publishes the body and Flystick table once per drain through a
/// TripleBuffer per reader: a reader never waits, locks or allocates. Memory is bounded: one 64 KiB receive
/// buffer, one reused DTrackFrame, three tables per reader. Exactly one thread reads as each DTrackReader.
class DTrackReceiver {
public:
    /// Binds UDP `port` (1..65535, or 0 for a free port chosen by the system: see port()) on `bind_address`
    /// (dotted IPv4; "0.0.0.0" = every interface, which is what DTrack's sender needs; "127.0.0.1" for tests)
    /// and starts the thread. Throws tridex::Error naming the port when the address is not IPv4 or the socket
    /// cannot be created or bound (e.g. the port is in use).
    explicit DTrackReceiver(int port, const std::string& bind_address = "0.0.0.0");
    /// Stops the thread and closes the socket.
    ~DTrackReceiver();
    DTrackReceiver(const DTrackReceiver&) = delete;
    DTrackReceiver& operator=(const DTrackReceiver&) = delete;

    /// The bound UDP port.
    int port() const { return port_; }
    /// Reader side (one thread per DTrackReader): the newest published table. Valid until that reader's next
    /// latest() call.
    const DTrackBodyTable& latest(DTrackReader reader = DTrackReader::kView) {
        return tables_[static_cast<std::size_t>(reader)].latest();
    }
    /// Counters so far (any thread).
    DTrackReceiverStats stats() const;
    /// Stops the thread (idempotent); the last table stays readable.
    void stop();

private:
    void run();
    void handle(const char* data, std::size_t size, std::int64_t receipt_ns);

    int fd_ = -1;
    int port_ = 0;
    std::atomic<bool> stop_{false};
    std::array<TripleBuffer<DTrackBodyTable>, 2> tables_;  // one per DTrackReader
    DTrackBodyTable working_;  // receiver thread only
    DTrackFrame frame_;        // receiver thread only
    bool have_newest_ = false;         // receiver thread only: an accepted datagram carried a frame counter
    std::uint32_t newest_fr_ = 0;      // its counter, and when it arrived (ns)
    std::int64_t newest_receipt_ns_ = 0;
    std::atomic<std::uint64_t> datagrams_{0}, accepted_{0}, rejected_{0}, bytes_{0}, dropped_{0}, socket_errors_{0},
        flysticks_dropped_{0}, published_{0};
    std::array<std::atomic<std::uint64_t>, static_cast<std::size_t>(DTrackReject::kCount)> by_reason_{};
    std::thread thread_;
};

}  // namespace tridex::devices
