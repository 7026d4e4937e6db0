// The sealed link (devices/net/sealed_link.hpp) over real ENet on loopback: the handshake completes, reliable
// datagrams (one large enough for ENet to fragment) and unreliable ones arrive intact both ways, the wrong key never
// connects, and a listener drops a joiner of another key at once.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "devices/net/enet_link.hpp"
#include "devices/net/sealed_link.hpp"

namespace {

using namespace tridex::devices::net;
using Bytes = std::vector<std::uint8_t>;
using Clock = std::chrono::steady_clock;

SessionKey key_of(std::uint8_t seed) {
    std::uint8_t b[SessionKey::kBytes];
    for (std::size_t i = 0; i < sizeof b; ++i) b[i] = static_cast<std::uint8_t>(seed + 31 * i);
    return SessionKey(b);
}

/// A sealed listener on a free loopback port and a sealed joiner connecting to it, with what each delivered.
struct EnetPair {
    std::unique_ptr<SealedLink> host, join;
    std::vector<Bytes> host_got, join_got;

    EnetPair(const SessionKey& host_key, const SessionKey& join_key) {
        std::unique_ptr<EnetLink> listener = EnetLink::listen("127.0.0.1", 0);
        const std::uint16_t port = listener->port();
        host = std::make_unique<SealedLink>(std::move(listener), host_key, SealRole::kListener);
        join = std::make_unique<SealedLink>(EnetLink::connect("127.0.0.1", port), join_key, SealRole::kJoiner);
    }
    /// Polls both ends every millisecond until done() or `seconds` passed; true when done.
    bool run_until(const std::function<bool()>& done, double seconds) {
        const auto end = Clock::now() + std::chrono::duration<double>(seconds);
        LinkEvent ev;
        while (Clock::now() < end) {
            while (host->poll(ev))
                if (ev.kind == LinkEvent::kData) host_got.push_back(ev.data);
            while (join->poll(ev))
                if (ev.kind == LinkEvent::kData) join_got.push_back(ev.data);
            if (done()) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        return false;
    }
};

TEST(SealedLinkEnet, HandshakeAndRoundTripsOverLoopback) {
    EnetPair p(key_of(1), key_of(1));
    ASSERT_TRUE(p.run_until([&] { return p.host->connected() && p.join->connected(); }, 10.0));
    Bytes big(20000);
    for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<std::uint8_t>(i * 13 + 5);
    std::vector<Bytes> reliable;
    for (int i = 0; i < 10; ++i) {
        const std::string s = "reliable " + std::to_string(i);
        reliable.emplace_back(s.begin(), s.end());
    }
    reliable.push_back(big);
    for (const Bytes& b : reliable) {
        p.host->send(b, true);
        p.join->send(b, true);
    }
    const Bytes pose = {1, 2, 3, 4, 5, 6, 7, 8};
    p.host->send(pose, false);
    p.join->send(pose, false);
    const std::size_t want = reliable.size();
    ASSERT_TRUE(p.run_until([&] { return p.host_got.size() >= want && p.join_got.size() >= want; }, 10.0));
    p.run_until([] { return false; }, 0.05);  // let the unreliable ones in
    // Reliable datagrams arrive in order; the unreliable one, when it arrives, is intact.
    for (const std::vector<Bytes>* got : {&p.host_got, &p.join_got}) {
        std::vector<Bytes> rel;
        for (const Bytes& b : *got)
            if (b != pose) rel.push_back(b);
        EXPECT_EQ(rel, reliable);
        EXPECT_LE(got->size(), want + 1);
    }
    EXPECT_EQ(p.host->stats().refused(), 0u);
    EXPECT_EQ(p.join->stats().refused(), 0u);
    EXPECT_GT(p.host->traffic().datagrams, 0u);
}

TEST(SealedLinkEnet, WrongKeyNeverConnects) {
    EnetPair p(key_of(1), key_of(2));
    EXPECT_FALSE(p.run_until([&] { return p.host->connected() || p.join->connected(); }, 1.0));
    // The listener drops the joiner after each refused hello; the joiner's ENet connects again every 0.2 s.
    EXPECT_GE(p.host->stats().hello_refused, 1u);
    EXPECT_GE(p.join->stats().hello_refused, 1u);
    EXPECT_NE(p.join->handshake_failure().find("different keys"), std::string::npos) << p.join->handshake_failure();
    EXPECT_TRUE(p.host_got.empty());
    EXPECT_TRUE(p.join_got.empty());
}

// A joiner with another key that keeps trying does not hold the listener: the listener drops it after its hello, and
// a joiner with the listener's key is served meanwhile.
TEST(SealedLinkEnet, AListenerDropsAWrongKeyJoinerAndServesTheRightOne) {
    EnetPair p(key_of(1), key_of(2));
    ASSERT_TRUE(p.run_until([&] { return p.host->stats().hello_refused > 0; }, 10.0));
    EXPECT_FALSE(p.host->reached()) << "the listener still holds the joiner it refused";
    const std::string where = p.host->where();  // "127.0.0.1:PORT"
    const auto port = static_cast<std::uint16_t>(std::stoi(where.substr(where.rfind(':') + 1)));
    SealedLink right(EnetLink::connect("127.0.0.1", port), key_of(1), SealRole::kJoiner);
    LinkEvent ev;
    const bool served = p.run_until(
        [&] {
            while (right.poll(ev)) {
            }
            return right.connected() && p.host->connected();
        },
        10.0);
    EXPECT_TRUE(served) << "host refused " << p.host->stats().hello_refused << " hellos";
    EXPECT_FALSE(p.join->connected());
    EXPECT_EQ(right.handshake_failure(), "");
}

}  // namespace
