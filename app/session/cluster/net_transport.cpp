// app/session/cluster/net_transport.cpp - rank 0 of a network wall: an EnetHub whose peers (each its own link,
// sealed with the session's key when there is one) claim the render ranks; a network thread moves whole messages
// between the links and per-rank queues (mutex + condition variable) that the session's frame thread reads and
// fills. net_transport_member.cpp is the render ranks' end; net_transport_wire.cpp their datagrams.
#include "app/session/cluster/net_transport.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <memory>
#include <utility>

#include "app/session/cluster/net_transport_wire.hpp"
#include "core/error.hpp"
#include "devices/net/enet_hub.hpp"

namespace tridex::app {

namespace net = devices::net;
using namespace netwire;

namespace {

constexpr double kClaimTimeoutS = 10.0;  // a connected process that claims no rank in this long is dropped

double steady_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

std::string overflow_text() {
    return "it sent more than " + std::to_string(kMaxQueuedBytes >> 20) + " MiB that were not received";
}

/// Rank 0 of a network wall (make_listener_transport documents it).
class ListenerTransport final : public NetTransport {
public:
    ListenerTransport(std::unique_ptr<net::EnetHub> hub, int render_ranks, const std::optional<net::SessionKey>& key,
                      const std::string& host)
        : hub_(std::move(hub)),
          key_(key),
          render_ranks_(render_ranks),
          port_(hub_->port()),
          slots_(static_cast<std::size_t>(render_ranks) + 1) {
        name_ = "ENet " + enet_version() + " on " + host + ":" + std::to_string(port_) + (key_ ? " (sealed)" : "");
        start();
    }
    ~ListenerTransport() override { stop(); }
    ListenerTransport(const ListenerTransport&) = delete;
    ListenerTransport& operator=(const ListenerTransport&) = delete;

    int rank() const override { return 0; }
    int size() const override { return render_ranks_ + 1; }
    std::string name() const override { return name_; }
    bool open_membership() const override { return true; }
    /// The bound UDP port.
    std::uint16_t port() const { return port_; }

    void send(int to, std::vector<unsigned char> bytes) override {
        check_rank(to, "send to");
        std::lock_guard lock(mutex_);
        Slot& s = slots_[static_cast<std::size_t>(to)];
        if (!s.present) return;
        s.out.push_back(std::move(bytes));
        ++s.sent;
    }

    std::optional<std::vector<unsigned char>> receive(int from, Clock::time_point deadline) override {
        check_rank(from, "receive from");
        std::unique_lock lock(mutex_);
        Slot& s = slots_[static_cast<std::size_t>(from)];
        cv_.wait_until(lock, deadline, [&] { return !s.in.empty() || s.left; });
        if (!s.in.empty()) {
            Message m = std::move(s.in.front());
            s.in.pop_front();
            s.in_bytes -= m.size();
            return m;
        }
        if (s.left) throw Error("render rank " + std::to_string(from) + " left (" + s.left_reason + ")");
        return std::nullopt;
    }

    bool flush(Clock::time_point deadline) override {
        std::unique_lock lock(mutex_);
        const auto all_acked = [&] {
            return std::all_of(slots_.begin(), slots_.end(),
                               [](const Slot& s) { return !s.lost && s.acked >= s.sent; });
        };
        const auto any_lost = [&] {
            return std::any_of(slots_.begin(), slots_.end(), [](const Slot& s) { return s.lost; });
        };
        cv_.wait_until(lock, deadline, [&] { return all_acked() || any_lost(); });
        return all_acked();
    }

    [[noreturn]] void abort_all(int code) override {
        std::unique_lock lock(mutex_);
        for (Slot& s : slots_)
            if (s.present) {
                s.abort = code;
                ++s.sent;  // the member counts the abort as a message and acknowledges it
            }
        // Until every process present has the abort, or the time is up.
        cv_.wait_until(lock, deadline_after(kAbortFlushS), [&] {
            return std::all_of(slots_.begin(), slots_.end(),
                               [](const Slot& s) { return !s.present || s.acked >= s.sent; });
        });
        std::_Exit(code);
    }

    std::vector<int> arrivals() override {
        std::lock_guard lock(mutex_);
        return std::exchange(arrivals_, {});
    }

    bool present(int r) const override {
        if (r == 0) return true;
        if (r < 1 || r > render_ranks_) return false;
        std::lock_guard lock(mutex_);
        return slots_[static_cast<std::size_t>(r)].present;
    }

    void release(int r) override {
        check_rank(r, "release");
        std::lock_guard lock(mutex_);
        Slot& s = slots_[static_cast<std::size_t>(r)];
        if (s.holder) drops_.push_back(Drop{s.holder, std::move(s.out)});
        s = Slot{};
        arrivals_.erase(std::remove(arrivals_.begin(), arrivals_.end(), r), arrivals_.end());
    }

private:
    /// One render rank as the frame thread sees it (under mutex_).
    struct Slot {
        bool present = false;      // a process holds the rank and is connected
        std::uint64_t holder = 0;  // the number of the peer that holds it (0: none)
        bool left = false;         // its process disconnected and it was not released since
        std::string left_reason{};
        std::string where{};       // its process's address
        std::deque<Message> in{};  // whole messages from it, not yet received
        std::size_t in_bytes = 0;
        std::deque<Message> out{};   // messages for it, not yet handed to the link
        std::optional<int> abort{};  // an abort to send after `out`
        std::uint64_t sent = 0;      // messages queued for its process (and an abort)
        std::uint64_t acked = 0;     // of them, received whole by its process
        bool lost = false;           // its process left before acknowledging all: flush cannot succeed
    };
    /// One connected process, on the network thread only.
    struct Peer {
        std::unique_ptr<net::DatagramLink> link;
        std::string where;
        double since_s = 0.0;  // when it connected
        int rank = 0;          // the rank it holds (0: no claim taken yet)
        std::uint64_t id = 0;  // its number while it holds a rank
        Inbox inbox{};
        Outbox outbox{};
        bool releasing = false;  // its rank was released: dropped once its outbox is empty
        bool gone = false;       // dropped or disconnected: removed at the end of the pass
    };
    /// A released rank's old process: dropped once `out` went to it.
    struct Drop {
        std::uint64_t id = 0;
        std::deque<Message> out{};
    };

    void check_rank(int r, const char* what) const {
        if (r < 1 || r > render_ranks_)
            throw Error("cluster: rank 0 cannot " + std::string(what) + " rank " + std::to_string(r) +
                        " (render ranks 1.." + std::to_string(render_ranks_) + ")");
    }

    bool service() override {
        bool busy = accept_peers();
        for (auto& p : peers_)
            if (!p->gone) busy |= poll_peer(*p);
        busy |= release_peers();
        for (auto& p : peers_)
            if (!p->gone && (p->rank || p->releasing)) busy |= pump(*p);
        peers_.erase(std::remove_if(peers_.begin(), peers_.end(), [](const auto& p) { return p->gone; }), peers_.end());
        return busy;
    }

    void thread_failed(const std::string& what) override {
        std::fprintf(stderr, "tridex: cluster: rank 0's network thread: %s\n", what.c_str());
    }

    bool accept_peers() {
        bool any = false;
        while (std::unique_ptr<net::DatagramLink> inner = hub_->accept()) {
            auto p = std::make_unique<Peer>();
            p->where = inner->where();
            p->since_s = steady_s();
            p->link = key_ ? std::make_unique<net::SealedLink>(std::move(inner), *key_, net::SealRole::kListener)
                           : std::move(inner);
            peers_.push_back(std::move(p));
            any = true;
        }
        return any;
    }

    bool poll_peer(Peer& p) {
        net::LinkEvent ev;
        int n = 0;
        while (!p.gone && n < kMaxEventsPerPass && p.link->poll(ev)) {
            ++n;
            if (ev.kind == net::LinkEvent::kDisconnected) {
                leave(p, "its connection closed or timed out");
            } else if (ev.kind == net::LinkEvent::kData) {
                try {
                    on_datagram(p, ev.data);
                } catch (const Error& e) {
                    refuse(p, std::string("rank 0 could not read a datagram: ") + e.what());
                    leave(p, std::string("it sent a malformed datagram: ") + e.what());
                }
            }
        }
        if (p.gone) return n > 0;
        if (const std::string failure = p.link->handshake_failure(); !failure.empty()) {
            std::fprintf(stderr, "tridex: cluster: the process at %s was refused: %s\n", p.where.c_str(),
                         failure.c_str());
            p.link->drop_peer();
            leave(p, failure);
        } else if (!p.rank && !p.releasing && steady_s() - p.since_s > kClaimTimeoutS) {
            refuse(p, "no claim of a rank within " + seconds_text(kClaimTimeoutS));
        }
        return n > 0;
    }

    void on_datagram(Peer& p, std::vector<std::uint8_t>& d) {
        const std::optional<Kind> kind = datagram_kind(d);
        if (p.releasing) {  // only its acknowledgements still matter: they open the window for what it is owed
            if (kind == Kind::kControl) {
                const Control c = decode_control(d);
                if (c.type == ControlType::kAck) p.outbox.acked(c.bytes);
            }
            return;
        }
        if (!kind) throw Error("a datagram of " + std::to_string(d.size()) + " bytes that is not this protocol's");
        if (*kind != Kind::kControl) {
            if (!p.rank) throw Error("a message before the claim of a rank");
            std::optional<Message> m;
            try {
                m = p.inbox.push(d);
            } catch (const Error& e) {
                refuse(p, std::string("rank 0 refuses ") + e.what());
                leave(p, std::string("it sent ") + e.what());
                return;
            }
            if (m) deliver(p, std::move(*m));
            return;
        }
        const Control c = decode_control(d);
        if (c.type == ControlType::kClaim && !p.rank) return on_claim(p, c);
        if (c.version != kProtocol) throw Error("a control datagram of version " + std::to_string(c.version));
        if (c.type == ControlType::kAck && p.rank) {
            p.outbox.acked(c.bytes);
            std::lock_guard lock(mutex_);
            Slot& s = slots_[static_cast<std::size_t>(p.rank)];
            if (s.holder == p.id) s.acked = std::max(s.acked, std::min(c.count, s.sent));
            cv_.notify_all();
            return;
        }
        throw Error("a control datagram of type " + std::to_string(static_cast<int>(c.type)) + " from " +
                    (p.rank ? "render rank " + std::to_string(p.rank) : std::string("a process without a rank")));
    }

    void on_claim(Peer& p, const Control& c) {
        if (c.version != kProtocol)
            return refuse(p, "it speaks protocol version " + std::to_string(c.version) + ", rank 0 version " +
                                 std::to_string(kProtocol) + " (run the same tridex on every rank)");
        if (c.rank < 1 || c.rank > render_ranks_)
            return refuse(p, "rank " + std::to_string(c.rank) + " is not a render rank of this wall (1.." +
                                 std::to_string(render_ranks_) + ")");
        std::string held_by;
        bool taken = false;
        {
            std::lock_guard lock(mutex_);
            Slot& s = slots_[static_cast<std::size_t>(c.rank)];
            if (s.present) {
                held_by = s.where;
            } else {
                s = Slot{};  // what an earlier process of the rank sent and was not received is dropped
                s.present = true;
                s.holder = p.id = ++next_id_;
                s.where = p.where;
                arrivals_.erase(std::remove(arrivals_.begin(), arrivals_.end(), c.rank), arrivals_.end());
                arrivals_.push_back(c.rank);
                taken = true;
            }
        }
        if (!taken)
            return refuse(p, "render rank " + std::to_string(c.rank) + " is held by the connected process at " +
                                 held_by + " (a new process may claim it once that one left and was released)");
        p.rank = c.rank;
        p.link->send(encode_accept(c.rank), true);
        std::fprintf(stderr, "tridex: cluster: the process at %s claimed render rank %d\n", p.where.c_str(), c.rank);
    }

    // Answers the peer with a refusal and disconnects it once that is sent (leave() then frees a rank it held).
    void refuse(Peer& p, const std::string& why) {
        if (p.gone) return;
        std::fprintf(stderr, "tridex: cluster: refused the process at %s: %s\n", p.where.c_str(), why.c_str());
        p.link->send(encode_refuse(why), true);
        p.link->drop_peer();
        p.gone = true;
    }

    // The peer's connection ended or it was dropped for `why`: it is forgotten, and a rank it held is absent, with
    // `why` to tell.
    void leave(Peer& p, const std::string& why) {
        p.gone = true;
        if (!p.rank) return;
        {
            std::lock_guard lock(mutex_);
            Slot& s = slots_[static_cast<std::size_t>(p.rank)];
            if (s.holder == p.id) {
                s.present = false;
                s.holder = 0;
                s.left = true;
                s.left_reason = why;
                s.out.clear();
                s.abort.reset();
                s.lost = s.acked < s.sent;
            }
            cv_.notify_all();
        }
        p.rank = 0;
    }

    void deliver(Peer& p, Message m) {
        {
            std::lock_guard lock(mutex_);
            Slot& s = slots_[static_cast<std::size_t>(p.rank)];
            if (s.holder != p.id) return;  // released: what it sends is dropped
            if (s.in_bytes + m.size() <= kMaxQueuedBytes || s.in.empty()) {
                s.in_bytes += m.size();
                s.in.push_back(std::move(m));
                cv_.notify_all();
                return;
            }
        }
        refuse(p, "rank 0 refuses: " + overflow_text());
        leave(p, overflow_text());
    }

    // A released rank's old process is owed what was queued for it before the release: it is dropped once that went.
    bool release_peers() {
        std::vector<Drop> drops;
        {
            std::lock_guard lock(mutex_);
            drops.swap(drops_);
        }
        for (Drop& d : drops)
            for (auto& p : peers_)
                if (!p->gone && p->rank && p->id == d.id) {
                    p->outbox.add(d.out);
                    p->releasing = true;
                    p->rank = 0;
                }
        return !drops.empty();
    }

    // Takes what the frame thread queued for the peer, hands the link what the window allows, and acknowledges what
    // came from it.
    bool pump(Peer& p) {
        if (p.rank) {
            std::lock_guard lock(mutex_);
            Slot& s = slots_[static_cast<std::size_t>(p.rank)];
            if (s.holder == p.id) {
                p.outbox.add(s.out);
                if (s.abort) p.outbox.add_abort(*std::exchange(s.abort, std::nullopt));
            }
        }
        bool busy = p.outbox.pump(*p.link, scratch_);
        if (const auto ack = p.inbox.ack_due()) {
            p.link->send(*ack, true);
            busy = true;
        }
        if (p.releasing && p.outbox.empty()) {
            p.link->drop_peer();
            p.gone = true;
        }
        return busy;
    }

    std::unique_ptr<net::EnetHub> hub_;
    std::optional<net::SessionKey> key_;
    int render_ranks_ = 1;
    std::uint16_t port_ = 0;
    std::string name_;
    std::vector<std::unique_ptr<Peer>> peers_;  // network thread
    std::uint64_t next_id_ = 0;                 // network thread
    // Under mutex_:
    std::vector<Slot> slots_;  // by rank; [0] unused
    std::vector<int> arrivals_;
    std::vector<Drop> drops_;
};

}  // namespace

std::unique_ptr<ClusterTransport> make_listener_transport(const std::string& host, std::uint16_t port, int render_ranks,
                                                          const std::optional<net::SessionKey>& key) {
    const std::string shown = host.empty() ? "0.0.0.0" : host;
    const std::string what = "--cluster-listen " + shown + ":" + std::to_string(port);
    if (render_ranks < 1 || render_ranks > 31)
        throw Error(what + ": " + std::to_string(render_ranks) + " render ranks is not 1..31");
    const std::size_t max_peers =
        std::min<std::size_t>(static_cast<std::size_t>(render_ranks) + 4, net::EnetHub::kMaxPeers);
    std::unique_ptr<net::EnetHub> hub;
    try {
        hub = net::EnetHub::listen(host, port, max_peers, kPeerTimeoutS);
    } catch (const Error& e) {
        throw Error(what + ": " + reason_of(e));
    }
    return std::make_unique<ListenerTransport>(std::move(hub), render_ranks, key, shown);
}

std::uint16_t listener_port(const ClusterTransport& transport) {
    const auto* l = dynamic_cast<const ListenerTransport*>(&transport);
    return l ? l->port() : 0;
}

}  // namespace tridex::app
