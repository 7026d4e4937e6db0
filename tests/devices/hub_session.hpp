// tests/devices/hub_session.hpp - an EnetHub on a free loopback port with its joiners, for the hub's tests: what
// each end delivered, bounded waits that poll every millisecond, and datagrams tagged with their joiner's number.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "devices/net/enet_hub.hpp"
#include "devices/net/enet_link.hpp"
#include "devices/net/sealed_link.hpp"

namespace tridex::test {

using namespace tridex::devices::net;
using Bytes = std::vector<std::uint8_t>;
using Clock = std::chrono::steady_clock;

inline SessionKey key_of(std::uint8_t seed) {
    std::uint8_t b[SessionKey::kBytes];
    for (std::size_t i = 0; i < sizeof b; ++i) b[i] = static_cast<std::uint8_t>(seed + 31 * i);
    return SessionKey(b);
}

inline Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

/// A datagram of `n` bytes tagged with `tag` in its first byte (a joiner's number), the rest a pattern of the tag.
inline Bytes tagged(std::uint8_t tag, std::size_t n) {
    Bytes b(n);
    for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>(i == 0 ? tag : i * 7 + tag * 13);
    return b;
}

/// One end of a connection and what its poll() delivered.
struct End {
    std::unique_ptr<DatagramLink> link;
    std::vector<Bytes> got;
    int connects = 0, disconnects = 0;

    void drain() {
        LinkEvent ev;
        while (link && link->poll(ev)) {
            if (ev.kind == LinkEvent::kData) got.push_back(ev.data);
            connects += ev.kind == LinkEvent::kConnected;
            disconnects += ev.kind == LinkEvent::kDisconnected;
        }
    }
    /// True when `b` arrived.
    bool has(const Bytes& b) const {
        for (const Bytes& g : got)
            if (g == b) return true;
        return false;
    }
};

/// A hub on a free loopback port, the links it accepted (wrapped by `wrap` when set) and the joiners.
struct Session {
    std::unique_ptr<EnetHub> hub;
    std::function<std::unique_ptr<DatagramLink>(std::unique_ptr<DatagramLink>)> wrap;
    std::vector<std::unique_ptr<End>> hosted, joiners;
    bool poll_hosted = true;  ///< false: run_until() services the hub and accepts, but leaves the hosted links unpolled

    explicit Session(std::size_t max_peers) : hub(EnetHub::listen("127.0.0.1", 0, max_peers)) {}
    /// A new joiner: plain, or sealed with `key`.
    End& join(const SessionKey* key = nullptr) {
        std::unique_ptr<DatagramLink> link = EnetLink::connect("127.0.0.1", hub->port());
        if (key) link = std::make_unique<SealedLink>(std::move(link), *key, SealRole::kJoiner);
        joiners.push_back(std::make_unique<End>());
        joiners.back()->link = std::move(link);
        return *joiners.back();
    }
    /// Accepts and polls everything every millisecond until done() or `seconds` passed; true when done.
    bool run_until(const std::function<bool()>& done, double seconds) {
        const auto end = Clock::now() + std::chrono::duration<double>(seconds);
        while (Clock::now() < end) {
            hub->service();
            while (std::unique_ptr<DatagramLink> link = hub->accept()) {
                hosted.push_back(std::make_unique<End>());
                hosted.back()->link = wrap ? wrap(std::move(link)) : std::move(link);
            }
            if (poll_hosted)
                for (auto& e : hosted) e->drain();
            for (auto& e : joiners) e->drain();
            if (done()) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        return false;
    }
    /// True when every joiner and hosted link is connected and there are n of each.
    bool all_up(std::size_t n) const {
        if (hosted.size() != n || joiners.size() != n) return false;
        for (const auto& e : hosted)
            if (!e->link->connected() || e->connects != 1) return false;
        for (const auto& e : joiners)
            if (!e->link->connected()) return false;
        return true;
    }
    /// The hosted link serving `joiner`: the one that received the joiner's tag (joiner's first datagram).
    End* host_of(std::uint8_t tag) {
        for (auto& e : hosted)
            if (!e->got.empty() && e->got.front().size() == 1 && e->got.front()[0] == tag) return e.get();
        return nullptr;
    }
    /// Each joiner i (tag i + 1) sends its tag reliably; true when every hosted link knows its joiner.
    bool identify() {
        for (std::size_t i = 0; i < joiners.size(); ++i)
            joiners[i]->link->send(Bytes{static_cast<std::uint8_t>(i + 1)}, true);
        return run_until(
            [&] {
                for (std::size_t i = 0; i < joiners.size(); ++i)
                    if (!host_of(static_cast<std::uint8_t>(i + 1))) return false;
                return true;
            },
            10.0);
    }
    /// A reliable datagram each way between joiner i and its hosted link; true when both arrived.
    bool round_trip(std::size_t i, const std::string& what) {
        End* h = host_of(static_cast<std::uint8_t>(i + 1));
        if (!h) return false;
        const Bytes up = text("up " + what), down = text("down " + what);
        joiners[i]->link->send(up, true);
        h->link->send(down, true);
        return run_until([&] { return h->has(up) && joiners[i]->has(down); }, 10.0);
    }
};

/// True when every datagram in `got` carries `tag` in its first byte.
inline bool all_tagged(const std::vector<Bytes>& got, std::uint8_t tag) {
    for (const Bytes& b : got)
        if (b.empty() || b[0] != tag) return false;
    return true;
}

}  // namespace tridex::test
