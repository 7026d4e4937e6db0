// devices/net/enet_link.cpp - the ENet host behind EnetLink.
#include "devices/net/enet_link.hpp"

#include <enet/enet.h>

#include <array>
#include <atomic>
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

namespace {

/// What the intercept counts for one host, and the address of its connected peer (written by the thread that
/// services the host, read by the intercept on that thread and by traffic() on any).
struct HostWatch {
    std::atomic<ENetHost*> host{nullptr};
    std::atomic<std::uint64_t> datagrams{0}, foreign{0};
    std::atomic<bool> have_peer{false};
    std::atomic<enet_uint32> peer_host{0};
    std::atomic<enet_uint16> peer_port{0};
};

/// The watched hosts (ENet's intercept callback carries no user data): looked up by host, without locks.
std::array<HostWatch, 64> g_watch{};

int ENET_CALLBACK intercept(ENetHost* host, ENetEvent*) {
    for (HostWatch& w : g_watch) {
        if (w.host.load(std::memory_order_acquire) != host) continue;
        w.datagrams.fetch_add(1, std::memory_order_relaxed);
        if (!w.have_peer.load(std::memory_order_acquire)) return 0;
        const ENetAddress& a = host->receivedAddress;
        if (a.host == w.peer_host.load(std::memory_order_relaxed) &&
            a.port == w.peer_port.load(std::memory_order_relaxed))
            return 0;
        w.foreign.fetch_add(1, std::memory_order_relaxed);
        return is_enet_connect(host->receivedData, host->receivedDataLength) ? 0 : 1;
    }
    return 0;
}

/// Takes a free slot for `host` and installs the intercept; nullptr (traffic not counted, the link works as
/// before) when every slot is taken.
HostWatch* watch_host(ENetHost* host) {
    for (HostWatch& w : g_watch) {
        ENetHost* empty = nullptr;
        if (!w.host.compare_exchange_strong(empty, host, std::memory_order_acq_rel)) continue;
        w.datagrams.store(0, std::memory_order_relaxed);
        w.foreign.store(0, std::memory_order_relaxed);
        w.have_peer.store(false, std::memory_order_release);
        host->intercept = intercept;
        return &w;
    }
    return nullptr;
}

}  // namespace

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
        if (watch) watch->host.store(nullptr, std::memory_order_release);
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
                m.set_peer(e.peer);
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

LinkTraffic EnetLink::traffic() const {
    LinkTraffic t;
    if (const HostWatch* w = impl_->watch) {
        t.datagrams = w->datagrams.load(std::memory_order_relaxed);
        t.foreign = w->foreign.load(std::memory_order_relaxed);
    }
    return t;
}

}  // namespace tridex::devices::net
