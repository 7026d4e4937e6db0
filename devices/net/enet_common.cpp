// devices/net/enet_common.cpp - the ENet pieces EnetLink and EnetHub share.
#include "devices/net/enet_common.hpp"

#include <array>
#include <cstdlib>
#include <mutex>

#include "core/error.hpp"

namespace tridex::devices::net {

void init_enet_once() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (enet_initialize() != 0) throw Error("net: ENet could not initialise its sockets");
        std::atexit(enet_deinitialize);
    });
}

ENetHost* listen_host(const std::string& what, const std::string& host, std::uint16_t port, std::size_t peer_slots) {
    init_enet_once();
    ENetAddress address{};
    address.port = port;
    address.host = ENET_HOST_ANY;
    const std::string where = what + " " + host + ":" + std::to_string(port);
    if (!host.empty() && host != "0.0.0.0" && enet_address_set_host(&address, host.c_str()) != 0)
        throw Error(where + ": cannot resolve host '" + host + "'");
    ENetHost* h = enet_host_create(&address, peer_slots, 2, 0, 0);
    if (!h) throw Error(where + ": cannot listen there (address in use?)");
    return h;
}

void tune_peer(ENetPeer* peer, double peer_timeout_s) {
    const auto ms = static_cast<enet_uint32>(peer_timeout_s * 1000.0);
    enet_peer_timeout(peer, 32, ms, ms);
}

void no_throttle(ENetPeer* peer) {
    peer->packetThrottle = ENET_PEER_PACKET_THROTTLE_SCALE;
    peer->packetThrottleAcceleration = 0;
    peer->packetThrottleDeceleration = 0;
}

void send_datagram(ENetHost* host, ENetPeer* peer, const std::vector<std::uint8_t>& bytes, bool reliable) {
    ENetPacket* packet = enet_packet_create(bytes.data(), bytes.size(), reliable ? ENET_PACKET_FLAG_RELIABLE : 0);
    if (!packet) return;
    if (enet_peer_send(peer, reliable ? kReliableChannel : kUnreliableChannel, packet) != 0)
        enet_packet_destroy(packet);
    enet_host_flush(host);
}

std::string address_text(const ENetAddress& address) {
    char ip[64];
    if (enet_address_get_host_ip(&address, ip, sizeof ip) != 0) return {};
    return std::string(ip) + ":" + std::to_string(address.port);
}

namespace {

/// True when a raw ENet datagram's first command is a connect from a peer that has no id yet (ENet's protocol.h:
/// a big-endian 16-bit peer id whose top two bits are flags, 2 more bytes of sent time when the sent-time flag is set,
/// then the command byte, its low 4 bits the command).
bool is_enet_connect(const enet_uint8* data, std::size_t size) {
    if (size < 2) return false;
    const unsigned peer_id = (static_cast<unsigned>(data[0]) << 8) | data[1];
    const std::size_t header = (peer_id & ENET_PROTOCOL_HEADER_FLAG_SENT_TIME) ? 4 : 2;
    if (size <= header) return false;
    const bool no_id = (peer_id & ENET_PROTOCOL_MAXIMUM_PEER_ID) == ENET_PROTOCOL_MAXIMUM_PEER_ID;
    return no_id && (data[header] & ENET_PROTOCOL_COMMAND_MASK) == ENET_PROTOCOL_COMMAND_CONNECT;
}

/// True when `a` is the address of one of the host's peers that is not disconnected (connected or connecting).
bool from_a_peer(const ENetHost* host, const ENetAddress& a) {
    for (std::size_t i = 0; i < host->peerCount; ++i) {
        const ENetPeer& p = host->peers[i];
        if (p.state != ENET_PEER_STATE_DISCONNECTED && p.address.host == a.host && p.address.port == a.port) return true;
    }
    return false;
}

/// The watched hosts (ENet's intercept callback carries no user data): looked up by host, without locks.
std::array<HostWatch, 64> g_watch{};

int ENET_CALLBACK intercept(ENetHost* host, ENetEvent*) {
    for (HostWatch& w : g_watch) {
        if (w.host.load(std::memory_order_acquire) != host) continue;
        w.datagrams.fetch_add(1, std::memory_order_relaxed);
        if (!w.have_peer.load(std::memory_order_acquire)) {
            if (w.hub.load(std::memory_order_relaxed) && !from_a_peer(host, host->receivedAddress))
                w.foreign.fetch_add(1, std::memory_order_relaxed);
            return 0;
        }
        const ENetAddress& a = host->receivedAddress;
        if (a.host == w.peer_host.load(std::memory_order_relaxed) &&
            a.port == w.peer_port.load(std::memory_order_relaxed))
            return 0;
        w.foreign.fetch_add(1, std::memory_order_relaxed);
        return is_enet_connect(host->receivedData, host->receivedDataLength) ? 0 : 1;
    }
    return 0;
}

}  // namespace

HostWatch* watch_host(ENetHost* host) {
    for (HostWatch& w : g_watch) {
        ENetHost* empty = nullptr;
        if (!w.host.compare_exchange_strong(empty, host, std::memory_order_acq_rel)) continue;
        w.datagrams.store(0, std::memory_order_relaxed);
        w.foreign.store(0, std::memory_order_relaxed);
        w.have_peer.store(false, std::memory_order_release);
        w.hub.store(false, std::memory_order_relaxed);
        host->intercept = intercept;
        return &w;
    }
    return nullptr;
}

void unwatch_host(HostWatch* watch) {
    if (watch) watch->host.store(nullptr, std::memory_order_release);
}

LinkTraffic watch_traffic(const HostWatch* watch) {
    LinkTraffic t;
    if (watch) {
        t.datagrams = watch->datagrams.load(std::memory_order_relaxed);
        t.foreign = watch->foreign.load(std::memory_order_relaxed);
    }
    return t;
}

}  // namespace tridex::devices::net
