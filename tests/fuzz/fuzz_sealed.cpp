// tests/fuzz/fuzz_sealed.cpp - libFuzzer target: the sealed link's receiving side (devices/net/sealed_link.hpp)
// after a completed handshake over a LinkShim pair. The input is a list of operations, each an opcode byte and its
// arguments: inject raw bytes at the listener, have the joiner seal a datagram (carried and kept), replay, flip a
// byte of, or truncate a kept datagram, or reconnect. Bad datagrams must be counted and dropped: any exception, a
// payload delivered that the joiner never sent (or twice), or counters that do not add up is a finding.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "devices/net/link_shim.hpp"
#include "devices/net/sealed_link.hpp"

namespace net = tridex::devices::net;
using Bytes = std::vector<std::uint8_t>;

namespace {

/// The listener's inner link with datagrams slipped in ahead of the shim's.
class InjectLink final : public net::DatagramLink {
public:
    InjectLink(std::unique_ptr<net::DatagramLink> inner, std::deque<Bytes>& inject)
        : inner_(std::move(inner)), inject_(inject) {}
    void send(const Bytes& b, bool reliable) override { inner_->send(b, reliable); }
    bool poll(net::LinkEvent& ev) override {
        if (inject_.empty()) return inner_->poll(ev);
        ev.kind = net::LinkEvent::kData;
        ev.data = std::move(inject_.front());
        inject_.pop_front();
        return true;
    }
    bool connected() const override { return inner_->connected(); }
    const char* where() const override { return inner_->where(); }

private:
    std::unique_ptr<net::DatagramLink> inner_;
    std::deque<Bytes>& inject_;
};

/// The joiner's inner link, keeping a copy of every sealed datagram it carries.
class KeepLink final : public net::DatagramLink {
public:
    KeepLink(std::unique_ptr<net::DatagramLink> inner, std::vector<Bytes>& kept)
        : inner_(std::move(inner)), kept_(kept) {}
    void send(const Bytes& b, bool reliable) override {
        if (kept_.size() < 256) kept_.push_back(b);
        inner_->send(b, reliable);
    }
    bool poll(net::LinkEvent& ev) override { return inner_->poll(ev); }
    bool connected() const override { return inner_->connected(); }
    const char* where() const override { return inner_->where(); }

private:
    std::unique_ptr<net::DatagramLink> inner_;
    std::vector<Bytes>& kept_;
};

[[noreturn]] void finding(const char* what) {
    std::fprintf(stderr, "tridex fuzz: sealed link: %s\n", what);
    std::abort();
}

const net::SessionKey& fixed_key() {
    static const std::uint8_t bytes[net::SessionKey::kBytes] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
    static const net::SessionKey key(bytes);
    return key;
}

/// One listener and one joiner over a shim, the joiner's kept datagrams and what the listener delivered.
struct Rig {
    double now = 0.0;
    net::LinkShim shim{net::ShimConfig{}, [this] { return now; }};
    std::deque<Bytes> inject;
    std::vector<Bytes> kept;
    std::unique_ptr<net::SealedLink> host, join;
    std::set<Bytes> sent, delivered;
    std::uint64_t data_events = 0;
    int next = 0;

    Rig() {
        host = std::make_unique<net::SealedLink>(std::make_unique<InjectLink>(shim.server_end(), inject), fixed_key(),
                                                 net::SealRole::kListener);
        join = std::make_unique<net::SealedLink>(std::make_unique<KeepLink>(shim.client_end(), kept), fixed_key(),
                                                 net::SealRole::kJoiner);
        pump();
        if (!host->connected() || !join->connected()) finding("the handshake did not complete");
    }
    void pump() {
        net::LinkEvent ev;
        for (int round = 0; round < 4; ++round) {
            for (;;) {
                if (!host->poll(ev)) {
                    if (inject.empty()) break;
                    continue;  // poll() stopped after kMaxInnerEventsPerPoll events
                }
                if (ev.kind != net::LinkEvent::kData) continue;
                ++data_events;
                if (!sent.count(ev.data)) finding("delivered a payload the joiner never sent");
                if (!delivered.insert(ev.data).second) finding("delivered a payload twice");
            }
            while (join->poll(ev)) {}
        }
    }
    void seal(bool reliable) {
        const std::string s = "payload " + std::to_string(next++);
        const Bytes b(s.begin(), s.end());
        sent.insert(b);
        join->send(b, reliable);
    }
    const Bytes* pick(std::uint8_t k) const { return kept.empty() ? nullptr : &kept[k % kept.size()]; }
};

}  // namespace

/// One fuzz input as a list of operations on a freshly connected pair.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    Rig rig;
    std::size_t i = 0;
    const auto arg = [&]() -> std::uint8_t { return i < size ? data[i++] : 0; };
    while (i < size) {
        const std::uint8_t op = data[i++];
        switch (op % 6) {
            case 0: {  // raw bytes at the listener
                const std::size_t n = std::min<std::size_t>(arg(), size - i);
                rig.inject.emplace_back(data + i, data + i + n);
                i += n;
                break;
            }
            case 1: rig.seal((op & 0x80) != 0); break;
            case 2:  // replay a kept datagram
                if (const Bytes* b = rig.pick(arg())) rig.inject.push_back(*b);
                break;
            case 3:  // flip a byte of a kept datagram
                if (const Bytes* b = rig.pick(arg())) {
                    Bytes bad = *b;
                    const std::uint8_t at = arg(), x = arg();
                    bad[at % bad.size()] ^= x;
                    rig.inject.push_back(std::move(bad));
                }
                break;
            case 4:  // truncate a kept datagram
                if (const Bytes* b = rig.pick(arg()))
                    rig.inject.emplace_back(b->begin(), b->begin() + arg() % b->size());
                break;
            case 5:  // reconnect: what was kept belongs to the old connection now
                rig.shim.set_cut(true);
                rig.pump();
                rig.shim.set_cut(false);
                break;
        }
        rig.pump();
    }
    if (rig.host->stats().accepted != rig.data_events) finding("accepted does not count the datagrams delivered");
    return 0;
}
