// The sealed link (devices/net/sealed_link.hpp) over a LinkShim pair: the handshake, round trips, every refusal under
// its own counter, a datagram of an old connection, key files, and the cost of refusing a flood.
#include "devices/net/sealed_link.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <deque>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "devices/net/link_shim.hpp"

namespace {

using namespace tridex::devices::net;
using Bytes = std::vector<std::uint8_t>;

/// What one end's tap saw and what the test slips in under the sealed link.
struct Tap {
    std::vector<Bytes> sent;   ///< every datagram the sealed link handed to the inner link (the wire)
    std::deque<Bytes> inject;  ///< datagrams poll() returns before the inner link's
    bool forward = true;       ///< false: sent datagrams are captured, not carried
};

/// A DatagramLink between the sealed link and a shim end that records the wire and injects datagrams.
class TapLink final : public DatagramLink {
public:
    TapLink(std::unique_ptr<DatagramLink> inner, std::shared_ptr<Tap> tap) : inner_(std::move(inner)), tap_(tap) {}
    void send(const Bytes& bytes, bool reliable) override {
        tap_->sent.push_back(bytes);
        if (tap_->forward) inner_->send(bytes, reliable);
    }
    bool poll(LinkEvent& ev) override {
        if (!tap_->inject.empty()) {
            ev.kind = LinkEvent::kData;
            ev.data = std::move(tap_->inject.front());
            tap_->inject.pop_front();
            return true;
        }
        return inner_->poll(ev);
    }
    bool connected() const override { return inner_->connected(); }
    const char* where() const override { return inner_->where(); }

private:
    std::unique_ptr<DatagramLink> inner_;
    std::shared_ptr<Tap> tap_;
};

/// Argon2id costs a fraction of a second: each passphrase's key is derived once per process.
const SessionKey& key_a() {
    static const SessionKey k = key_from_passphrase("correct horse battery staple");
    return k;
}
const SessionKey& key_b() {
    static const SessionKey k = key_from_passphrase("correct horse battery stable");
    return k;
}

/// A listener (host) and a joiner sealed over one shim pair, with their taps and the events each delivered.
struct Pair {
    double now = 0.0;
    LinkShim shim{ShimConfig{}, [this] { return now; }};
    std::shared_ptr<Tap> host_tap = std::make_shared<Tap>(), join_tap = std::make_shared<Tap>();
    std::unique_ptr<SealedLink> host, join;
    std::vector<LinkEvent> host_events, join_events;

    Pair(const SessionKey& host_key, const SessionKey& join_key) {
        host = std::make_unique<SealedLink>(std::make_unique<TapLink>(shim.server_end(), host_tap), host_key,
                                            SealRole::kListener);
        join = std::make_unique<SealedLink>(std::make_unique<TapLink>(shim.client_end(), join_tap), join_key,
                                            SealRole::kJoiner);
    }
    static void drain(SealedLink& link, Tap& tap, std::vector<LinkEvent>& out) {
        LinkEvent ev;
        do {
            while (link.poll(ev)) out.push_back(ev);
        } while (!tap.inject.empty());
    }
    /// Polls both ends until the traffic settles (the handshake takes three half round trips).
    void pump() {
        for (int round = 0; round < 6; ++round) {
            drain(*host, *host_tap, host_events);
            drain(*join, *join_tap, join_events);
        }
    }
    static int count(const std::vector<LinkEvent>& evs, LinkEvent::Kind k) {
        return static_cast<int>(std::count_if(evs.begin(), evs.end(), [k](const LinkEvent& e) { return e.kind == k; }));
    }
    static std::vector<Bytes> data_of(const std::vector<LinkEvent>& evs) {
        std::vector<Bytes> out;
        for (const LinkEvent& e : evs)
            if (e.kind == LinkEvent::kData) out.push_back(e.data);
        return out;
    }
};

Bytes payload(const std::string& s) { return Bytes(s.begin(), s.end()); }

/// True when any 8-byte run of `secret` occurs in `wire`.
bool leaks(const Bytes& wire, const Bytes& secret) {
    for (std::size_t i = 0; i + 8 <= secret.size(); ++i)
        if (std::search(wire.begin(), wire.end(), secret.begin() + i, secret.begin() + i + 8) != wire.end())
            return true;
    return false;
}

TEST(SealedLink, RoundTripBothWaysOnBothChannelsAndNothingReadableOnTheWire) {
    Pair p(key_a(), key_a());
    EXPECT_FALSE(p.host->connected());
    p.host->send(payload("too early"), true);  // before the handshake: dropped
    EXPECT_EQ(p.host->stats().send_dropped, 1u);
    p.pump();
    ASSERT_TRUE(p.host->connected());
    ASSERT_TRUE(p.join->connected());
    EXPECT_EQ(Pair::count(p.host_events, LinkEvent::kConnected), 1);
    EXPECT_EQ(Pair::count(p.join_events, LinkEvent::kConnected), 1);

    const Bytes a = payload("host to joiner, reliable: the snapshot of the shared model, 0123456789");
    const Bytes b = payload("host to joiner, unreliable: a stylus pose at 1 kHz, abcdefghijklmnop");
    const Bytes c = payload("joiner to host, reliable: a stroke committed, ZYXWVUTSRQPONMLKJIH");
    const Bytes d = payload("joiner to host, unreliable: a heartbeat with a timestamp, !@#$%^&*()");
    p.host->send(a, true);
    p.host->send(b, false);
    p.join->send(c, true);
    p.join->send(d, false);
    p.join->send({}, false);  // an empty payload is a datagram too
    p.pump();
    EXPECT_EQ(Pair::data_of(p.join_events), (std::vector<Bytes>{a, b}));
    EXPECT_EQ(Pair::data_of(p.host_events), (std::vector<Bytes>{c, d, {}}));
    EXPECT_EQ(p.host->stats().accepted, 3u);
    EXPECT_EQ(p.join->stats().accepted, 2u);
    EXPECT_EQ(p.host->stats().refused() + p.join->stats().refused(), 0u);
    for (const std::shared_ptr<Tap>& tap : {p.host_tap, p.join_tap})
        for (const Bytes& wire : tap->sent)
            for (const Bytes& secret : {a, b, c, d}) EXPECT_FALSE(leaks(wire, secret));
    EXPECT_STREQ(p.host->where(), "shim:client");
}

TEST(SealedLink, WrongPassphraseNeverConnectsNorDelivers) {
    Pair p(key_a(), key_b());
    p.pump();
    EXPECT_FALSE(p.host->connected());
    EXPECT_FALSE(p.join->connected());
    EXPECT_EQ(Pair::count(p.host_events, LinkEvent::kConnected), 0);
    EXPECT_EQ(Pair::count(p.join_events, LinkEvent::kConnected), 0);
    EXPECT_EQ(p.host->stats().hello_refused, 1u);
    EXPECT_EQ(p.join->stats().hello_refused, 1u);
    p.host->send(payload("not for the wrong key"), true);
    p.join->send(payload("not for the wrong key"), false);
    p.pump();
    EXPECT_TRUE(p.host_events.empty());
    EXPECT_TRUE(p.join_events.empty());
    EXPECT_EQ(p.host->stats().send_dropped, 1u);
    EXPECT_EQ(p.join->stats().send_dropped, 1u);
}

// What the net driver reads to fail at once: the transport reached the peer, the handshake failed, and why.
TEST(SealedLink, HandshakeFailureNamesAnotherKeyOrAnUnsealedPeerAndEndsTheAttempt) {
    {
        Pair p(key_a(), key_b());
        p.pump();
        EXPECT_TRUE(p.join->reached());
        EXPECT_FALSE(p.join->connected());
        EXPECT_NE(p.join->handshake_failure().find("different keys"), std::string::npos) << p.join->handshake_failure();
        EXPECT_NE(p.host->handshake_failure().find("different keys"), std::string::npos) << p.host->handshake_failure();
    }
    {
        Pair p(key_a(), key_a());
        Pair::drain(*p.host, *p.host_tap, p.host_events);  // both connected, the joiner's hello sent, nothing confirmed
        Pair::drain(*p.join, *p.join_tap, p.join_events);
        ASSERT_TRUE(p.join->reached());
        ASSERT_FALSE(p.join->connected());
        EXPECT_EQ(p.join->handshake_failure(), "");
        p.join_tap->inject.push_back(payload("an unsealed datagram of 28 bytes or so"));
        Pair::drain(*p.join, *p.join_tap, p.join_events);
        EXPECT_NE(p.join->handshake_failure().find("not sealed"), std::string::npos) << p.join->handshake_failure();
        p.pump();  // this connection's handshake was given up: it never completes
        EXPECT_FALSE(p.join->connected());  // (the host took the joiner's confirmation, sent before it gave up)
        EXPECT_NE(p.join->handshake_failure(), "");
    }
    {
        Pair p(key_a(), key_a());
        p.pump();
        EXPECT_TRUE(p.join->connected());
        EXPECT_EQ(p.join->handshake_failure(), "");
        EXPECT_EQ(p.host->handshake_failure(), "");
    }
}

TEST(SealedLink, ReflectedOrDuplicatedHelloIsRefused) {
    Pair p(key_a(), key_a());
    Pair::drain(*p.host, *p.host_tap, p.host_events);  // the host's hello is on the wire
    ASSERT_EQ(p.host_tap->sent.size(), 1u);
    p.host_tap->inject.push_back(p.host_tap->sent[0]);  // its own hello, back at it
    Pair::drain(*p.host, *p.host_tap, p.host_events);
    EXPECT_EQ(p.host->stats().hello_refused, 1u);
    p.pump();  // the real handshake still completes
    EXPECT_TRUE(p.host->connected());
    const Bytes joiner_hello = p.join_tap->sent[0];
    p.host_tap->inject.push_back(joiner_hello);  // again, after the connection was confirmed
    p.pump();
    EXPECT_EQ(p.host->stats().hello_refused, 2u);
    EXPECT_EQ(Pair::count(p.host_events, LinkEvent::kConnected), 1);
}

/// A connected pair whose joiner's next datagrams are captured instead of carried.
struct Captured : Pair {
    Captured() : Pair(key_a(), key_a()) {
        pump();
        join_tap->forward = false;
        join_tap->sent.clear();
    }
    /// The joiner seals `n` unreliable datagrams "msg K" (counters 0..n-1); returns the wire bytes.
    std::vector<Bytes> seal(int n) {
        for (int i = 0; i < n; ++i) join->send(payload("msg " + std::to_string(i)), false);
        return join_tap->sent;
    }
    void inject(const Bytes& b) { host_tap->inject.push_back(b); }
};

TEST(SealedLink, EachFlippedByteIsRefusedAndTheGoodOnesAroundArrive) {
    Captured p;
    const std::vector<Bytes> w = p.seal(3);
    p.inject(w[0]);
    for (std::size_t i = 0; i < w[1].size(); ++i) {
        Bytes bad = w[1];
        bad[i] ^= 0x80;  // header (version, channel, counter), ciphertext, MAC
        p.inject(bad);
    }
    p.inject(w[1]);
    p.inject(w[2]);
    p.pump();
    const SealStats s = p.host->stats();
    EXPECT_EQ(s.bad_version, 1u);          // byte 0
    EXPECT_EQ(s.forged, w[1].size() - 1);  // every other byte
    EXPECT_EQ(s.accepted, 3u);
    EXPECT_EQ(Pair::data_of(p.host_events), (std::vector<Bytes>{payload("msg 0"), payload("msg 1"), payload("msg 2")}));
}

TEST(SealedLink, EveryTruncationIsRefusedAsTruncated) {
    Captured p;
    const std::vector<Bytes> w = p.seal(2);
    p.inject(w[0]);
    for (std::size_t n = 0; n < SealedLink::kHeaderBytes + SealedLink::kMacBytes; ++n)
        p.inject(Bytes(w[1].begin(), w[1].begin() + static_cast<std::ptrdiff_t>(std::min(n, w[1].size()))));
    p.inject(w[1]);
    p.pump();
    EXPECT_EQ(p.host->stats().truncated, SealedLink::kHeaderBytes + SealedLink::kMacBytes);
    EXPECT_EQ(p.host->stats().accepted, 2u);
    EXPECT_EQ(p.host->stats().forged, 0u);
}

TEST(SealedLink, ReplayedAndOutOfOrderAreToldApart) {
    Captured p;
    const std::vector<Bytes> w = p.seal(9);
    p.inject(w[0]);
    p.inject(w[0]);  // the same datagram twice: replayed
    p.inject(w[7]);
    p.inject(w[5]);  // counter 5 after 7, never seen: out of order
    p.inject(w[7]);  // replayed
    p.inject(w[0]);  // accepted before, still in the window: replayed
    p.inject(w[8]);
    p.pump();
    const SealStats s = p.host->stats();
    EXPECT_EQ(s.replayed, 3u);
    EXPECT_EQ(s.out_of_order, 1u);
    EXPECT_EQ(s.accepted, 3u);
    EXPECT_EQ(s.forged, 0u);
    EXPECT_EQ(Pair::data_of(p.host_events), (std::vector<Bytes>{payload("msg 0"), payload("msg 7"), payload("msg 8")}));
}

TEST(SealedLink, BadVersionIsRefusedAsBadVersion) {
    Captured p;
    const std::vector<Bytes> w = p.seal(2);
    for (std::uint8_t v : {0, 2, 255}) {
        Bytes bad = w[0];
        bad[0] = v;
        p.inject(bad);
    }
    p.inject(w[0]);
    p.inject(w[1]);
    p.pump();
    EXPECT_EQ(p.host->stats().bad_version, 3u);
    EXPECT_EQ(p.host->stats().accepted, 2u);
}

TEST(SealedLink, ReliableAndUnreliableCountersAreIndependent) {
    Captured p;
    p.join->send(payload("r0"), true);
    p.join->send(payload("u0"), false);
    p.join->send(payload("r1"), true);
    const std::vector<Bytes> w = p.join_tap->sent;
    p.inject(w[1]);  // the unreliable one overtakes the reliable ones
    p.inject(w[0]);
    p.inject(w[2]);
    p.pump();
    EXPECT_EQ(p.host->stats().accepted, 3u);
    EXPECT_EQ(p.host->stats().refused(), 0u);
}

TEST(SealedLink, DatagramOfAPreviousConnectionIsRefused) {
    Captured p;
    const std::vector<Bytes> old = p.seal(1);
    p.join_tap->forward = true;
    p.shim.set_cut(true);
    p.pump();
    EXPECT_EQ(Pair::count(p.host_events, LinkEvent::kDisconnected), 1);
    EXPECT_FALSE(p.host->connected());
    p.shim.set_cut(false);
    p.pump();
    ASSERT_TRUE(p.host->connected());
    ASSERT_TRUE(p.join->connected());
    EXPECT_EQ(Pair::count(p.host_events, LinkEvent::kConnected), 2);
    p.inject(old[0]);  // counter 0 is fresh in the new connection: only the connection key refuses it
    p.pump();
    EXPECT_EQ(p.host->stats().forged, 1u);
    EXPECT_EQ(p.host->stats().accepted, 0u);
    p.join->send(payload("new connection"), true);
    p.pump();
    EXPECT_EQ(Pair::data_of(p.host_events), (std::vector<Bytes>{payload("new connection")}));
}

TEST(SealedLink, AnOldHelloReplayedAheadOfTheNewOneDoesNotConnect) {
    Pair p(key_a(), key_a());
    p.pump();
    const Bytes old_hello = p.join_tap->sent[0];
    p.shim.set_cut(true);
    p.pump();
    p.shim.set_cut(false);
    Pair::drain(*p.host, *p.host_tap, p.host_events);  // the host's new hello goes out
    p.host_tap->inject.push_back(old_hello);           // the old joiner hello arrives first
    Pair::drain(*p.host, *p.host_tap, p.host_events);
    EXPECT_FALSE(p.host->connected());  // a key derived from it is never confirmed
    p.pump();                           // the real hello derives the key again; the confirmations match
    EXPECT_TRUE(p.host->connected());
    EXPECT_TRUE(p.join->connected());
    p.join->send(payload("after the replayed hello"), true);
    p.pump();
    EXPECT_EQ(Pair::data_of(p.host_events), (std::vector<Bytes>{payload("after the replayed hello")}));
    EXPECT_EQ(p.join->stats().forged, 1u);  // the host's confirmation under the replayed hello's key
}

/// Refuses `n` datagrams from `make` at the host; returns the seconds it took (injection excluded).
template <class Make>
double flood(Captured& p, int n, Make make) {
    for (int i = 0; i < n; ++i) p.inject(make());
    const auto t0 = std::chrono::steady_clock::now();
    Pair::drain(*p.host, *p.host_tap, p.host_events);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(SealedLink, AFloodOfRandomDatagramsIsRefusedAndCounted) {
    Captured p;
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> byte(0, 255), len(0, 300), body(26, 300);
    constexpr int kN = 100000;
    const auto random_bytes = [&](int n) {
        Bytes b(static_cast<std::size_t>(n));
        for (std::uint8_t& x : b) x = static_cast<std::uint8_t>(byte(rng));
        return b;
    };
    // Wholly random: most fail the length or version checks.
    const double t_random = flood(p, kN, [&] { return random_bytes(len(rng)); });
    const SealStats s1 = p.host->stats();
    EXPECT_EQ(s1.refused(), static_cast<std::uint64_t>(kN));
    // Shaped like data (version 1, a data channel, long enough): every one costs a MAC check.
    const double t_shaped = flood(p, kN, [&] {
        Bytes b = random_bytes(body(rng));
        b[0] = SealedLink::kVersion;
        b[1] = static_cast<std::uint8_t>(byte(rng) & 1);
        return b;
    });
    const SealStats s2 = p.host->stats();
    EXPECT_EQ(s2.refused(), 2u * kN);
    EXPECT_EQ(s2.forged - s1.forged, static_cast<std::uint64_t>(kN));
    EXPECT_EQ(s2.accepted, 0u);
    EXPECT_EQ(Pair::data_of(p.host_events).size(), 0u);
    EXPECT_TRUE(p.host->connected());
    std::printf(
        "sealed link flood: %d random datagrams refused in %.1f ms (%.3f us each: %llu truncated, %llu bad "
        "version, %llu forged, %llu hello refused)\n",
        kN, 1e3 * t_random, 1e6 * t_random / kN, static_cast<unsigned long long>(s1.truncated),
        static_cast<unsigned long long>(s1.bad_version), static_cast<unsigned long long>(s1.forged),
        static_cast<unsigned long long>(s1.hello_refused));
    std::printf(
        "sealed link flood: %d data-shaped random datagrams (26..300 bytes) refused by the MAC in %.1f ms "
        "(%.3f us each)\n",
        kN, 1e3 * t_shaped, 1e6 * t_shaped / kN);
    // The link still carries the joiner's datagrams.
    p.join_tap->forward = true;
    p.join->send(payload("after the flood"), false);
    p.pump();
    EXPECT_EQ(Pair::data_of(p.host_events), (std::vector<Bytes>{payload("after the flood")}));
}

TEST(SealedLink, StatsAreReadableFromAnotherThreadWhileItPolls) {
    Captured p;
    std::atomic<bool> done{false};
    std::uint64_t most = 0;
    std::thread reader([&] {
        while (!done.load()) most = std::max(most, p.host->stats().refused());
    });
    std::mt19937 rng(11);
    for (int i = 0; i < 20000; ++i) p.inject(Bytes(static_cast<std::size_t>(rng() % 64), 0x42));
    Pair::drain(*p.host, *p.host_tap, p.host_events);
    done = true;
    reader.join();
    EXPECT_LE(most, 20000u);
    EXPECT_EQ(p.host->stats().refused(), 20000u);
}

}  // namespace
