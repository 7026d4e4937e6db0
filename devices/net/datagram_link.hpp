// devices/net/datagram_link.hpp - the transport under the net driver and the device server: datagrams one
// way or the other over a connection, reliable (ordered, retransmitted) or unreliable (newest wins).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tridex::devices::net {

/// What poll() found.
struct LinkEvent {
    enum Kind : std::uint8_t {
        kConnected,     ///< a peer connected (server) or the connection was made (client)
        kDisconnected,  ///< the peer went away or timed out
        kData,          ///< a datagram arrived: `data`
    };
    Kind kind = kData;
    /// kData: the datagram; kConnected: the peer's address as text ("HOST:PORT"), or empty. Its capacity is reused
    /// between polls.
    std::vector<std::uint8_t> data;
};

/// What arrived on a link's socket (any thread may read it).
struct LinkTraffic {
    std::uint64_t datagrams = 0;  ///< UDP datagrams received on the socket, whatever they held
    /// Datagrams from an address other than the connected peer's while one is connected (floods, replays and
    /// spoofed traffic from elsewhere on the network): counted, and dropped unless they ask to connect (so a session
    /// can still take over from a silent one, or be told it is refused).
    std::uint64_t foreign = 0;
};

/// One end of a datagram connection (ENet over UDP, or an in-process shim with injected latency and loss).
/// Not thread-safe: one thread sends and polls.
class DatagramLink {
public:
    virtual ~DatagramLink() = default;
    /// Queues a datagram for the peer: reliable = delivered once, in order, retransmitted as needed (handshake,
    /// snapshots, contact parameters); unreliable = may be lost, never retransmitted (states, forces,
    /// heartbeats). Dropped silently while not connected.
    virtual void send(const std::vector<std::uint8_t>& bytes, bool reliable) = 0;
    /// The next event, without waiting; false when there is none. Also services the transport (sends what
    /// was queued, reconnects a client whose connection dropped).
    virtual bool poll(LinkEvent& ev) = 0;
    /// True while a peer is connected.
    virtual bool connected() const = 0;
    /// "HOST:PORT" of the far end (client) or the listening address (server), for messages.
    virtual const char* where() const = 0;
    /// What arrived on the socket so far; any thread may call it. A transport without a socket returns zeros.
    virtual LinkTraffic traffic() const { return {}; }
    /// True while the transport reached the peer, whether or not connected() yet (a sealed link whose handshake is
    /// pending or failed). A link without a handshake of its own returns connected().
    virtual bool reached() const { return connected(); }
    /// What is known to stop the connection the transport made from carrying datagrams, as one line for messages
    /// ("the handshake failed: ..."): a sealed link's peer that holds another key or sends unsealed datagrams. ""
    /// while nothing is known to be wrong (always, for a link without a handshake of its own).
    virtual std::string handshake_failure() const { return {}; }
    /// A server: ends the current peer's connection once what was queued for it is sent (so it can read why), and is
    /// free for the next peer at once; no kDisconnected follows for it. A client, or a link without peers to
    /// drop: nothing.
    virtual void drop_peer() {}
    /// True when every datagram is authenticated and encrypted (SealedLink); false for a plain transport.
    virtual bool sealed() const { return false; }
    /// Datagrams the link refused as not the peer's (forged, replayed, out of order, truncated: SealStats::refused);
    /// 0 for a link that does not check. Any thread.
    virtual std::uint64_t refused() const { return 0; }
};

}  // namespace tridex::devices::net
