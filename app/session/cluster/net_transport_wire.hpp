// app/session/cluster/net_transport_wire.hpp - what both ends of a network wall (net_transport.hpp) share: the
// datagrams (a message split into data datagrams of at most kMaxChunkBytes and joined again, and the small control
// datagrams of the claim protocol (claim, accept, refuse), of flush (ack) and of abort_all (abort)), and the network
// thread's loop with the lock and signal between it and the session's frame thread.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/session/cluster/cluster_transport.hpp"
#include "devices/net/datagram_link.hpp"

namespace tridex::app::netwire {

/// Version of the control datagrams' layout; a claim of another version is refused.
constexpr std::uint16_t kProtocol = 1;
/// Largest payload of one data datagram (bytes).
constexpr std::size_t kMaxChunkBytes = std::size_t(256) << 10;
/// Largest message joined from data datagrams (bytes); a peer that sends a larger one is disconnected.
constexpr std::size_t kMaxMessageBytes = std::size_t(1) << 30;
/// Longest reason text a refusal carries (bytes).
constexpr std::size_t kMaxReasonBytes = 1000;

/// A message's bytes.
using Message = std::vector<unsigned char>;

constexpr double kPeerTimeoutS = 3.0;    ///< a silent peer is disconnected after this long (s)
constexpr double kAbortFlushS = 1.0;     ///< abort_all waits this long for what it sent to arrive (s)
constexpr int kMaxEventsPerPass = 4096;  ///< events taken from one link per pass of the network thread
/// Bytes of whole messages from one peer not yet received; past it the peer is disconnected (rank 0) or the
/// transport fails (a render rank). One message alone is always taken.
constexpr std::size_t kMaxQueuedBytes = std::size_t(1) << 30;
/// Data bytes a sender hands to its link beyond what the far end acknowledged: each pass of the network thread stays
/// short (ENet times a peer out when its host is not serviced for kPeerTimeoutS while data is unacknowledged), and
/// ENet's queues stay small however large the message.
constexpr std::uint64_t kWindowBytes = std::uint64_t(8) << 20;

/// Byte 0 of every datagram.
enum class Kind : std::uint8_t {
    kDataMore = 0xD1,  ///< a part of a message, more follow
    kDataLast = 0xD2,  ///< the last (or only) part of a message
    kControl = 0xC1,   ///< a control datagram: "TDXW", u16 version, type byte, its fields (little-endian)
};

/// What a control datagram says.
enum class ControlType : std::uint8_t {
    kClaim = 1,   ///< member -> rank 0: the rank it claims
    kAccept = 2,  ///< rank 0 -> member: the claim is taken
    kRefuse = 3,  ///< rank 0 -> member: the claim is refused, with the reason
    kAck = 4,     ///< either way: whole messages and data bytes received from the other end so far
    kAbort = 5,   ///< rank 0 -> member: the session ends with this exit code
};

/// A decoded control datagram; the fields its type does not carry keep their defaults.
struct Control {
    ControlType type = ControlType::kAck;  ///< what it says
    std::uint16_t version = kProtocol;     ///< another version: only `type` and `version` are read
    int rank = 0;                          ///< kClaim, kAccept
    std::string reason{};                  ///< kRefuse
    std::uint64_t count = 0;               ///< kAck: whole messages
    std::uint64_t bytes = 0;               ///< kAck: data bytes (the payloads of data datagrams)
    int code = 0;                          ///< kAbort
};

/// The kind of a datagram (byte 0), or nullopt when it is empty or byte 0 is no Kind.
std::optional<Kind> datagram_kind(const std::vector<std::uint8_t>& datagram);

/// Datagrams a message of `bytes` bytes is split into (an empty message is one datagram).
std::size_t chunk_count(std::size_t bytes);
/// Fills `out` with datagram `i` (0..chunk_count - 1) of `message`: its kind byte and its part of the bytes.
void make_chunk(const std::vector<unsigned char>& message, std::size_t i, std::vector<std::uint8_t>& out);

// The control datagrams, each "TDXW", kProtocol, the type byte and its fields.
/// A claim of render rank `rank` (u16).
std::vector<std::uint8_t> encode_claim(int rank);
/// The acceptance of a claim of `rank` (u16).
std::vector<std::uint8_t> encode_accept(int rank);
/// A refusal with its reason (UTF-8, cut at kMaxReasonBytes).
std::vector<std::uint8_t> encode_refuse(const std::string& reason);
/// An acknowledgement: `count` whole messages and `bytes` data bytes received so far (u64 each).
std::vector<std::uint8_t> encode_ack(std::uint64_t count, std::uint64_t bytes);
/// The end of the session with exit code `code` (i32).
std::vector<std::uint8_t> encode_abort(int code);
/// A control datagram's fields. Throws tridex::Error naming what is wrong (too short, not "TDXW", an unknown type, a
/// length that does not match the type). A datagram of another version is returned with its type and version only.
Control decode_control(const std::vector<std::uint8_t>& datagram);

/// What one link received (network thread only): its data datagrams joined into messages, in order, and the counts
/// its acknowledgements carry.
class Inbox {
public:
    /// Takes a data datagram (kDataMore or kDataLast); returns the message it completes, or nullopt while more parts
    /// are to come. Throws tridex::Error when the message would pass kMaxMessageBytes (the peer is then to be
    /// disconnected: the rest of its stream cannot be read).
    std::optional<Message> push(std::vector<std::uint8_t>& datagram);
    /// Counts a control datagram the sender counts as a message (an abort).
    void count_message() { ++messages_; }
    /// The acknowledgement to send when anything came since the last one, else nullopt (one per pass at most).
    std::optional<std::vector<std::uint8_t>> ack_due();

private:
    Message partial_;
    std::uint64_t messages_ = 0, bytes_ = 0;              // whole messages, data bytes
    std::uint64_t acked_messages_ = 0, acked_bytes_ = 0;  // as the last acknowledgement said
};

/// The messages one link sends (network thread only), handed to it as data datagrams while fewer than kWindowBytes
/// of them are unacknowledged, and an abort once they all went.
class Outbox {
public:
    /// Appends the messages of `more` (which is emptied) after those queued.
    void add(std::deque<Message>& more);
    /// Sends abort(code) once every message queued before it went.
    void add_abort(int code) { abort_ = code; }
    /// Hands datagrams to `link` as the window allows; true when it sent any.
    bool pump(devices::net::DatagramLink& link, std::vector<std::uint8_t>& scratch);
    /// The far end acknowledged `bytes` data bytes in all.
    void acked(std::uint64_t bytes) { acked_ = std::max(acked_, std::min(bytes, sent_)); }
    /// True when nothing is left to hand to the link.
    bool empty() const { return queue_.empty() && !abort_; }

private:
    std::deque<Message> queue_;
    std::size_t chunk_ = 0;  // the next datagram of queue_.front()
    std::uint64_t sent_ = 0, acked_ = 0;
    std::optional<int> abort_;
};

/// "ENet 1.3.17": the version of the ENet headers built against.
std::string enet_version();
/// A duration for messages, "2 s" or "0.5 s" (to 0.1 s).
std::string seconds_text(double s);
/// A devices/net error "--x HOST:PORT: why" as "why", to be given under the cluster option's name.
std::string reason_of(const std::exception& e);

/// What both ends share: the network thread's loop and the lock and signal between it and the frame thread.
class NetTransport : public ClusterTransport {
protected:
    /// Starts the network thread (the derived object is complete by then).
    void start() {
        thread_ = std::thread([this] { run(); });
    }
    /// Stops and joins the network thread; every derived destructor calls it before its members go.
    void stop() {
        stop_.store(true);
        if (thread_.joinable()) thread_.join();
    }
    /// One pass of the network thread; true when it moved anything (then the next pass follows at once).
    virtual bool service() = 0;
    /// The network thread met an unexpected exception (out of memory): the transport fails with `what`.
    virtual void thread_failed(const std::string& what) = 0;

    /// Guards what the network thread and the frame thread share (each derived class says which members).
    mutable std::mutex mutex_;
    /// Notified when a message, an acknowledgement, a claim's answer or a leave comes.
    std::condition_variable cv_;
    /// The datagram being sent (network thread only).
    std::vector<std::uint8_t> scratch_;

private:
    void run();

    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace tridex::app::netwire
