// devices/net/enet_common.hpp - what EnetLink and EnetHub share over ENet (internal to devices/net; it includes
// <enet/enet.h>, so nothing outside devices/net includes it): the channels, ENet's one-time initialisation, binding
// a listener, tuning a peer, sending one datagram, a peer's address as text, and the per-host datagram counters an
// ENet intercept keeps.
#pragma once

#include <enet/enet.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "devices/net/datagram_link.hpp"

namespace tridex::devices::net {

/// The ENet channel of reliable datagrams (ordered, retransmitted) and of unreliable sequenced ones.
constexpr enet_uint8 kReliableChannel = 0, kUnreliableChannel = 1;

/// enet_initialize() once per process (enet_deinitialize at exit). Throws tridex::Error when ENet cannot initialise.
void init_enet_once();

/// An ENet host bound to host:port ("" or "0.0.0.0" = every interface; port 0 = a port the system picks, which the
/// host's address.port then holds) with `peer_slots` peer slots and two channels. Throws tridex::Error
/// "<what> HOST:PORT: cannot resolve host 'HOST'" or "<what> HOST:PORT: cannot listen there (address in use?)".
ENetHost* listen_host(const std::string& what, const std::string& host, std::uint16_t port, std::size_t peer_slots);

/// Sets how long a silent peer is kept before ENet disconnects it (seconds; enet_peer_timeout).
void tune_peer(ENetPeer* peer, double peer_timeout_s);

/// On a connected peer: ENet's packet throttle stays at its full scale, so it never drops unreliable datagrams when
/// the round trip varies (which would thin 1 kHz states on a busy machine; the links' own watchdogs handle a bad
/// link).
void no_throttle(ENetPeer* peer);

/// Queues `bytes` for `peer` on the reliable or unreliable channel and flushes the host; dropped when ENet cannot
/// allocate or queue the packet.
void send_datagram(ENetHost* host, ENetPeer* peer, const std::vector<std::uint8_t>& bytes, bool reliable);

/// "IP:PORT" of an ENet address, or "" when ENet cannot print it.
std::string address_text(const ENetAddress& address);

/// What the intercept counts for one host, and the address of its connected peer (written by the thread that
/// services the host, read by the intercept on that thread and by traffic() on any). While have_peer is false every
/// datagram is only counted; a hub's (hub true) is also counted as foreign when it comes from an address of none of
/// the host's peers (connected or connecting), and is left to ENet all the same.
struct HostWatch {
    std::atomic<ENetHost*> host{nullptr};
    std::atomic<std::uint64_t> datagrams{0}, foreign{0};
    std::atomic<bool> have_peer{false};
    std::atomic<bool> hub{false};
    std::atomic<enet_uint32> peer_host{0};
    std::atomic<enet_uint16> peer_port{0};
};

/// Takes a free counter slot for `host` and installs the intercept (which counts every datagram, and drops one from
/// an address other than the watched peer's, unless it is an ENet connect); nullptr (traffic not counted, the host
/// works as before) when every slot is taken. The owner calls unwatch_host() before destroying the host.
HostWatch* watch_host(ENetHost* host);

/// Frees the counter slot (nullptr: nothing).
void unwatch_host(HostWatch* watch);

/// The slot's counters as LinkTraffic (zeros for nullptr).
LinkTraffic watch_traffic(const HostWatch* watch);

}  // namespace tridex::devices::net
