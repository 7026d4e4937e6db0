// app/session/cluster/net_transport_member.cpp - a render rank of a network wall: an EnetLink to rank 0 (sealed
// with the session's key when there is one) that claims the rank and, once accepted, carries whole messages between
// rank 0 and queues that the session's frame thread reads and fills, on a network thread of its own.
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
#include "devices/net/enet_link.hpp"

namespace tridex::app {

namespace net = devices::net;
using namespace netwire;

namespace {

/// A render rank of a network wall (make_member_transport documents it).
class MemberTransport final : public NetTransport {
public:
    MemberTransport(std::unique_ptr<net::DatagramLink> link, int rank, int render_ranks, std::string what,
                    std::string name)
        : link_(std::move(link)),
          rank_(rank),
          render_ranks_(render_ranks),
          what_(std::move(what)),
          name_(std::move(name)) {
        start();
    }
    ~MemberTransport() override { stop(); }
    MemberTransport(const MemberTransport&) = delete;
    MemberTransport& operator=(const MemberTransport&) = delete;

    int rank() const override { return rank_; }
    int size() const override { return render_ranks_ + 1; }
    std::string name() const override { return name_; }
    bool open_membership() const override { return true; }

    /// Waits until rank 0 answered the claim; throws tridex::Error "--cluster-connect HOST:PORT: ..." unless it
    /// accepted it by `deadline` (`wait_s`: the time to the deadline when the wait began, for the message).
    void wait_for_accept(Clock::time_point deadline, double wait_s) {
        std::unique_lock lock(mutex_);
        cv_.wait_until(lock, deadline, [&] { return phase_ != Phase::kClaiming; });
        switch (phase_) {
            case Phase::kAccepted: return;
            case Phase::kRefused: throw Error(what_ + ": rank 0 refused the claim: " + why_);
            case Phase::kFailed: throw Error(what_ + ": " + why_);
            case Phase::kClaiming: break;
        }
        throw Error(what_ + ": " +
                    (reached_ ? "rank 0 answered but did not accept the claim" : std::string("no answer from rank 0")) +
                    " within " + seconds_text(wait_s));
    }

    void send(int to, std::vector<unsigned char> bytes) override {
        check_rank(to, "send to");
        std::lock_guard lock(mutex_);
        throw_if_ended();
        out_.push_back(std::move(bytes));
        ++sent_;
    }

    std::optional<std::vector<unsigned char>> receive(int from, Clock::time_point deadline) override {
        check_rank(from, "receive from");
        std::unique_lock lock(mutex_);
        cv_.wait_until(lock, deadline, [&] { return !in_.empty() || aborted_ || !failure_.empty(); });
        if (aborted_) throw_if_ended();
        if (!in_.empty()) {
            Message m = std::move(in_.front());
            in_.pop_front();
            in_bytes_ -= m.size();
            return m;
        }
        throw_if_ended();
        return std::nullopt;
    }

    bool flush(Clock::time_point deadline) override {
        std::unique_lock lock(mutex_);
        cv_.wait_until(lock, deadline, [&] { return acked_ >= sent_ || !failure_.empty(); });
        return acked_ >= sent_;
    }

    [[noreturn]] void abort_all(int code) override {
        flush(deadline_after(kAbortFlushS));
        std::_Exit(code);
    }

private:
    enum class Phase : std::uint8_t { kClaiming, kAccepted, kRefused, kFailed };

    void check_rank(int r, const char* what) const {
        if (r != 0)
            throw Error("cluster: render rank " + std::to_string(rank_) + " cannot " + what + " rank " +
                        std::to_string(r) + " (a render rank talks to rank 0 only)");
    }
    // Throws why the session ended for this rank, if it did (under mutex_).
    void throw_if_ended() const {
        if (aborted_) throw Error("rank 0 ended the session (code " + std::to_string(*aborted_) + ")");
        if (!failure_.empty()) throw Error(failure_);
    }

    bool service() override {
        if (!link_) return false;
        bool busy = false;
        net::LinkEvent ev;
        for (int n = 0; link_ && !done_ && n < kMaxEventsPerPass && link_->poll(ev); ++n) {
            busy = true;
            if (ev.kind == net::LinkEvent::kConnected && !accepted_) {
                link_->send(encode_claim(rank_), true);  // again after a reconnect before the answer
            } else if (ev.kind == net::LinkEvent::kDisconnected && accepted_) {
                end("rank 0 left (its connection closed or timed out)");
            } else if (ev.kind == net::LinkEvent::kData) {
                try {
                    on_datagram(ev.data);
                } catch (const Error& e) {
                    end(std::string("rank 0 sent a datagram this rank cannot read: ") + e.what());
                }
            }
        }
        if (done_) link_.reset();  // refused or failed before the accept: no reconnect, no second claim
        if (!link_) return busy;
        if (!accepted_) {
            const std::string failure = link_->handshake_failure();
            std::lock_guard lock(mutex_);
            reached_ = link_->reached();
            if (!failure.empty()) set_phase(Phase::kFailed, failure + " (does rank 0 use the same key?)");
            return busy;
        }
        return send_queued() || busy;
    }

    void thread_failed(const std::string& what) override {
        {
            std::lock_guard lock(mutex_);
            set_phase(Phase::kFailed, "the network thread failed: " + what);
        }
        end("the network thread failed: " + what);
    }

    void on_datagram(std::vector<std::uint8_t>& d) {
        const std::optional<Kind> kind = datagram_kind(d);
        if (!accepted_) return on_answer(d, kind);
        if (!kind) throw Error("a datagram of " + std::to_string(d.size()) + " bytes that is not this protocol's");
        if (*kind != Kind::kControl) {
            std::optional<Message> m = inbox_.push(d);
            if (m) deliver(std::move(*m));
            return;
        }
        const Control c = decode_control(d);
        if (c.version != kProtocol) throw Error("a control datagram of version " + std::to_string(c.version));
        if (c.type == ControlType::kAck) outbox_.acked(c.bytes);
        std::lock_guard lock(mutex_);
        if (c.type == ControlType::kAck) {
            acked_ = std::max(acked_, std::min(c.count, sent_));
        } else if (c.type == ControlType::kAbort) {
            if (!aborted_) aborted_ = c.code;
            inbox_.count_message();  // rank 0 counts the abort as a message: its flush waits for it
        } else {
            throw Error("a control datagram of type " + std::to_string(static_cast<int>(c.type)) + " after the accept");
        }
        cv_.notify_all();
    }

    // Rank 0's answer to the claim (the only datagram expected before the accept).
    void on_answer(const std::vector<std::uint8_t>& d, std::optional<Kind> kind) {
        if (kind != Kind::kControl) {
            std::lock_guard lock(mutex_);
            set_phase(Phase::kFailed,
                      "rank 0 answered with a datagram that is not this protocol's (does rank 0 seal "
                      "its datagrams with a key this process was not given?)");
            return;
        }
        Control c;
        try {
            c = decode_control(d);
        } catch (const Error& e) {
            std::lock_guard lock(mutex_);
            set_phase(Phase::kFailed, std::string("rank 0 answered with ") + e.what());
            return;
        }
        std::lock_guard lock(mutex_);
        if (c.version != kProtocol)
            set_phase(Phase::kFailed, "rank 0 speaks protocol version " + std::to_string(c.version) + ", this rank " +
                                          std::to_string(kProtocol) + " (run the same tridex on every rank)");
        else if (c.type == ControlType::kRefuse)
            set_phase(Phase::kRefused, c.reason);
        else if (c.type == ControlType::kAccept && c.rank == rank_)
            set_phase(Phase::kAccepted, "");
        else
            set_phase(Phase::kFailed, "rank 0 answered the claim with a control datagram of type " +
                                          std::to_string(static_cast<int>(c.type)));
    }

    // Under mutex_: the claim's outcome; a failure or refusal ends the link.
    void set_phase(Phase phase, const std::string& why) {
        if (phase_ != Phase::kClaiming) return;
        phase_ = phase;
        why_ = why;
        accepted_ = phase == Phase::kAccepted;
        if (!accepted_) done_ = true;
        cv_.notify_all();
    }

    void deliver(Message m) {
        {
            std::lock_guard lock(mutex_);
            if (in_bytes_ + m.size() <= kMaxQueuedBytes || in_.empty()) {
                in_bytes_ += m.size();
                in_.push_back(std::move(m));
                cv_.notify_all();
                return;
            }
        }
        end("rank 0 sent more than " + std::to_string(kMaxQueuedBytes >> 20) + " MiB that were not received");
    }

    // The connection to rank 0 ends for good (no reconnect): receive() and send() throw `why` from now on.
    void end(const std::string& why) {
        {
            std::lock_guard lock(mutex_);
            if (failure_.empty()) failure_ = why;
            cv_.notify_all();
        }
        link_.reset();
    }

    // Takes what the frame thread queued, hands the link what the window allows, and acknowledges what came.
    bool send_queued() {
        {
            std::lock_guard lock(mutex_);
            outbox_.add(out_);
        }
        bool busy = outbox_.pump(*link_, scratch_);
        if (const auto ack = inbox_.ack_due()) {
            link_->send(*ack, true);
            busy = true;
        }
        return busy;
    }

    // Network thread:
    std::unique_ptr<net::DatagramLink> link_;  // null once the connection ended for good
    Inbox inbox_{};
    Outbox outbox_{};
    const int rank_, render_ranks_;
    const std::string what_, name_;
    // Under mutex_ (accepted_ and done_ are written under it by the network thread, which alone reads them):
    Phase phase_ = Phase::kClaiming;
    std::string why_;
    bool reached_ = false;
    bool accepted_ = false;
    bool done_ = false;
    std::deque<Message> in_;
    std::size_t in_bytes_ = 0;
    std::deque<Message> out_;
    std::uint64_t sent_ = 0, acked_ = 0;
    std::optional<int> aborted_;
    std::string failure_;
};

}  // namespace

std::unique_ptr<ClusterTransport> make_member_transport(const std::string& host, std::uint16_t port, int rank,
                                                        int render_ranks, const std::optional<net::SessionKey>& key,
                                                        ClusterTransport::Clock::time_point deadline) {
    const std::string where = host + ":" + std::to_string(port);
    const std::string what = "--cluster-connect " + where;
    if (render_ranks < 1 || render_ranks > 31)
        throw Error(what + ": " + std::to_string(render_ranks) + " render ranks is not 1..31");
    if (rank < 1 || rank > render_ranks)
        throw Error(what + ": rank " + std::to_string(rank) + " is not a render rank (1.." +
                    std::to_string(render_ranks) + ")");
    if (port == 0) throw Error(what + ": port 0 is no port to connect to");
    const double wait_s = std::chrono::duration<double>(deadline - ClusterTransport::Clock::now()).count();
    std::unique_ptr<net::DatagramLink> link;
    try {
        link = net::EnetLink::connect(host, port, kPeerTimeoutS);
    } catch (const Error& e) {
        throw Error(what + ": " + reason_of(e));
    }
    if (key) link = std::make_unique<net::SealedLink>(std::move(link), *key, net::SealRole::kJoiner);
    const std::string name = "ENet " + enet_version() + " on " + where + (key ? " (sealed)" : "");
    auto t = std::make_unique<MemberTransport>(std::move(link), rank, render_ranks, what, name);
    t->wait_for_accept(deadline, wait_s);
    return t;
}

}  // namespace tridex::app
