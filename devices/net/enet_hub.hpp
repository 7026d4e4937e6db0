// devices/net/enet_hub.hpp - an ENet listener that serves several peers at once and hands each out as its own
// DatagramLink (a shared session: one host, several joiners). docs/devices/enet-hub.md describes it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "devices/net/datagram_link.hpp"

namespace tridex::devices::net {

/// What an EnetHub did so far (a snapshot; read it on the thread that polls).
struct HubStats {
    std::uint64_t accepted = 0;            ///< peers that connected and were queued for accept()
    std::uint64_t refused = 0;             ///< connects refused at once because max_peers peers were connected
    std::uint64_t unreliable_dropped = 0;  ///< unreliable datagrams dropped, oldest first, from a full peer queue
    std::uint64_t overflowed = 0;          ///< peers disconnected because their reliable queue reached its bound
    std::uint64_t stray = 0;               ///< datagrams from peers no longer served (dropped or refused), discarded
    std::size_t connected = 0;             ///< peers served now (handed out by accept() or waiting for it)
};

/// An ENet host (reliable datagrams on channel 0, unreliable sequenced ones on channel 1, as EnetLink) that serves
/// up to max_peers peers at once. accept() hands each newly connected peer out as a DatagramLink of its own, whose
/// poll() services the hub (enet_host_service with timeout 0) and dispatches what arrived into per-peer queues, so
/// that each link can be wrapped in a SealedLink (SealRole::kListener) like a one-peer EnetLink. A peer that connects
/// while max_peers are served is disconnected at once and counted (HubStats::refused).
///
/// Per-peer queues are bounded: past kMaxQueuedUnreliable datagrams or kMaxQueuedUnreliableBytes the oldest
/// unreliable datagrams are dropped (counted); past kMaxQueuedReliable datagrams or kMaxQueuedReliableBytes the peer
/// is disconnected (counted in HubStats::overflowed; its link then reports kDisconnected after what was queued),
/// since a reliable datagram is never dropped silently.
///
/// Lifetime: the links share the hub's state, so a link may outlive the hub; destroying the hub disconnects every
/// peer at once and closes the socket, and each link still held then delivers what was queued, reports
/// kDisconnected and stays dead. Destroying a link disconnects its peer (after its queued reliable datagrams).
/// Not thread-safe: one thread calls the hub and all its links.
class EnetHub {
public:
    static constexpr std::size_t kMaxPeers = 32;                        ///< largest max_peers
    static constexpr int kMaxEventsPerService = 1024;                   ///< ENet events handled per service()
    static constexpr std::size_t kMaxQueuedUnreliable = 256;            ///< unreliable datagrams queued per peer
    static constexpr std::size_t kMaxQueuedUnreliableBytes = 4u << 20;  ///< their bytes, per peer
    static constexpr std::size_t kMaxQueuedReliable = 4096;             ///< reliable datagrams queued per peer
    static constexpr std::size_t kMaxQueuedReliableBytes = 64u << 20;   ///< their bytes, per peer

    /// A hub listening on host:port ("" or "0.0.0.0" = every interface; port 0 = a free port the system picks, which
    /// port() and where() then name), serving up to max_peers (1..kMaxPeers) peers; peer_timeout_s (> 0): how long
    /// a silent peer is kept before its link reports kDisconnected. Throws tridex::Error "--host HOST:PORT: cannot
    /// listen there (address in use?)" when ENet cannot bind, "... cannot resolve host" for an unknown host name, and
    /// "--host HOST:PORT: ..." naming the bad value when max_peers or peer_timeout_s is out of range.
    static std::unique_ptr<EnetHub> listen(const std::string& host, std::uint16_t port, std::size_t max_peers,
                                           double peer_timeout_s = 1.0);
    /// Disconnects every peer at once and closes the socket (links still held report kDisconnected).
    ~EnetHub();
    EnetHub(const EnetHub&) = delete;
    EnetHub& operator=(const EnetHub&) = delete;

    /// The link of the next newly connected peer not yet handed out, or nullptr when there is none (services the
    /// hub first when none is waiting). A peer that left before it was handed out is never handed out. The link:
    /// send() goes to that peer only (dropped once it is gone); poll() reports kConnected (data: the peer's
    /// "HOST:PORT") on its first call, then the peer's kData, then kDisconnected once it left, timed out or was
    /// disconnected by the hub (after the datagrams queued before), and then nothing: connected() is false for
    /// good and a peer that comes back is a new accept(). where() is the peer's "HOST:PORT"; traffic() is the
    /// hub's socket counters (as traffic() below); drop_peer() disconnects the peer after its
    /// queued reliable datagrams, with no kDisconnected after it.
    std::unique_ptr<DatagramLink> accept();
    /// Services ENet (timeout 0) and dispatches at most kMaxEventsPerService events into the per-peer queues
    /// without taking any; a caller may call it once per loop (each link's poll() also does).
    void service();
    /// The local UDP port (bound, so never 0).
    std::uint16_t port() const;
    /// "HOST:PORT" of the listening address, for messages.
    const char* where() const;
    /// The counters so far.
    HubStats stats() const;
    /// The socket's counters so far, readable from any thread: every UDP datagram received (datagrams), and of them
    /// those from an address of none of the hub's peers, connected or connecting (foreign: floods and stray traffic,
    /// and each new peer's first connect), which ENet discards unless they are a valid connect. Zeros once closed, or
    /// when the process watches too many ENet hosts to count this one's.
    LinkTraffic traffic() const;

private:
    struct Core;
    class PeerLink;
    explicit EnetHub(std::shared_ptr<Core> core);
    std::shared_ptr<Core> core_;
};

}  // namespace tridex::devices::net
