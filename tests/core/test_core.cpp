// Tests of core/: the lock-free hand-offs and the mesh topology checks.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <string>
#include <thread>

#include "core/change_signal.hpp"
#include "core/crc32.hpp"
#include "core/format.hpp"
#include "core/pose.hpp"
#include "core/spsc_ring.hpp"
#include "core/thread_name.hpp"
#include "core/tri_mesh.hpp"
#include "core/triple_buffer.hpp"

namespace tridex {
namespace {

TEST(Format, LengthsInMillimetresAsAPersonReadsThem) {
    EXPECT_EQ(format_mm(0.0117188), "11.7 mm");
    EXPECT_EQ(format_mm(0.012), "12 mm");
    EXPECT_EQ(format_mm(-0.012), "-12 mm");
    EXPECT_EQ(format_mm(8.67e-16), "0 mm");
    EXPECT_EQ(format_mm(-1e-9), "0 mm");
    EXPECT_EQ(format_mm(0.00006), "0.1 mm");
    EXPECT_EQ(format_mm(std::nan("")), "-- mm");
}

TEST(ThreadName, NamesTheCallingThreadCutToFifteenBytes) {
    std::string seen_short, seen_long;
    std::thread t([&] {
        auto comm = [] {
            std::ifstream in("/proc/thread-self/comm");
            std::string s;
            std::getline(in, s);
            return s;
        };
        name_this_thread("tridex-sculpt");
        seen_short = comm();
        name_this_thread("a-name-longer-than-fifteen-bytes");
        seen_long = comm();
    });
    t.join();
    EXPECT_EQ(seen_short, "tridex-sculpt");
    EXPECT_EQ(seen_long, "a-name-longer-t");
}

TEST(SpscRing, KeepsOrderAndRefusesWhenFull) {
    SpscRing<int> ring(4);
    EXPECT_EQ(ring.capacity(), 4u);
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.try_push(i));
    EXPECT_FALSE(ring.try_push(99));
    int v = -1;
    for (int i = 0; i < 4; ++i) {
        ASSERT_TRUE(ring.try_pop(v));
        EXPECT_EQ(v, i);
    }
    EXPECT_FALSE(ring.try_pop(v));
}

TEST(SpscRing, TwoThreadsLoseNothing) {
    SpscRing<long> ring(64);
    constexpr long kCount = 200000;
    std::thread producer([&] {
        for (long i = 0; i < kCount;)
            if (ring.try_push(i)) ++i;
    });
    long expected = 0, v = 0;
    while (expected < kCount) {
        if (ring.try_pop(v)) {
            ASSERT_EQ(v, expected++);
        }
    }
    producer.join();
}

struct Big {
    long a = 0;
    long payload[256] = {};
    long b = 0;
};

TEST(TripleBuffer, ReaderSeesOnlyCompleteSnapshotsInOrder) {
    TripleBuffer<Big> tb;
    EXPECT_EQ(tb.latest().a, 0);
    constexpr long kCount = 100000;
    std::thread writer([&] {
        for (long i = 1; i <= kCount; ++i) {
            Big& s = tb.back();
            s.a = i;
            for (long& p : s.payload) p = i;
            s.b = i;
            tb.publish();
        }
    });
    long last = 0;
    while (last < kCount) {
        const Big& s = tb.latest();
        ASSERT_EQ(s.a, s.b);
        ASSERT_EQ(s.payload[128], s.a);
        ASSERT_GE(s.a, last);
        last = s.a;
    }
    writer.join();
}

TEST(TripleBuffer, UnreadUntilTheReaderTakesTheNewest) {
    TripleBuffer<int> tb;
    EXPECT_FALSE(tb.unread());  // nothing published yet
    tb.back() = 1;
    tb.publish();
    EXPECT_TRUE(tb.unread());
    tb.back() = 2;
    tb.publish();  // replaces 1 unseen
    EXPECT_TRUE(tb.unread());
    EXPECT_EQ(tb.latest(), 2);
    EXPECT_FALSE(tb.unread());
    EXPECT_EQ(tb.latest(), 2);  // reading again changes nothing
    EXPECT_FALSE(tb.unread());
    tb.back() = 3;
    tb.publish();
    EXPECT_TRUE(tb.unread());
}

TriMesh unit_cube() {
    TriMesh m;
    for (int i = 0; i < 8; ++i) m.positions.push_back(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
    // Two CCW-from-outside triangles per face.
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}

TEST(TriMesh, CubeIsClosedWithUnitVolume) {
    const TriMesh cube = unit_cube();
    const EdgeStats s = edge_stats(cube);
    EXPECT_EQ(s.edges, 18u);
    EXPECT_EQ(s.boundary_edges, 0u);
    EXPECT_EQ(s.nonmanifold_edges, 0u);
    EXPECT_EQ(s.misoriented_edges, 0u);
    EXPECT_NEAR(signed_volume(cube), 1.0, 1e-12);
    const auto n = vertex_normals(cube);
    EXPECT_NEAR(glm::length(n[0]), 1.0, 1e-12);
    EXPECT_LT(n[0].x, 0.0);
}

TEST(TriMesh, OpenAndNonManifoldEdgesAreCounted) {
    TriMesh cube = unit_cube();
    cube.triangles.pop_back();
    EXPECT_EQ(edge_stats(cube).boundary_edges, 3u);
    TriMesh fan = unit_cube();
    fan.triangles.push_back({0, 2, 7});  // third triangle on edge 0-2
    EXPECT_GE(edge_stats(fan).nonmanifold_edges, 1u);
}


// ---- CRC-32 (core/crc32.hpp) ----

TEST(Crc32, KnownVectorsAndContinuation) {
    EXPECT_EQ(tridex::crc32_ieee("123456789", 9), 0xCBF43926u);
    EXPECT_EQ(tridex::crc32_ieee("6789", 4, tridex::crc32_ieee("12345", 5)), 0xCBF43926u);
    EXPECT_EQ(tridex::crc32_ieee("", 0), 0u);
    // The 4-byte fast path and the byte tail agree, whatever the split.
    std::string text(1000, '\0');
    for (std::size_t i = 0; i < text.size(); ++i) text[i] = static_cast<char>(i * 37 + 11);
    const std::uint32_t whole = tridex::crc32_ieee(text.data(), text.size());
    for (std::size_t split : {1u, 3u, 4u, 5u, 999u})
        EXPECT_EQ(tridex::crc32_ieee(text.data() + split, text.size() - split, tridex::crc32_ieee(text.data(), split)), whole);
    std::uint32_t bytewise = 0;
    for (char c : text) bytewise = tridex::crc32_ieee(&c, 1, bytewise);
    EXPECT_EQ(bytewise, whole);
}

// A waiter returns at once for a count it has not seen, at its deadline when nothing comes, and when another thread
// notifies.
TEST(ChangeSignal, WakesForACountNotSeenOrAtTheDeadline) {
    using Clock = tridex::ChangeSignal::Clock;
    tridex::ChangeSignal signal;
    EXPECT_EQ(signal.count(), 0u);
    const Clock::time_point t0 = Clock::now();
    EXPECT_FALSE(signal.wait_past(0, t0 + std::chrono::milliseconds(20)));
    EXPECT_GE(Clock::now() - t0, std::chrono::milliseconds(20));  // it waited out the deadline
    signal.notify();
    EXPECT_EQ(signal.count(), 1u);
    EXPECT_TRUE(signal.wait_past(0, Clock::now()));  // a count not seen: at once, even at a passed deadline
    EXPECT_FALSE(signal.wait_past(1, Clock::now()));
    std::thread other([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        signal.notify();
    });
    EXPECT_TRUE(signal.wait_past(1, Clock::now() + std::chrono::seconds(60)));
    other.join();
    EXPECT_EQ(signal.count(), 2u);
}

TEST(Pose, InverseAndCompositionUndoEachOtherAndPlacedBoxesHoldTheTurnedCorners) {
    const Pose a{Vec3(0.1, -0.2, 0.3), glm::angleAxis(0.7, glm::normalize(Vec3(1.0, 2.0, -0.5)))};
    const Pose b{Vec3(-0.05, 0.4, 0.0), glm::angleAxis(-1.3, Vec3(0.0, 0.0, 1.0))};
    const Vec3 p(0.02, -0.03, 0.05);
    EXPECT_NEAR(glm::length(a.inverse().apply(a.apply(p)) - p), 0.0, 1e-15);
    EXPECT_NEAR(glm::length((a * b).apply(p) - a.apply(b.apply(p))), 0.0, 1e-15);
    EXPECT_NEAR(glm::length((a * a.inverse()).apply(p) - p), 0.0, 1e-15);
    EXPECT_TRUE(Pose{}.is_identity());
    EXPECT_FALSE(a.is_identity());
    // A unit cube turned 45 degrees about z: its box widens to sqrt(2) in x and y, keeps z, and moves with the pose.
    const Aabb cube{Vec3(-0.5), Vec3(0.5)};
    const Aabb box = placed(cube, Pose{Vec3(1.0, 0.0, 0.0), glm::angleAxis(glm::radians(45.0), Vec3(0.0, 0.0, 1.0))});
    EXPECT_NEAR(box.size().x, std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(box.size().y, std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(box.size().z, 1.0, 1e-12);
    EXPECT_NEAR(box.centre().x, 1.0, 1e-12);
    EXPECT_TRUE(placed(Aabb{}, a).empty());
}
}  // namespace
}  // namespace tridex
