// A network wall's transport (app/session/cluster/net_transport.hpp) over real ENet on 127.0.0.1, port 0: rank 0 and
// its render ranks exchange messages of any size whole and in order, claims of a held, out-of-range or other-protocol
// rank are refused, a process that dies leaves its rank to a new one once released (nothing of the old one leaks),
// a sealed wall lets in only the processes with its key, and a render rank learns that rank 0 left or ended the
// session. No GPU: these run under ThreadSanitizer too (each transport's network thread beside the test's).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <string>
#include <thread>

#include "app/session/cluster/net_transport.hpp"
#include "app/session/cluster/net_transport_wire.hpp"
#include "core/error.hpp"
#include "devices/net/enet_link.hpp"
#include "error_of.hpp"

namespace tridex::app {
namespace {

namespace net = devices::net;
using Bytes = std::vector<unsigned char>;
using Clock = std::chrono::steady_clock;

constexpr const char* kHost = "127.0.0.1";

net::SessionKey key_of(std::uint8_t seed) {
    std::uint8_t b[net::SessionKey::kBytes];
    for (std::size_t i = 0; i < sizeof b; ++i) b[i] = static_cast<std::uint8_t>(seed + 29 * i);
    return net::SessionKey(b);
}

Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

Bytes random_bytes(std::size_t n, std::mt19937& rng) {
    Bytes b(n);
    for (unsigned char& c : b) c = static_cast<unsigned char>(rng());
    return b;
}

std::unique_ptr<ClusterTransport> listener(int render_ranks, const std::optional<net::SessionKey>& key = {}) {
    return make_listener_transport(kHost, 0, render_ranks, key);
}

std::unique_ptr<ClusterTransport> member(const ClusterTransport& rank0, int rank, int render_ranks,
                                         const std::optional<net::SessionKey>& key = {}, double wait_s = 3.0) {
    return make_member_transport(kHost, listener_port(rank0), rank, render_ranks, key, deadline_after(wait_s));
}

// The next message from `from`, failing the test when none comes within `wait_s`.
Bytes next(ClusterTransport& t, int from, double wait_s = 5.0) {
    std::optional<Bytes> m = t.receive(from, deadline_after(wait_s));
    EXPECT_TRUE(m.has_value()) << "no message from rank " << from << " within " << wait_s << " s";
    return m ? *m : Bytes{};
}

using test::error_of;

// Waits until rank 0 no longer has render rank r's process (at most wait_s).
bool wait_absent(const ClusterTransport& rank0, int r, double wait_s) {
    const auto end = deadline_after(wait_s);
    while (rank0.present(r) && Clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return !rank0.present(r);
}

// Receives until the transport throws (at most wait_s); its message, or "" when it did not.
std::string wait_error(ClusterTransport& t, int from, double wait_s) {
    const auto end = deadline_after(wait_s);
    while (Clock::now() < end) {
        const std::string e = error_of([&] { (void)t.receive(from, deadline_after(0.05)); });
        if (!e.empty()) return e;
    }
    return "";
}

TEST(ClusterLink, RanksExchangeMessagesWholeAndInOrder) {
    auto rank0 = listener(2);
    EXPECT_TRUE(rank0->open_membership());
    EXPECT_EQ(rank0->rank(), 0);
    EXPECT_EQ(rank0->size(), 3);
    EXPECT_NE(listener_port(*rank0), 0);
    EXPECT_NE(rank0->name().find("ENet "), std::string::npos) << rank0->name();
    EXPECT_NE(rank0->name().find(":" + std::to_string(listener_port(*rank0))), std::string::npos) << rank0->name();
    auto r1 = member(*rank0, 1, 2);
    auto r2 = member(*rank0, 2, 2);
    EXPECT_EQ(listener_port(*r1), 0);
    EXPECT_EQ(r1->rank(), 1);
    EXPECT_EQ(r2->size(), 3);
    EXPECT_EQ(rank0->arrivals(), (std::vector<int>{1, 2}));
    EXPECT_TRUE(rank0->arrivals().empty());
    EXPECT_TRUE(rank0->present(1) && rank0->present(2));

    std::mt19937 rng(7);
    const Bytes big = random_bytes(5'000'000, rng), back = random_bytes(1'234'567, rng);
    rank0->send(1, text("hello 1"));
    rank0->send(1, big);
    rank0->send(1, {});
    rank0->send(2, text("hello 2"));
    r1->send(0, back);
    r2->send(0, text("from 2"));
    EXPECT_TRUE(rank0->flush(deadline_after(5.0)));
    EXPECT_TRUE(r1->flush(deadline_after(5.0)));
    EXPECT_TRUE(r2->flush(deadline_after(5.0)));
    EXPECT_EQ(next(*r1, 0), text("hello 1"));
    EXPECT_TRUE(next(*r1, 0) == big) << "the 5 MB message changed on its way";
    EXPECT_TRUE(next(*r1, 0).empty());
    EXPECT_EQ(next(*r2, 0), text("hello 2"));
    EXPECT_TRUE(next(*rank0, 1) == back);
    EXPECT_EQ(next(*rank0, 2), text("from 2"));
    EXPECT_FALSE(rank0->receive(1, deadline_after(0.05)).has_value());
    EXPECT_FALSE(r2->receive(0, deadline_after(0.05)).has_value());

    EXPECT_NE(error_of([&] { rank0->send(3, text("x")); }), "");
    EXPECT_NE(error_of([&] { rank0->send(0, text("x")); }), "");
    EXPECT_NE(error_of([&] { r1->send(2, text("x")); }), "");
    EXPECT_NE(error_of([&] { (void)r1->receive(2, deadline_after(0.01)); }), "");
}

// A claim sent by hand over a plain link; rank 0's answer to it.
netwire::Control answer_to(std::uint16_t port, const std::vector<std::uint8_t>& claim) {
    auto link = net::EnetLink::connect(kHost, port, 3.0);
    const auto end = deadline_after(3.0);
    net::LinkEvent ev;
    while (Clock::now() < end) {
        while (link->poll(ev)) {
            if (ev.kind == net::LinkEvent::kConnected) link->send(claim, true);
            if (ev.kind == net::LinkEvent::kData) return netwire::decode_control(ev.data);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ADD_FAILURE() << "no answer from rank 0";
    return {};
}

TEST(ClusterLink, RefusesAHeldRankOneOutOfRangeAndAnotherProtocol) {
    auto rank0 = listener(2);
    auto r1 = member(*rank0, 1, 2);
    const std::string held = error_of([&] { member(*rank0, 1, 2); });
    EXPECT_NE(held.find("--cluster-connect 127.0.0.1:"), std::string::npos) << held;
    EXPECT_NE(held.find("refused"), std::string::npos) << held;
    EXPECT_NE(held.find("render rank 1 is held"), std::string::npos) << held;
    // A member that believes the wall is larger claims a rank rank 0 does not have.
    const std::string range = error_of([&] { member(*rank0, 3, 4); });
    EXPECT_NE(range.find("rank 3 is not a render rank of this wall (1..2)"), std::string::npos) << range;

    std::vector<std::uint8_t> other = netwire::encode_claim(2);
    other[5] = 99;  // the protocol version (u16 after the kind byte and "TDXW")
    const netwire::Control a = answer_to(listener_port(*rank0), other);
    EXPECT_EQ(a.type, netwire::ControlType::kRefuse);
    EXPECT_NE(a.reason.find("version 99"), std::string::npos) << a.reason;
    const netwire::Control b = answer_to(listener_port(*rank0), {0xC1, 'X', 'Y'});
    EXPECT_EQ(b.type, netwire::ControlType::kRefuse);
    EXPECT_NE(b.reason.find("could not read"), std::string::npos) << b.reason;

    // Rank 0 carries on: rank 2 is still free, rank 1's process still served.
    auto r2 = member(*rank0, 2, 2);
    EXPECT_EQ(rank0->arrivals(), (std::vector<int>{1, 2}));
    rank0->send(1, text("still here"));
    EXPECT_EQ(next(*r1, 0), text("still here"));
}

TEST(ClusterLink, ANewProcessTakesAReleasedRankAndNothingOfTheOldLeaks) {
    auto rank0 = listener(1);
    auto old = member(*rank0, 1, 1);
    EXPECT_EQ(rank0->arrivals(), std::vector<int>{1});
    old->send(0, text("old a"));
    ASSERT_TRUE(old->flush(deadline_after(3.0)));
    old.reset();  // its process dies
    ASSERT_TRUE(wait_absent(*rank0, 1, 5.0));
    EXPECT_EQ(next(*rank0, 1), text("old a"));  // what came before the leave is still received
    const std::string left = error_of([&] { (void)rank0->receive(1, deadline_after(1.0)); });
    EXPECT_NE(left.find("render rank 1 left"), std::string::npos) << left;
    EXPECT_TRUE(rank0->flush(deadline_after(1.0)));  // nothing was sent to it unacknowledged
    rank0->send(1, text("to nobody"));               // absent: dropped
    rank0->release(1);

    // A second process, alive, sends something rank 0 releases unread.
    auto second = member(*rank0, 1, 1);
    EXPECT_EQ(rank0->arrivals(), std::vector<int>{1});
    second->send(0, text("stale"));
    ASSERT_TRUE(second->flush(deadline_after(3.0)));
    rank0->send(1, text("owed"));  // queued before the release: still sent before the disconnect
    rank0->release(1);
    EXPECT_FALSE(rank0->present(1));
    EXPECT_TRUE(rank0->arrivals().empty());
    EXPECT_FALSE(rank0->receive(1, deadline_after(0.05)).has_value());  // "stale" went with the release
    rank0->send(1, text("dropped"));
    EXPECT_EQ(next(*second, 0), text("owed"));
    const std::string dropped = wait_error(*second, 0, 5.0);
    EXPECT_NE(dropped.find("rank 0 left"), std::string::npos) << dropped;

    auto third = member(*rank0, 1, 1);
    EXPECT_EQ(rank0->arrivals(), std::vector<int>{1});
    EXPECT_TRUE(rank0->present(1));
    third->send(0, text("fresh"));
    EXPECT_EQ(next(*rank0, 1), text("fresh"));
    rank0->send(1, text("to the new one"));
    EXPECT_EQ(next(*third, 0), text("to the new one"));
    EXPECT_TRUE(rank0->flush(deadline_after(3.0)));
    EXPECT_FALSE(rank0->receive(1, deadline_after(0.05)).has_value());
}

TEST(ClusterLink, ASealedWallLetsInOnlyItsKey) {
    const net::SessionKey key = key_of(3);
    auto rank0 = listener(2, key);
    EXPECT_NE(rank0->name().find("(sealed)"), std::string::npos) << rank0->name();
    auto r1 = member(*rank0, 1, 2, key);
    EXPECT_NE(r1->name().find("(sealed)"), std::string::npos) << r1->name();
    rank0->send(1, text("sealed hello"));
    EXPECT_EQ(next(*r1, 0), text("sealed hello"));

    const auto t0 = Clock::now();
    const std::string other = error_of([&] { member(*rank0, 2, 2, key_of(4), 2.0); });
    EXPECT_NE(other.find("handshake failed"), std::string::npos) << other;
    EXPECT_NE(other.find("same key"), std::string::npos) << other;
    const std::string none = error_of([&] { member(*rank0, 2, 2, std::nullopt, 2.0); });
    EXPECT_NE(none.find("--cluster-connect"), std::string::npos) << none;
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 5.0);
    EXPECT_FALSE(rank0->present(2));
    EXPECT_TRUE(rank0->arrivals().size() == 1);

    auto open = listener(1);
    const std::string keyed = error_of([&] { member(*open, 1, 1, key, 2.0); });
    EXPECT_NE(keyed.find("handshake failed"), std::string::npos) << keyed;
    EXPECT_FALSE(open->present(1));
}

TEST(ClusterLink, ARenderRankLearnsThatRankZeroLeft) {
    auto rank0 = listener(1);
    auto r1 = member(*rank0, 1, 1);
    rank0->send(1, text("last"));
    ASSERT_TRUE(rank0->flush(deadline_after(3.0)));
    rank0.reset();
    EXPECT_EQ(next(*r1, 0), text("last"));
    const std::string left = wait_error(*r1, 0, 5.0);
    EXPECT_EQ(left, "rank 0 left (its connection closed or timed out)");
    EXPECT_NE(error_of([&] { r1->send(0, text("x")); }), "");
}

TEST(ClusterLink, ManyMessagesOfMixedSizesQueueWithoutLoss) {
    auto rank0 = listener(1);
    auto r1 = member(*rank0, 1, 1);
    std::mt19937 rng(11);
    std::uniform_int_distribution<std::size_t> size(0, 300 << 10);
    std::vector<Bytes> down, up;
    for (int i = 0; i < 200; ++i) {
        down.push_back(random_bytes(i % 25 == 3 ? 1'500'000 + size(rng) : size(rng), rng));  // a few of 6 datagrams
        up.push_back(random_bytes(size(rng) / 4, rng));
        rank0->send(1, down.back());
        r1->send(0, up.back());
    }
    EXPECT_TRUE(rank0->flush(deadline_after(20.0)));  // every message whole in r1's transport before r1 reads any
    EXPECT_TRUE(r1->flush(deadline_after(20.0)));
    for (std::size_t i = 0; i < down.size(); ++i) ASSERT_TRUE(next(*r1, 0, 1.0) == down[i]) << "message " << i;
    for (std::size_t i = 0; i < up.size(); ++i) ASSERT_TRUE(next(*rank0, 1, 1.0) == up[i]) << "message " << i;
    EXPECT_FALSE(r1->receive(0, deadline_after(0.05)).has_value());
}

TEST(ClusterLink, AnAbortFromRankZeroEndsTheRenderRanksReceive) {
    // A rank 0 by hand (one plain link): it accepts the claim, then ends the session with code 7.
    auto server = net::EnetLink::listen(kHost, 0);
    const std::uint16_t port = server->port();
    std::atomic<bool> stop{false};
    std::atomic<std::uint64_t> acked{0};
    std::thread fake([&] {
        net::LinkEvent ev;
        while (!stop.load()) {
            while (server->poll(ev)) {
                if (ev.kind != net::LinkEvent::kData) continue;
                const netwire::Control c = netwire::decode_control(ev.data);
                if (c.type == netwire::ControlType::kClaim) {
                    server->send(netwire::encode_accept(c.rank), true);
                    server->send(netwire::encode_abort(7), true);
                } else if (c.type == netwire::ControlType::kAck) {
                    acked.store(c.count);
                }
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    });
    {
        auto r1 = make_member_transport(kHost, port, 1, 1, std::nullopt, deadline_after(3.0));
        const std::string ended = wait_error(*r1, 0, 3.0);
        EXPECT_EQ(ended, "rank 0 ended the session (code 7)");
        const auto end = deadline_after(3.0);
        while (acked.load() < 1 && Clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        EXPECT_EQ(acked.load(), 1u);  // the abort counts as a message, so rank 0's flush waits for it
    }
    stop.store(true);
    fake.join();
}

TEST(ClusterLink, RankZerosAbortEndsItsProcessWithTheCode) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_EXIT(
        {
            auto rank0 = listener(1);
            auto r1 = member(*rank0, 1, 1);
            rank0->abort_all(5);
        },
        ::testing::ExitedWithCode(5), "");
}

TEST(ClusterLink, AListeningAddressIsAPortOrAnAddressAndAPort) {
    std::string host;
    std::uint16_t port = 1;
    devices::net::split_listen_address("7100", "--cluster-listen", host, port);
    EXPECT_EQ(host, "0.0.0.0");
    EXPECT_EQ(port, 7100);
    devices::net::split_listen_address("127.0.0.1:0", "--cluster-listen", host, port);
    EXPECT_EQ(host, "127.0.0.1");
    EXPECT_EQ(port, 0);
    const std::string bad = error_of([&] { devices::net::split_listen_address("wall:x", "--cluster-listen", host, port); });
    EXPECT_NE(bad.find("--cluster-listen: 'wall:x' is not HOST:PORT"), std::string::npos) << bad;
}

TEST(ClusterLink, BadOptionsAreNamed) {
    const std::string ranks = error_of([] { listener(0); });
    EXPECT_NE(ranks.find("--cluster-listen 127.0.0.1:0: 0 render ranks is not 1..31"), std::string::npos) << ranks;
    auto rank0 = listener(1);
    const std::string taken = error_of([&] { make_listener_transport(kHost, listener_port(*rank0), 1, {}); });
    EXPECT_NE(taken.find("--cluster-listen 127.0.0.1:" + std::to_string(listener_port(*rank0)) + ": "),
              std::string::npos)
        << taken;
    const auto t0 = Clock::now();
    const std::string none = error_of([] { make_member_transport(kHost, 9, 1, 1, {}, deadline_after(0.5)); });
    EXPECT_NE(none.find("--cluster-connect 127.0.0.1:9: no answer from rank 0 within 0.5 s"), std::string::npos)
        << none;
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 2.0);
}

}  // namespace
}  // namespace tridex::app
