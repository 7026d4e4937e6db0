// devices/net/enet_link.hpp - DatagramLink over ENet (Debian libenet-dev): reliable datagrams on channel 0,
// unreliable sequenced ones on channel 1, one peer at a time.
//
// Why ENet rather than Asio: the link needs exactly what ENet is, a connection over UDP with a reliable ordered
// channel (handshake, snapshots) beside an unreliable one that drops late datagrams (1 kHz states and forces),
// fragmentation of large reliable datagrams, and peer time-outs; over Asio each of these would be our code.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "devices/net/datagram_link.hpp"

namespace tridex::devices::net {

/// "HOST:PORT" split; throws tridex::Error "<what>: 'x' is not HOST:PORT (port 1..65535)" naming `what`.
/// allow_port_zero: port 0 is accepted (a listener on a port the system picks).
void split_host_port(const std::string& s, const std::string& what, std::string& host, std::uint16_t& port,
                     bool allow_port_zero = false);

/// A listening address "[ADDR:]PORT" split: ADDR defaults to "0.0.0.0" (every interface), PORT may be 0 (one the
/// system picks). Throws tridex::Error as split_host_port, naming `what`.
void split_listen_address(const std::string& s, const std::string& what, std::string& host, std::uint16_t& port);

/// An ENet host serving one peer (listen) or connected to a server (connect). Not thread-safe: one thread
/// sends and polls. A client whose connection drops (server gone or restarted) tries again every
/// 0.2 s from poll(); a server takes the next peer after its peer left, refuses a second peer while the current
/// one speaks (the newcomer is disconnected at once), and lets a newcomer take over from a peer silent for 0.5 s (a
/// session that reconnected before ENet timed its old connection out). While a peer is connected, a datagram from
/// any other address is counted as foreign and dropped before ENet reads it, unless it is an ENet connect.
class EnetLink final : public DatagramLink {
public:
    /// A server listening on host:port ("0.0.0.0" or "" = every interface; port 0 = a free port the system picks,
    /// which where() and port() then name). Throws tridex::Error "--listen HOST:PORT: cannot listen (address in
    /// use?)" when ENet cannot bind.
    static std::unique_ptr<EnetLink> listen(const std::string& host, std::uint16_t port);
    /// A client connecting to host:port (not waiting: poll() reports kConnected). Throws tridex::Error when the
    /// host name does not resolve. peer_timeout_s: how long a silent peer is kept before kDisconnected.
    static std::unique_ptr<EnetLink> connect(const std::string& host, std::uint16_t port, double peer_timeout_s = 1.0);
    ~EnetLink() override;

    void send(const std::vector<std::uint8_t>& bytes, bool reliable) override;
    bool poll(LinkEvent& ev) override;
    bool connected() const override;
    const char* where() const override { return where_.c_str(); }
    /// Datagrams received and foreign ones (LinkTraffic), counted by an ENet intercept before ENet parses them.
    LinkTraffic traffic() const override;
    /// A server: disconnects the current peer after its queued reliable datagrams (enet_peer_disconnect_later) and
    /// takes the next connect at once; a client: nothing.
    void drop_peer() override;
    /// The local UDP port (a listener's, once bound).
    std::uint16_t port() const;

private:
    struct Impl;
    explicit EnetLink(std::unique_ptr<Impl> impl, std::string where);
    std::unique_ptr<Impl> impl_;
    std::string where_;
};

}  // namespace tridex::devices::net
