// devices/net/enet_hub.cpp - the ENet host behind EnetHub, its per-peer queues and the per-peer links.
#include "devices/net/enet_hub.hpp"

#include <algorithm>
#include <deque>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "devices/net/enet_common.hpp"

namespace tridex::devices::net {

namespace {

/// Datagrams waiting for a link's poll(), oldest first, with their arrival numbers and total size.
struct Queue {
    struct Item {
        std::uint64_t seq = 0;
        std::vector<std::uint8_t> bytes;
    };
    std::deque<Item> items;
    std::size_t bytes = 0;

    void push(std::uint64_t seq, const ENetPacket& packet) {
        items.push_back({seq, std::vector<std::uint8_t>(packet.data, packet.data + packet.dataLength)});
        bytes += packet.dataLength;
    }
    /// Moves the oldest datagram into `out` (its capacity is reused for the next datagram).
    void pop_into(std::vector<std::uint8_t>& out) {
        bytes -= items.front().bytes.size();  // before the swap: the item then holds out's old bytes
        out.swap(items.front().bytes);
        items.pop_front();
    }
    void drop_front() {
        bytes -= items.front().bytes.size();
        items.pop_front();
    }
    bool over(std::size_t max_items, std::size_t max_bytes) const {
        return items.size() > max_items || bytes > max_bytes;
    }
    void clear() {
        items.clear();
        bytes = 0;
    }
};

/// One peer's state, shared by the hub's core and the peer's link.
struct HubPeer {
    ENetPeer* peer = nullptr;  // while the hub serves it; nullptr once it left, was dropped, or the hub closed
    std::string where;         // "HOST:PORT"
    Queue reliable, unreliable;
    std::uint64_t next_seq = 0;  // arrival number of the next datagram (keeps the two queues in arrival order)
    bool left = false;           // it left, timed out or was disconnected: kDisconnected follows the queued data
};

}  // namespace

struct EnetHub::Core {
    ENetHost* host = nullptr;    // nullptr once closed
    HostWatch* watch = nullptr;  // the socket's counters (nullptr: not counted)
    std::size_t max_peers = 1;
    double peer_timeout_s = 1.0;
    std::string where;
    std::vector<std::shared_ptr<HubPeer>> served;  // every peer with an ENet connection (peer != nullptr)
    std::deque<std::shared_ptr<HubPeer>> waiting;  // served, not yet handed out by accept()
    HubStats stats;

    ~Core() { close(); }

    /// Forgets p's ENet peer: no event of it reaches p any more.
    void detach(HubPeer& p) {
        if (p.peer) p.peer->data = nullptr;
        p.peer = nullptr;
        const auto is_p = [&](const std::shared_ptr<HubPeer>& q) { return q.get() == &p; };
        served.erase(std::remove_if(served.begin(), served.end(), is_p), served.end());
        waiting.erase(std::remove_if(waiting.begin(), waiting.end(), is_p), waiting.end());
    }
    /// Disconnects p's peer after its queued reliable datagrams (its later DISCONNECT event is ignored).
    void drop(HubPeer& p) {
        if (!p.peer) return;
        enet_peer_disconnect_later(p.peer, 0);
        if (host) enet_host_flush(host);
        detach(p);
    }
    void close() {
        for (const std::shared_ptr<HubPeer>& p : served) {
            enet_peer_disconnect_now(p->peer, 0);
            p->peer->data = nullptr;
            p->peer = nullptr;
            p->left = true;
        }
        served.clear();
        waiting.clear();
        unwatch_host(watch);
        watch = nullptr;
        if (host) enet_host_destroy(host);
        host = nullptr;
    }
    void service() {
        if (!host) return;
        ENetEvent e;
        for (int i = 0; i < kMaxEventsPerService && enet_host_service(host, &e, 0) > 0; ++i) {
            switch (e.type) {
                case ENET_EVENT_TYPE_CONNECT: on_connect(e.peer); break;
                case ENET_EVENT_TYPE_DISCONNECT:
                    if (auto* p = static_cast<HubPeer*>(e.peer->data)) {
                        p->left = true;
                        detach(*p);
                    }
                    break;
                case ENET_EVENT_TYPE_RECEIVE:
                    on_receive(e.peer, *e.packet);
                    enet_packet_destroy(e.packet);
                    break;
                case ENET_EVENT_TYPE_NONE: break;
            }
        }
    }
    void on_connect(ENetPeer* peer) {
        if (auto* old = static_cast<HubPeer*>(peer->data)) {  // a slot ENet reused without a DISCONNECT event
            old->left = true;
            detach(*old);
        }
        if (served.size() >= max_peers) {
            enet_peer_disconnect_now(peer, 0);
            ++stats.refused;
            return;
        }
        auto p = std::make_shared<HubPeer>();
        p->peer = peer;
        p->where = address_text(peer->address);
        peer->data = p.get();
        tune_peer(peer, peer_timeout_s);
        no_throttle(peer);
        served.push_back(p);
        waiting.push_back(std::move(p));
        ++stats.accepted;
    }
    void on_receive(ENetPeer* peer, const ENetPacket& packet) {
        auto* p = static_cast<HubPeer*>(peer->data);
        if (!p) {
            ++stats.stray;
            return;
        }
        if (packet.flags & ENET_PACKET_FLAG_RELIABLE) {
            p->reliable.push(p->next_seq++, packet);
            if (!p->reliable.over(kMaxQueuedReliable, kMaxQueuedReliableBytes)) return;
            // The link's reader does not keep up: the peer goes (its link delivers what was queued, this datagram
            // too, then kDisconnected) rather than lose a reliable datagram silently.
            enet_peer_disconnect_now(peer, 0);
            p->left = true;
            detach(*p);
            ++stats.overflowed;
            return;
        }
        p->unreliable.push(p->next_seq++, packet);
        while (!p->unreliable.items.empty() && p->unreliable.over(kMaxQueuedUnreliable, kMaxQueuedUnreliableBytes)) {
            p->unreliable.drop_front();
            ++stats.unreliable_dropped;
        }
    }
};

/// One peer's DatagramLink (EnetHub::accept() documents it).
class EnetHub::PeerLink final : public DatagramLink {
public:
    PeerLink(std::shared_ptr<Core> core, std::shared_ptr<HubPeer> peer)
        : core_(std::move(core)), peer_(std::move(peer)) {}
    ~PeerLink() override { core_->drop(*peer_); }
    PeerLink(const PeerLink&) = delete;
    PeerLink& operator=(const PeerLink&) = delete;

    void send(const std::vector<std::uint8_t>& bytes, bool reliable) override {
        if (peer_->peer && core_->host) send_datagram(core_->host, peer_->peer, bytes, reliable);
    }
    bool poll(LinkEvent& ev) override {
        if (dead_) return false;
        HubPeer& p = *peer_;
        if (p.reliable.items.empty() && p.unreliable.items.empty()) core_->service();
        if (!announced_) {
            announced_ = true;
            ev.kind = LinkEvent::kConnected;
            ev.data.assign(p.where.begin(), p.where.end());
            return true;
        }
        Queue* q = nullptr;
        if (!p.reliable.items.empty()) q = &p.reliable;
        if (!p.unreliable.items.empty() && (!q || p.unreliable.items.front().seq < q->items.front().seq))
            q = &p.unreliable;
        if (q) {
            ev.kind = LinkEvent::kData;
            q->pop_into(ev.data);
            return true;
        }
        if (!p.left) return false;
        dead_ = true;
        ev.kind = LinkEvent::kDisconnected;
        ev.data.clear();
        return true;
    }
    bool connected() const override { return !dead_ && peer_->peer != nullptr; }
    const char* where() const override { return peer_->where.c_str(); }
    LinkTraffic traffic() const override { return watch_traffic(core_->watch); }
    void drop_peer() override {
        core_->drop(*peer_);
        peer_->reliable.clear();
        peer_->unreliable.clear();
        dead_ = true;
    }

private:
    std::shared_ptr<Core> core_;
    std::shared_ptr<HubPeer> peer_;
    bool announced_ = false;  // kConnected went upward
    bool dead_ = false;       // kDisconnected went upward, or the peer was dropped: nothing more
};

EnetHub::EnetHub(std::shared_ptr<Core> core) : core_(std::move(core)) {}

EnetHub::~EnetHub() { core_->close(); }

std::unique_ptr<EnetHub> EnetHub::listen(const std::string& host, std::uint16_t port, std::size_t max_peers,
                                         double peer_timeout_s) {
    const std::string what = "--host " + host + ":" + std::to_string(port);
    if (max_peers < 1 || max_peers > kMaxPeers)
        throw Error(what + ": " + std::to_string(max_peers) + " peers is not 1.." + std::to_string(kMaxPeers));
    if (!(peer_timeout_s > 0.0))
        throw Error(what + ": a peer time-out of " + std::to_string(peer_timeout_s) + " s is not positive");
    auto core = std::make_shared<Core>();
    core->max_peers = max_peers;
    core->peer_timeout_s = peer_timeout_s;
    // Slots for the peers served, one per peer still being dropped (disconnect_later), and one so a peer beyond
    // max_peers can be told it is refused.
    core->host = listen_host("--host", host, port, 2 * max_peers + 1);
    core->watch = watch_host(core->host);
    if (core->watch) core->watch->hub.store(true, std::memory_order_relaxed);
    core->where = host + ":" + std::to_string(core->host->address.port);
    return std::unique_ptr<EnetHub>(new EnetHub(std::move(core)));
}

std::unique_ptr<DatagramLink> EnetHub::accept() {
    Core& c = *core_;
    if (c.waiting.empty()) c.service();
    if (c.waiting.empty()) return nullptr;
    std::shared_ptr<HubPeer> p = std::move(c.waiting.front());
    c.waiting.pop_front();
    return std::make_unique<PeerLink>(core_, std::move(p));
}

void EnetHub::service() { core_->service(); }

std::uint16_t EnetHub::port() const { return core_->host ? core_->host->address.port : 0; }

const char* EnetHub::where() const { return core_->where.c_str(); }

LinkTraffic EnetHub::traffic() const { return watch_traffic(core_->watch); }

HubStats EnetHub::stats() const {
    HubStats s = core_->stats;
    s.connected = core_->served.size();
    return s;
}

}  // namespace tridex::devices::net
