// devices/net/link_shim.cpp - delay queues with deterministic loss between two in-process link ends.
#include "devices/net/link_shim.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace tridex::devices::net {

class ShimEnd final : public DatagramLink {
public:
    ShimEnd(LinkShim& shim, int end) : shim_(shim), end_(end) {}
    ~ShimEnd() override {
        std::lock_guard lock(shim_.mutex_);
        shim_.attached_[end_] = false;
        shim_.queue_[end_].clear();
        if (shim_.attached_[1 - end_]) shim_.queue_[1 - end_].push_back({shim_.clock_(), {}, true, false});
    }
    void send(const std::vector<std::uint8_t>& bytes, bool reliable) override { shim_.send(end_, bytes, reliable); }
    bool poll(LinkEvent& ev) override { return shim_.poll(end_, ev); }
    bool connected() const override { return shim_.connected(end_); }
    const char* where() const override { return shim_.where_[1 - end_].c_str(); }

private:
    LinkShim& shim_;
    int end_;
};

LinkShim::LinkShim(ShimConfig cfg, std::function<double()> clock) : cfg_(cfg), clock_(std::move(clock)), rng_(cfg.seed) {
    if (!(std::isfinite(cfg_.latency_s) && cfg_.latency_s >= 0.0))
        throw Error("ShimConfig.latency_s = " + std::to_string(cfg_.latency_s) + " must be finite and >= 0 s");
    if (!(cfg_.loss >= 0.0 && cfg_.loss < 1.0))
        throw Error("ShimConfig.loss = " + std::to_string(cfg_.loss) + " must be in [0, 1)");
    if (!clock_) throw Error("LinkShim: no clock given");
}

LinkShim::~LinkShim() = default;

std::unique_ptr<DatagramLink> LinkShim::server_end() {
    std::lock_guard lock(mutex_);
    if (attached_[0]) throw Error("LinkShim: the server end was already taken");
    attached_[0] = true;
    if (attached_[1] && !cut_)
        for (int e = 0; e < 2; ++e) queue_[e].push_front({clock_(), {}, true, true});
    return std::make_unique<ShimEnd>(*this, 0);
}

std::unique_ptr<DatagramLink> LinkShim::client_end() {
    std::lock_guard lock(mutex_);
    if (attached_[1]) throw Error("LinkShim: the client end was already taken");
    attached_[1] = true;
    if (attached_[0] && !cut_)
        for (int e = 0; e < 2; ++e) queue_[e].push_front({clock_(), {}, true, true});
    return std::make_unique<ShimEnd>(*this, 1);
}

void LinkShim::set_cut(bool cut) {
    std::lock_guard lock(mutex_);
    if (cut == cut_) return;
    cut_ = cut;
    const double now = clock_();
    for (int e = 0; e < 2; ++e) {
        queue_[e].clear();
        last_reliable_due_[e] = now;
        if (attached_[e] && attached_[1 - e]) queue_[e].push_back({now, {}, true, !cut});
    }
}

ShimStats LinkShim::stats() const {
    std::lock_guard lock(mutex_);
    return stats_;
}

bool LinkShim::connected(int end) const {
    std::lock_guard lock(mutex_);
    return attached_[end] && attached_[1 - end] && !cut_;
}

void LinkShim::send(int from, const std::vector<std::uint8_t>& bytes, bool reliable) {
    std::lock_guard lock(mutex_);
    const int to = 1 - from;
    if (cut_ || !attached_[to]) return;
    ++stats_.sent;
    const double now = clock_();
    double due = now + cfg_.latency_s;
    if (reliable) {
        // Each lost try costs a round trip and the retransmission timer; reliable datagrams stay in order.
        while (uniform_(rng_) < cfg_.loss) {
            due += 2.0 * cfg_.latency_s + cfg_.retransmit_extra_s;
            ++stats_.resent;
        }
        due = std::max(due, last_reliable_due_[to]);
        last_reliable_due_[to] = due;
    } else if (uniform_(rng_) < cfg_.loss) {
        ++stats_.lost;
        return;
    }
    std::deque<InFlight>& q = queue_[to];
    auto it = std::upper_bound(q.begin(), q.end(), due, [](double d, const InFlight& f) { return d < f.due_s; });
    q.insert(it, InFlight{due, bytes, false, false});
}

bool LinkShim::poll(int at, LinkEvent& ev) {
    std::lock_guard lock(mutex_);
    std::deque<InFlight>& q = queue_[at];
    if (q.empty() || q.front().due_s > clock_()) return false;
    InFlight& f = q.front();
    if (f.control) {
        ev.kind = f.connect ? LinkEvent::kConnected : LinkEvent::kDisconnected;
        ev.data.clear();
    } else {
        ev.kind = LinkEvent::kData;
        ev.data.assign(f.bytes.begin(), f.bytes.end());
        ++stats_.delivered;
    }
    q.pop_front();
    return true;
}

}  // namespace tridex::devices::net
