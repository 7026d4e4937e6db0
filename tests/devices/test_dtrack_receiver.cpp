// Tests of devices/tracking/dtrack_receiver over loopback UDP: poses arrive in SI units with a receipt time, the
// newest one per body wins, late or replayed frame counters are refused, bad datagrams (64 KiB of junk included) are counted by reason and dropped, and a
// reader polling while a sender floods never waits (run under ThreadSanitizer with the devices tests).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <string>
#include <thread>

#include "core/error.hpp"
#include "devices/tracking/dtrack_receiver.hpp"
#include "dtrack_sender.hpp"

namespace tridex::devices {
namespace {

using test::dtrack_datagram;
using test::dtrack_flystick_datagram;
using test::DTrackSender;
using test::rotation_y_deg;

/// Waits (up to 5 s) until the receiver has seen `n` datagrams.
bool wait_for(const DTrackReceiver& rx, std::uint64_t n) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (rx.stats().datagrams < n) {
        if (std::chrono::steady_clock::now() > until) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return true;
}

/// Waits (up to 5 s) until the published table has `accepted` datagrams in it.
const DTrackBodyTable& wait_table(DTrackReceiver& rx, std::uint64_t accepted) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    for (;;) {
        const DTrackBodyTable& t = rx.latest();
        if (t.accepted >= accepted || std::chrono::steady_clock::now() > until) return t;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

TEST(DTrackReceiver, ReceivesPosesInMetresWithReceiptTime) {
    DTrackReceiver rx(0, "127.0.0.1");
    ASSERT_GT(rx.port(), 0);
    DTrackSender tx(rx.port());
    const auto before = std::chrono::steady_clock::now().time_since_epoch();
    ASSERT_TRUE(tx.send(dtrack_datagram(10, 2, Vec3(120.0, 1700.0, 850.0), rotation_y_deg(30.0))));
    const DTrackBodyTable& t = wait_table(rx, 1);
    ASSERT_EQ(t.accepted, 1u);
    const DTrackBodySample& s = t.bodies[2];
    ASSERT_TRUE(s.seen);
    EXPECT_FALSE(t.bodies[0].seen);
    EXPECT_EQ(s.frame_counter, 10u);
    EXPECT_NEAR(s.body.position_m.x, 0.120, 1e-9);
    EXPECT_NEAR(s.body.position_m.y, 1.700, 1e-9);
    EXPECT_NEAR(s.body.position_m.z, 0.850, 1e-9);
    const Vec3 x = s.body.pose().rotate(Vec3(1, 0, 0));
    EXPECT_NEAR(x.x, std::cos(M_PI / 6), 1e-8);
    EXPECT_NEAR(x.z, -std::sin(M_PI / 6), 1e-8);
    EXPECT_GE(s.receipt_ns, std::chrono::duration_cast<std::chrono::nanoseconds>(before).count());
    EXPECT_LE(s.receipt_ns,
              std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
                  .count());
}

TEST(DTrackReceiver, NewestPoseWinsAndOtherBodiesKeepTheirs) {
    DTrackReceiver rx(0, "127.0.0.1");
    DTrackSender tx(rx.port());
    ASSERT_TRUE(tx.send(dtrack_datagram(1, 0, Vec3(0, 1000, 500), glm::dmat3(1.0))));
    ASSERT_TRUE(tx.send(dtrack_datagram(2, 1, Vec3(0, 0, 0), glm::dmat3(1.0))));
    ASSERT_TRUE(tx.send(dtrack_datagram(3, 0, Vec3(10, 1000, 500), glm::dmat3(1.0))));
    const DTrackBodyTable& t = wait_table(rx, 3);
    ASSERT_EQ(t.accepted, 3u);
    EXPECT_EQ(t.bodies[0].frame_counter, 3u);
    EXPECT_NEAR(t.bodies[0].body.position_m.x, 0.010, 1e-12);
    EXPECT_EQ(t.bodies[1].frame_counter, 2u);
    EXPECT_EQ(t.bodies[0].datagram, 3u);
    EXPECT_LE(t.bodies[1].receipt_ns, t.bodies[0].receipt_ns);
}

TEST(DTrackReceiver, KeepsTheNewestFlystickWithButtonsAndJoystick) {
    DTrackReceiver rx(0, "127.0.0.1");
    DTrackSender tx(rx.port());
    ASSERT_TRUE(tx.send(dtrack_flystick_datagram(1, 1, Vec3(100, 1200, 300), rotation_y_deg(30.0), 0x1, 0.0, 0.5)));
    ASSERT_TRUE(tx.send(dtrack_flystick_datagram(2, 1, Vec3(150, 1200, 300), glm::dmat3(1.0), 0x5, -0.25, -1.0)));
    const DTrackBodyTable& t = wait_table(rx, 2);
    ASSERT_EQ(t.accepted, 2u);
    EXPECT_FALSE(t.flysticks[0].seen);
    const DTrackFlystickSample& f = t.flysticks[1];
    ASSERT_TRUE(f.seen);
    EXPECT_EQ(f.frame_counter, 2u);
    EXPECT_EQ(f.datagram, 2u);
    EXPECT_NEAR(f.flystick.body.position_m.x, 0.150, 1e-9);
    EXPECT_EQ(f.flystick.buttons, 0x5u);
    ASSERT_EQ(f.flystick.controller_count, 2);
    EXPECT_DOUBLE_EQ(f.flystick.controllers[0], -0.25);
    EXPECT_DOUBLE_EQ(f.flystick.controllers[1], -1.0);
    EXPECT_FALSE(t.bodies[1].seen);  // a Flystick is not a standard body
    // Ids past the kept range are counted and dropped.
    ASSERT_TRUE(tx.send(dtrack_flystick_datagram(3, kDTrackKeptFlysticks, Vec3(0), glm::dmat3(1.0), 0, 0, 0)));
    wait_table(rx, 3);
    EXPECT_EQ(rx.stats().flysticks_dropped, 1u);
}

TEST(DTrackReceiver, BadDatagramsAreCountedAndDropped) {
    DTrackReceiver rx(0, "127.0.0.1");
    DTrackSender tx(rx.port());
    std::mt19937_64 rng(7);
    std::string junk(65507, '\0');  // the largest UDP payload over IPv4: 64 KiB of junk
    for (char& c : junk) c = static_cast<char>(rng() & 0xFF);
    ASSERT_TRUE(tx.send(junk));
    ASSERT_TRUE(tx.send("6d 1 [0 1.0][1 2"));                                     // truncated
    ASSERT_TRUE(tx.send("6d 1 [0 1.0][1 2 x][1 0 0 0 1 0 0 0 1]"));               // non-numeric
    ASSERT_TRUE(tx.send("6d 1 [0 1.0][nan 2 3][1 0 0 0 1 0 0 0 1]"));             // NaN
    ASSERT_TRUE(tx.send("6d 2 [0 1.0][1 2 3][1 0 0 0 1 0 0 0 1]"));               // wrong body count
    ASSERT_TRUE(tx.send(""));                                                     // empty
    ASSERT_TRUE(tx.send(dtrack_datagram(5, 0, Vec3(1, 2, 3), glm::dmat3(1.0))));  // good
    ASSERT_TRUE(wait_for(rx, 7));
    const DTrackReceiverStats s = rx.stats();
    EXPECT_EQ(s.datagrams, 7u);
    EXPECT_EQ(s.accepted, 1u);
    EXPECT_EQ(s.rejected, 6u);
    const auto at = [&](DTrackReject r) { return s.by_reason[static_cast<std::size_t>(r)]; };
    EXPECT_EQ(at(DTrackReject::kNotText), 1u);
    EXPECT_EQ(at(DTrackReject::kTruncated), 1u);
    EXPECT_EQ(at(DTrackReject::kNotNumeric), 1u);
    EXPECT_EQ(at(DTrackReject::kNotFinite), 1u);
    EXPECT_EQ(at(DTrackReject::kBodyCount), 1u);
    EXPECT_EQ(at(DTrackReject::kEmpty), 1u);
    const DTrackBodyTable& t = wait_table(rx, 1);
    EXPECT_TRUE(t.bodies[0].seen);
    EXPECT_EQ(t.bodies[0].frame_counter, 5u);
}

// A datagram whose frame counter is older than the newest accepted one (late, or replayed by someone on the network,
// however old) is rejected as replayed and moves nothing; the newest frame's counter again is another datagram of
// that frame; after a second of silence any counter is a restarted tracker and accepted.
TEST(DTrackReceiver, LateOrReplayedFrameCountersAreRejected) {
    DTrackReceiver rx(0, "127.0.0.1");
    DTrackSender tx(rx.port());
    ASSERT_TRUE(tx.send(dtrack_datagram(100, 0, Vec3(10, 0, 0), glm::dmat3(1.0))));
    ASSERT_TRUE(tx.send(dtrack_datagram(101, 0, Vec3(11, 0, 0), glm::dmat3(1.0))));
    ASSERT_TRUE(tx.send(dtrack_datagram(100, 0, Vec3(99, 0, 0), glm::dmat3(1.0))));  // replayed
    ASSERT_TRUE(tx.send(dtrack_datagram(101, 1, Vec3(11, 0, 0), glm::dmat3(1.0))));  // the same frame, body 1
    ASSERT_TRUE(tx.send(dtrack_datagram(1, 0, Vec3(99, 0, 0), glm::dmat3(1.0))));    // an old one replayed
    ASSERT_TRUE(tx.send(dtrack_datagram(5000, 0, Vec3(12, 0, 0), glm::dmat3(1.0))));
    ASSERT_TRUE(tx.send(dtrack_datagram(3, 0, Vec3(99, 0, 0), glm::dmat3(1.0))));  // far behind, no silence
    ASSERT_TRUE(wait_for(rx, 7));
    DTrackReceiverStats s = rx.stats();
    EXPECT_EQ(s.accepted, 4u);
    EXPECT_EQ(s.rejected, 3u);
    EXPECT_EQ(s.by_reason[static_cast<std::size_t>(DTrackReject::kReplayed)], 3u);
    EXPECT_STREQ(to_string(DTrackReject::kReplayed), "replayed");
    const DTrackBodyTable& t = wait_table(rx, 4);
    EXPECT_EQ(t.bodies[1].frame_counter, 101u);
    EXPECT_EQ(t.bodies[0].frame_counter, 5000u);
    EXPECT_NEAR(t.bodies[0].body.position_m.x, 0.012, 1e-12);
    // After a silence of kDTrackRestartGapNs, a counter far behind is a restarted tracker.
    std::this_thread::sleep_for(std::chrono::nanoseconds(kDTrackRestartGapNs + 100'000'000));
    ASSERT_TRUE(tx.send(dtrack_datagram(2, 0, Vec3(15, 0, 0), glm::dmat3(1.0))));
    ASSERT_TRUE(wait_for(rx, 8));
    s = rx.stats();
    EXPECT_EQ(s.accepted, 5u);
    EXPECT_EQ(s.rejected, 3u);
    EXPECT_EQ(wait_table(rx, 5).bodies[0].frame_counter, 2u);
}

TEST(DTrackReceiver, ReaderNeverWaitsWhileASenderFloods) {
    DTrackReceiver rx(0, "127.0.0.1");
    constexpr unsigned kN = 3000;
    std::atomic<bool> done{false};
    std::thread sender([port = rx.port(), &done] {
        DTrackSender tx(port);
        for (unsigned i = 1; i <= kN; ++i) {
            tx.send(dtrack_datagram(i, static_cast<int>(i % 4), Vec3(i, 0, 0), glm::dmat3(1.0)));
            if (i % 64 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        done.store(true);
    });
    std::uint64_t reads = 0, last_accepted = 0;
    double worst_us = 0.0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < deadline) {
        const bool finished = done.load();
        const auto t0 = std::chrono::steady_clock::now();
        const DTrackBodyTable& t = rx.latest();
        worst_us = std::max(worst_us,
                            std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
        EXPECT_GE(t.accepted, last_accepted);  // snapshots only move forward
        for (int b = 0; b < 4; ++b) {
            if (t.bodies[b].seen) {
                EXPECT_EQ(static_cast<int>(t.bodies[b].frame_counter % 4), b);
            }
        }
        last_accepted = t.accepted;
        ++reads;
        if (finished && t.accepted == rx.stats().accepted) {
            std::this_thread::sleep_for(std::chrono::milliseconds(30));  // the last drain
            if (rx.latest().accepted == rx.stats().accepted) break;
        }
    }
    sender.join();
    // Loopback may drop datagrams when the socket buffer is full; whatever arrived was accepted.
    EXPECT_TRUE(wait_for(rx, 1));
    EXPECT_EQ(rx.stats().rejected, 0u);
    std::printf(
        "[ dtrack ] flood: %llu datagrams received of %u, %llu reads, slowest latest() %.1f us (preemption included)\n",
        static_cast<unsigned long long>(rx.stats().datagrams), kN, static_cast<unsigned long long>(reads), worst_us);
}

TEST(DTrackReceiver, BadPortOrAddressOrBusyPortThrowsNamingIt) {
    EXPECT_THROW(DTrackReceiver(70000), Error);
    EXPECT_THROW(DTrackReceiver(0, "localhost-ish"), Error);
    DTrackReceiver a(0, "127.0.0.1");
    try {
        DTrackReceiver b(a.port(), "127.0.0.1");
        FAIL() << "a second receiver bound the same port";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(std::to_string(a.port())), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace tridex::devices
