// devices/net/enet_link.cpp - the ENet host behind EnetLink.
#include "devices/net/enet_link.hpp"

#include <enet/enet.h>

#include <chrono>
#include <cstdlib>
#include <mutex>

#include "core/error.hpp"

namespace tridex::devices::net {

namespace {

constexpr enet_uint8 kReliableChannel = 0, kUnreliableChannel = 1;
constexpr double kTakeOverS = 0.5;

void init_enet_once() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (enet_initialize() != 0) throw Error("net: ENet could not initialise its sockets");
        std::atexit(enet_deinitialize);
    });
}

double now_s() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

void split_host_port(const std::string& s, const std::string& what, std::string& host, std::uint16_t& port,
                     bool allow_port_zero) {
    const auto colon = s.rfind(':');
    const auto bad = [&] {
        return Error(what + ": '" + s + "' is not HOST:PORT (port " + (allow_port_zero ? "0" : "1") + "..65535)");
    };
    if (colon == std::string::npos || colon + 1 >= s.size()) throw bad();
    const std::string p = s.substr(colon + 1);
    if (p.find_first_not_of("0123456789") != std::string::npos || p.size() > 5) throw bad();
    const long v = std::strtol(p.c_str(), nullptr, 10);
    if (v < (allow_port_zero ? 0 : 1) || v > 65535) throw bad();
    host = s.substr(0, colon);
    port = static_cast<std::uint16_t>(v);
}

struct EnetLink::Impl {
    ENetHost* host = nullptr;
    ENetPeer* peer = nullptr;  // the one connected peer (server), or the peer being connected to (client)
    bool server = false;
    bool up = false;
    ENetAddress address{};
    double peer_timeout_s = 1.0;
    double retry_s = 0.2;
    double next_retry_s = 0.0;
    double last_rx_s = 0.0;  // when the peer last sent a datagram

    ~Impl() {
        if (peer && up) {
            enet_peer_disconnect_now(peer, 0);
        }
        if (host) enet_host_destroy(host);
    }
    // Peer time-out, and no throttling: ENet's packet throttle drops unreliable datagrams when the round trip
    // varies, which would thin the 1 kHz states on a busy machine; the link's own watchdogs handle a bad link.
    void tune(ENetPeer* p) const {
        const auto ms = static_cast<enet_uint32>(peer_timeout_s * 1000.0);
        enet_peer_timeout(p, 32, ms, ms);
    }
    // On a connected peer: the throttle stays at its full scale (no unreliable datagram is dropped by it).
    static void no_throttle(ENetPeer* p) {
        p->packetThrottle = ENET_PEER_PACKET_THROTTLE_SCALE;
        p->packetThrottleAcceleration = 0;
        p->packetThrottleDeceleration = 0;
    }
    void start_connect() {
        peer = enet_host_connect(host, &address, 2, 0);
        if (peer) {
            tune(peer);
        }
        next_retry_s = now_s() + retry_s;
    }
};

EnetLink::EnetLink(std::unique_ptr<Impl> impl, std::string where) : impl_(std::move(impl)), where_(std::move(where)) {}

EnetLink::~EnetLink() = default;

std::unique_ptr<EnetLink> EnetLink::listen(const std::string& host, std::uint16_t port) {
    init_enet_once();
    auto impl = std::make_unique<Impl>();
    impl->server = true;
    impl->address.port = port;
    impl->address.host = ENET_HOST_ANY;
    if (!host.empty() && host != "0.0.0.0" && enet_address_set_host(&impl->address, host.c_str()) != 0)
        throw Error("--listen " + host + ":" + std::to_string(port) + ": cannot resolve host '" + host + "'");
    // Two peer slots: the session, and one more so a second session can be told it is refused.
    impl->host = enet_host_create(&impl->address, 2, 2, 0, 0);
    if (!impl->host)
        throw Error("--listen " + host + ":" + std::to_string(port) + ": cannot listen there (address in use?)");
    const std::uint16_t bound = impl->host->address.port;  // ENet reads back the port the system gave
    return std::unique_ptr<EnetLink>(new EnetLink(std::move(impl), host + ":" + std::to_string(bound)));
}

std::uint16_t EnetLink::port() const { return impl_->host->address.port; }

std::unique_ptr<EnetLink> EnetLink::connect(const std::string& host, std::uint16_t port, double peer_timeout_s) {
    init_enet_once();
    auto impl = std::make_unique<Impl>();
    impl->peer_timeout_s = peer_timeout_s;
    impl->address.port = port;
    if (enet_address_set_host(&impl->address, host.c_str()) != 0)
        throw Error("--device net:" + host + ":" + std::to_string(port) + ": cannot resolve host '" + host + "'");
    impl->host = enet_host_create(nullptr, 1, 2, 0, 0);
    if (!impl->host) throw Error("net: ENet could not create a client socket");
    impl->start_connect();
    return std::unique_ptr<EnetLink>(new EnetLink(std::move(impl), host + ":" + std::to_string(port)));
}

void EnetLink::send(const std::vector<std::uint8_t>& bytes, bool reliable) {
    Impl& m = *impl_;
    if (!m.up || !m.peer) return;
    ENetPacket* packet = enet_packet_create(bytes.data(), bytes.size(), reliable ? ENET_PACKET_FLAG_RELIABLE : 0);
    if (!packet) return;
    if (enet_peer_send(m.peer, reliable ? kReliableChannel : kUnreliableChannel, packet) != 0) enet_packet_destroy(packet);
    enet_host_flush(m.host);
}

bool EnetLink::poll(LinkEvent& ev) {
    Impl& m = *impl_;
    if (!m.server && !m.up && m.peer == nullptr && now_s() >= m.next_retry_s) m.start_connect();
    ENetEvent e;
    while (enet_host_service(m.host, &e, 0) > 0) {
        switch (e.type) {
            case ENET_EVENT_TYPE_CONNECT:
                if (m.server && m.up && e.peer != m.peer) {
                    // One session at a time: a newcomer is refused while the current peer speaks, and takes over from
                    // one silent for kTakeOverS (a session that reconnected before ENet timed its old connection out).
                    if (now_s() - m.last_rx_s < kTakeOverS) {
                        enet_peer_disconnect_now(e.peer, 0);
                        continue;
                    }
                    enet_peer_disconnect_now(m.peer, 0);
                }
                m.peer = e.peer;
                m.up = true;
                m.last_rx_s = now_s();
                m.tune(e.peer);
                Impl::no_throttle(e.peer);
                ev.kind = LinkEvent::kConnected;
                ev.data.clear();
                if (char ip[64]; enet_address_get_host_ip(&e.peer->address, ip, sizeof ip) == 0) {
                    const std::string who = std::string(ip) + ":" + std::to_string(e.peer->address.port);
                    ev.data.assign(who.begin(), who.end());
                }
                return true;
            case ENET_EVENT_TYPE_DISCONNECT:
                if (e.peer != m.peer) continue;
                m.up = false;
                m.peer = nullptr;
                if (!m.server) m.next_retry_s = now_s() + m.retry_s;
                ev.kind = LinkEvent::kDisconnected;
                ev.data.clear();
                return true;
            case ENET_EVENT_TYPE_RECEIVE: {
                const bool ours = e.peer == m.peer && m.up;
                if (ours) {
                    m.last_rx_s = now_s();
                    ev.kind = LinkEvent::kData;
                    ev.data.assign(e.packet->data, e.packet->data + e.packet->dataLength);
                }
                enet_packet_destroy(e.packet);
                if (ours) return true;
                continue;
            }
            case ENET_EVENT_TYPE_NONE: break;
        }
    }
    return false;
}

bool EnetLink::connected() const { return impl_->up; }

}  // namespace tridex::devices::net
