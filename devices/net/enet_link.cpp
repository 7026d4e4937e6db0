// devices/net/enet_link.cpp - the ENet host behind EnetLink.
#include "devices/net/enet_link.hpp"

#include <chrono>
#include <cstdlib>

#include "core/error.hpp"
#include "devices/net/enet_common.hpp"

namespace tridex::devices::net {

namespace {

constexpr double kTakeOverS = 0.5;

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

void split_listen_address(const std::string& s, const std::string& what, std::string& host, std::uint16_t& port) {
    split_host_port(s.find(':') == std::string::npos ? "0.0.0.0:" + s : s, what, host, port, true);
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
    double last_rx_s = 0.0;     // when the peer last sent a datagram
    HostWatch* watch = nullptr;  // this host's counters (nullptr: not counted)

    ~Impl() {
        unwatch_host(watch);
        if (peer && up) {
            enet_peer_disconnect_now(peer, 0);
        }
        if (host) enet_host_destroy(host);
    }
    /// The connected peer (or none): the intercept lets only its datagrams through.
    void set_peer(ENetPeer* p) {
        peer = p;
        up = p != nullptr;
        if (!watch) return;
        if (p) {
            watch->peer_host.store(p->address.host, std::memory_order_relaxed);
            watch->peer_port.store(p->address.port, std::memory_order_relaxed);
        }
        watch->have_peer.store(up, std::memory_order_release);
    }
    void start_connect() {
        peer = enet_host_connect(host, &address, 2, 0);
        if (peer) {
            tune_peer(peer, peer_timeout_s);
        }
        next_retry_s = now_s() + retry_s;
    }
};

EnetLink::EnetLink(std::unique_ptr<Impl> impl, std::string where) : impl_(std::move(impl)), where_(std::move(where)) {}

EnetLink::~EnetLink() = default;

std::unique_ptr<EnetLink> EnetLink::listen(const std::string& host, std::uint16_t port) {
    auto impl = std::make_unique<Impl>();
    impl->server = true;
    // Two peer slots: the session, and one more so a second session can be told it is refused.
    impl->host = listen_host("--listen", host, port, 2);
    impl->watch = watch_host(impl->host);
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
    impl->watch = watch_host(impl->host);
    impl->start_connect();
    return std::unique_ptr<EnetLink>(new EnetLink(std::move(impl), host + ":" + std::to_string(port)));
}

void EnetLink::send(const std::vector<std::uint8_t>& bytes, bool reliable) {
    Impl& m = *impl_;
    if (!m.up || !m.peer) return;
    send_datagram(m.host, m.peer, bytes, reliable);
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
                m.set_peer(e.peer);
                m.last_rx_s = now_s();
                tune_peer(e.peer, m.peer_timeout_s);
                no_throttle(e.peer);
                ev.kind = LinkEvent::kConnected;
                {
                    const std::string who = address_text(e.peer->address);
                    ev.data.assign(who.begin(), who.end());
                }
                return true;
            case ENET_EVENT_TYPE_DISCONNECT:
                if (e.peer != m.peer) continue;
                m.set_peer(nullptr);
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

void EnetLink::drop_peer() {
    Impl& m = *impl_;
    if (!m.server || !m.up || !m.peer) return;
    enet_peer_disconnect_later(m.peer, 0);  // its DISCONNECT event is then another peer's: ignored by poll()
    m.set_peer(nullptr);
    enet_host_flush(m.host);
}

LinkTraffic EnetLink::traffic() const { return watch_traffic(impl_->watch); }

}  // namespace tridex::devices::net
