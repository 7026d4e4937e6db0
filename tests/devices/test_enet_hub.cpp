// The multi-peer ENet listener (devices/net/enet_hub.hpp) over real ENet on loopback: several joiners are served at
// once, each through its own link, with every datagram reaching the right peer only; sealed links run their
// handshakes over it; a joiner that leaves is reported and a new one accepted; a peer beyond max_peers is refused;
// datagrams from an address of no peer are counted as foreign, a peer's are not.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "tests/devices/hub_session.hpp"

namespace {

using namespace tridex::test;

TEST(EnetHub, TwoJoinersExchangeDatagramsWithTheRightPeerOnly) {
    Session s(4);
    s.join();
    s.join();
    ASSERT_TRUE(s.run_until([&] { return s.all_up(2); }, 10.0));
    ASSERT_TRUE(s.identify());
    // Reliable: a small one, one of 200 KB (ENet fragments it), another small one; each tagged with its joiner.
    for (const std::uint8_t tag : {std::uint8_t{1}, std::uint8_t{2}}) {
        End* h = s.host_of(tag);
        EXPECT_EQ(std::string(h->link->where()).rfind("127.0.0.1:", 0), 0u) << h->link->where();
        for (std::size_t n : {16u, 200000u, 32u}) {
            s.joiners[tag - 1]->link->send(tagged(tag, n), true);
            h->link->send(tagged(tag, n + 1), true);
        }
    }
    const auto reliable_in = [&] {
        for (const std::uint8_t tag : {std::uint8_t{1}, std::uint8_t{2}})
            if (s.host_of(tag)->got.size() < 4 || s.joiners[tag - 1]->got.size() < 3) return false;
        return true;
    };
    ASSERT_TRUE(s.run_until(reliable_in, 20.0));
    // Unreliable: sent again each round until one arrives at each end (loopback seldom loses one).
    const auto unreliable_in = [&] {
        bool all = true;
        for (const std::uint8_t tag : {std::uint8_t{1}, std::uint8_t{2}}) {
            End* h = s.host_of(tag);
            End& j = *s.joiners[tag - 1];
            if (!h->has(tagged(tag, 9))) {
                j.link->send(tagged(tag, 9), false);
                all = false;
            }
            if (!j.has(tagged(tag, 10))) {
                h->link->send(tagged(tag, 10), false);
                all = false;
            }
        }
        return all;
    };
    ASSERT_TRUE(s.run_until(unreliable_in, 10.0));
    for (const std::uint8_t tag : {std::uint8_t{1}, std::uint8_t{2}}) {
        const End* h = s.host_of(tag);
        const End& j = *s.joiners[tag - 1];
        EXPECT_TRUE(all_tagged(h->got, tag)) << "a datagram of another joiner reached joiner " << int(tag) << "'s link";
        EXPECT_TRUE(all_tagged(j.got, tag)) << "joiner " << int(tag) << " got another joiner's datagram";
        const std::vector<Bytes> up_rel(h->got.begin() + 1, h->got.begin() + 4);
        const std::vector<Bytes> down_rel(j.got.begin(), j.got.begin() + 3);
        EXPECT_EQ(up_rel, (std::vector<Bytes>{tagged(tag, 16), tagged(tag, 200000), tagged(tag, 32)}));
        EXPECT_EQ(down_rel, (std::vector<Bytes>{tagged(tag, 17), tagged(tag, 200001), tagged(tag, 33)}));
    }
    const HubStats st = s.hub->stats();
    EXPECT_EQ(st.accepted, 2u);
    EXPECT_EQ(st.connected, 2u);
    EXPECT_EQ(st.refused, 0u);
    EXPECT_EQ(st.overflowed, 0u);
    EXPECT_GT(s.hosted[0]->link->traffic().datagrams, 0u);
}

TEST(EnetHub, SealedLinksHandshakeOverItAndAWrongKeyNeverJoins) {
    const SessionKey key = key_of(1), other = key_of(2);
    Session s(8);
    s.wrap = [&](std::unique_ptr<DatagramLink> link) -> std::unique_ptr<DatagramLink> {
        return std::make_unique<SealedLink>(std::move(link), key, SealRole::kListener);
    };
    s.join(&key);
    s.join(&key);
    ASSERT_TRUE(s.run_until([&] { return s.all_up(2); }, 10.0));
    ASSERT_TRUE(s.identify());
    ASSERT_TRUE(s.round_trip(0, "sealed 0"));
    ASSERT_TRUE(s.round_trip(1, "sealed 1"));
    // A joiner of another key: its hellos are refused (it retries every 0.2 s, each a new accept()).
    End& bad = s.join(&other);
    const auto refused = [&] {
        std::uint64_t n = 0;
        for (const auto& e : s.hosted) n += e->link->refused();
        return n;
    };
    ASSERT_TRUE(s.run_until([&] { return refused() > 0; }, 10.0));
    s.run_until([] { return false; }, 0.5);
    EXPECT_EQ(bad.connects, 0);
    EXPECT_FALSE(bad.link->connected());
    EXPECT_TRUE(bad.got.empty());
    EXPECT_TRUE(s.round_trip(0, "after 0"));
    EXPECT_TRUE(s.round_trip(1, "after 1"));
    EXPECT_EQ(s.host_of(1)->link->refused(), 0u);
    EXPECT_EQ(s.host_of(2)->link->refused(), 0u);
}

TEST(EnetHub, AJoinerThatLeavesIsReportedAndANewOneAccepted) {
    Session s(4);
    s.join();
    s.join();
    ASSERT_TRUE(s.run_until([&] { return s.all_up(2); }, 10.0));
    ASSERT_TRUE(s.identify());
    End* gone = s.host_of(1);
    End* stays = s.host_of(2);
    s.joiners[0]->link.reset();  // EnetLink's destructor disconnects at once
    ASSERT_TRUE(s.run_until([&] { return gone->disconnects == 1; }, 10.0));
    EXPECT_FALSE(gone->link->connected());
    EXPECT_EQ(stays->disconnects, 0);
    EXPECT_TRUE(s.round_trip(1, "still here"));
    // A new joiner is a new link; the old one stays dead.
    End& next = s.join();
    ASSERT_TRUE(s.run_until([&] { return s.hosted.size() == 3 && next.link->connected(); }, 10.0));
    next.link->send(Bytes{3}, true);
    ASSERT_TRUE(s.run_until([&] { return s.host_of(3) != nullptr; }, 10.0));
    EXPECT_TRUE(s.round_trip(2, "new"));
    EXPECT_EQ(gone->connects, 1);
    EXPECT_EQ(gone->disconnects, 1);
    EXPECT_FALSE(gone->link->connected());
    EXPECT_EQ(s.hub->stats().connected, 2u);
}

TEST(EnetHub, APeerBeyondMaxPeersIsRefused) {
    Session s(2);
    s.join();
    s.join();
    ASSERT_TRUE(s.run_until([&] { return s.all_up(2); }, 10.0));
    ASSERT_TRUE(s.identify());
    End& third = s.join();
    ASSERT_TRUE(s.run_until([&] { return s.hub->stats().refused > 0; }, 10.0));
    s.run_until([] { return false; }, 0.3);
    EXPECT_EQ(s.hosted.size(), 2u);
    EXPECT_EQ(s.hub->stats().accepted, 2u);
    EXPECT_EQ(s.hub->stats().connected, 2u);
    EXPECT_TRUE(third.got.empty());
    EXPECT_TRUE(s.round_trip(0, "unaffected 0"));
    EXPECT_TRUE(s.round_trip(1, "unaffected 1"));
    for (const auto& e : s.hosted) EXPECT_EQ(e->disconnects, 0);
}

/// A 4-byte datagram holding i (little-endian), and back.
Bytes numbered(std::uint32_t i, std::size_t size = 4) {
    Bytes b{static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(i >> 8), static_cast<std::uint8_t>(i >> 16),
            static_cast<std::uint8_t>(i >> 24)};
    b.resize(std::max<std::size_t>(size, 4), 0x5a);
    return b;
}
std::uint32_t number_of(const Bytes& b) {
    return b.size() < 4 ? 0xffffffffu : b[0] | b[1] << 8 | b[2] << 16 | static_cast<std::uint32_t>(b[3]) << 24;
}

// A hosted link nobody polls while its joiner floods: the oldest unreliable datagrams go (counted) and the queue holds
// kMaxQueuedUnreliable; past kMaxQueuedReliable reliable ones the peer is disconnected, and its link still delivers
// every reliable datagram that arrived, in order, before kDisconnected.
TEST(EnetHub, APeerQueueIsBounded) {
    Session s(2);
    End& j = s.join();
    ASSERT_TRUE(s.run_until([&] { return s.all_up(1); }, 10.0));
    End& h = *s.hosted[0];
    s.poll_hosted = false;
    std::uint32_t sent = 0;
    ASSERT_TRUE(s.run_until(
        [&] {
            for (int k = 0; k < 64; ++k) j.link->send(numbered(sent++), false);
            return s.hub->stats().unreliable_dropped > 0;
        },
        10.0));
    s.run_until([] { return false; }, 0.2);  // what is in flight lands
    const std::uint64_t dropped = s.hub->stats().unreliable_dropped;
    h.drain();
    ASSERT_EQ(h.got.size(), EnetHub::kMaxQueuedUnreliable);
    EXPECT_GE(number_of(h.got.front()), dropped) << "the oldest datagrams are the ones dropped";
    for (std::size_t i = 1; i < h.got.size(); ++i) ASSERT_LT(number_of(h.got[i - 1]), number_of(h.got[i]));
    EXPECT_TRUE(h.link->connected());

    h.got.clear();
    const std::uint32_t n = EnetHub::kMaxQueuedReliable + 1;
    for (std::uint32_t i = 0; i < n; ++i) j.link->send(numbered(i), true);
    ASSERT_TRUE(s.run_until([&] { return s.hub->stats().overflowed == 1; }, 30.0));
    EXPECT_FALSE(h.link->connected());
    h.drain();
    ASSERT_EQ(h.got.size(), n);
    std::size_t out_of_place = 0;
    for (std::uint32_t i = 0; i < n; ++i) out_of_place += number_of(h.got[i]) != i;
    EXPECT_EQ(out_of_place, 0u);
    EXPECT_EQ(h.disconnects, 1);
}

TEST(EnetHub, AReaderThatReusesItsBufferKeepsTheQueuesAccountsRight) {
    // A link's reader that keeps one buffer for every datagram (as SealedLink does): reading a large reliable datagram
    // and then small unreliable ones into it must leave both queues' byte counts right, or a queue counts as over its
    // bound and drops (or disconnects) what comes next.
    Session s(2);
    End& j = s.join();
    ASSERT_TRUE(s.run_until([&] { return s.all_up(1); }, 10.0));
    End& h = *s.hosted[0];
    s.poll_hosted = false;
    LinkEvent ev;  // kept across polls
    std::vector<Bytes> got;
    const auto read = [&] {
        while (h.link->poll(ev))
            if (ev.kind == LinkEvent::kData) got.push_back(ev.data);
    };
    j.link->send(numbered(0, 300000), true);
    ASSERT_TRUE(s.run_until([&] { read(); return !got.empty(); }, 20.0));
    std::uint32_t sent = 0;
    ASSERT_TRUE(s.run_until(
        [&] {
            read();
            for (int k = 0; k < 4 && sent < 600; ++k) j.link->send(numbered(100 + sent++), false);
            return sent >= 600;
        },
        30.0));
    s.run_until([&] { read(); return false; }, 0.3);  // what is in flight lands
    EXPECT_EQ(s.hub->stats().unreliable_dropped, 0u);
    EXPECT_EQ(s.hub->stats().overflowed, 0u);
    EXPECT_GT(got.size(), 500u) << "of 600 unreliable datagrams on loopback";
    EXPECT_TRUE(h.link->connected());
}

TEST(EnetHub, DatagramsFromNoPeerCountAsForeignAndAPeersDoNot) {
    Session s(2);
    s.join();
    ASSERT_TRUE(s.run_until([&] { return s.all_up(1); }, 10.0));
    ASSERT_TRUE(s.identify());
    const LinkTraffic before = s.hub->traffic();
    EXPECT_GT(before.datagrams, 0u);
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    ASSERT_GE(fd, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(s.hub->port());
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const std::uint8_t junk[40] = {0x12, 0x34, 0x56};
    for (int i = 0; i < 20; ++i) ::sendto(fd, junk, sizeof junk, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
    ::close(fd);
    ASSERT_TRUE(s.run_until([&] { return s.hub->traffic().foreign >= before.foreign + 20; }, 10.0));
    EXPECT_TRUE(s.round_trip(0, "after the junk"));  // the peer still speaks, and its datagrams are not foreign
    const LinkTraffic after = s.hub->traffic();
    EXPECT_EQ(after.foreign, before.foreign + 20);
    EXPECT_GE(after.datagrams, before.datagrams + 21);
}

TEST(EnetHub, ListenRefusesBadArgumentsAndABusyPort) {
    EXPECT_THROW(EnetHub::listen("127.0.0.1", 0, 0), tridex::Error);
    EXPECT_THROW(EnetHub::listen("127.0.0.1", 0, EnetHub::kMaxPeers + 1), tridex::Error);
    EXPECT_THROW(EnetHub::listen("127.0.0.1", 0, 2, 0.0), tridex::Error);
    const std::unique_ptr<EnetHub> first = EnetHub::listen("127.0.0.1", 0, 2);
    try {
        EnetHub::listen("127.0.0.1", first->port(), 2);
        ADD_FAILURE() << "a second hub listened on a busy port";
    } catch (const tridex::Error& e) {
        EXPECT_NE(std::string(e.what()).find("cannot listen"), std::string::npos) << e.what();
    }
}

}  // namespace
