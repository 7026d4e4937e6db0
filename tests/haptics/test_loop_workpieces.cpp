// Several workpieces in one haptic loop: each is felt in its own model frame and the forces add; every tick's sample
// reaches every workpiece in its model frame, carving only the target (touched, else nearest, else chosen; held
// through a stroke); Place moves the target alone; a replay's schedule chooses; bad lists are refused by name.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "haptics/haptic_loop.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

constexpr double kH = 1e-3;  // lattice cell, m

HapticLoopConfig plane_config() { return test::plain_plane_config(); }

// One workpiece: the half-space z < 10.25 mm of its model frame (the box of its 32 x 32 cell window), placed by a
// pose, with its own surface, ring and tap.
struct PlanePiece {
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring{4096};
    SpscRing<SequencedSample> tap{4096};
    Pose pose{};
    explicit PlanePiece(const Pose& p) : pose(p) { test::publish(surface, *test::z_plane(kH, 10.25f)); }
    LoopWorkpiece channel() {
        return LoopWorkpiece{&surface, &ring, &tap, pose, Aabb{Vec3(0.0), Vec3(0.032, 0.032, 0.01025)}};
    }
    std::vector<ToolSample> drain() {
        std::vector<ToolSample> out;
        ToolSample s;
        while (ring.try_pop(s)) out.push_back(s);
        return out;
    }
};

// Two planes side by side: A at the origin, B 0.1 m along x and turned 90 degrees about z.
struct TwoPlanes {
    PlanePiece a{Pose{}};
    PlanePiece b{Pose{Vec3(0.1, 0.0, 0.0), glm::angleAxis(glm::radians(90.0), Vec3(0.0, 0.0, 1.0))}};
    std::vector<LoopWorkpiece> channels() { return {a.channel(), b.channel()}; }
};

// A point of B's model frame in the world.
Vec3 in_b(const TwoPlanes& w, const Vec3& model_m) { return w.b.pose.apply(model_m); }

TEST(LoopWorkpieces, EachIsFeltInItsFrameAndOnlyTheTouchedOneIsCarved) {
    TwoPlanes w;
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoop loop(dev, w.channels(), plane_config());
    ASSERT_EQ(loop.workpieces(), 2u);
    EXPECT_EQ(loop.latest_view().workpiece_count, 2);
    EXPECT_EQ(loop.latest_view().workpiece_poses[1].position, w.b.pose.position);  // before the first tick too
    // Above B, then 0.75 mm into it: the force is B's plane normal (its model +z, still +z in the world).
    dev.state.pose.position = in_b(w, Vec3(0.012, 0.012, 0.016));
    (void)loop.step(0.0);
    TickRecord r;
    for (int t = 1; t <= 10; ++t) {
        dev.state.pose.position = in_b(w, Vec3(0.012 + 2e-4 * t, 0.012, 0.0115));
        r = loop.step(t * 1e-3);
    }
    EXPECT_TRUE(r.contact);
    EXPECT_EQ(r.workpiece, 1);
    EXPECT_NEAR(glm::length(r.force_n), 700.0 * 0.75e-3, 0.05);
    EXPECT_GT(glm::dot(glm::normalize(r.force_n), Vec3(0.0, 0.0, 1.0)), 0.999);
    EXPECT_EQ(loop.latest_view().target_workpiece, 1);
    // B got carving samples in its model frame; A got the same ticks' samples in its frame, carving nothing.
    const std::vector<ToolSample> sa = w.a.drain(), sb = w.b.drain();
    ASSERT_EQ(sa.size(), sb.size());
    ASSERT_EQ(sa.size(), 11u);
    std::size_t carved = 0;
    for (std::size_t i = 0; i < sa.size(); ++i) {
        EXPECT_EQ(sa[i].op, ToolOp::kNone) << i;
        if (sb[i].op == ToolOp::kSubtract) ++carved;
        EXPECT_NEAR(glm::length(w.b.pose.apply(sb[i].position) - sa[i].position), 0.0, 1e-12) << i;
    }
    EXPECT_GE(carved, 10u);  // from the second tick on: the first one chose B as the nearest
    EXPECT_NEAR(sb.back().position.z, 0.0115, 1e-12);
    // Both taps numbered their samples from 0.
    SequencedSample q;
    ASSERT_TRUE(w.b.tap.try_pop(q));
    EXPECT_EQ(q.seq, 0u);
}

TEST(LoopWorkpieces, TheForcesOfTwoTouchedWorkpiecesAdd) {
    // Two copies of the same plane, both unposed: the tool in both feels twice the force of one.
    // Paint: no recent cuts taken from the carved one's snapshot.
    PlanePiece alone{Pose{}}, a{Pose{}}, b{Pose{}};
    HapticLoopConfig cfg = plane_config();
    cfg.op = ToolOp::kPaint;
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoop one(dev, alone.surface, alone.ring, cfg);
    test::PoseDevice dev2(devices::DeviceProfile::phantom_omni());
    HapticLoop two(dev2, {a.channel(), b.channel()}, cfg);
    // 0.25 mm deep: both forces within the Omni's 0.88 N continuous force.
    const Vec3 above(0.012, 0.012, 0.016), inside(0.012, 0.012, 0.012);
    dev.state.pose.position = dev2.state.pose.position = above;
    (void)one.step(0.0);
    (void)two.step(0.0);
    dev.state.pose.position = dev2.state.pose.position = inside;
    TickRecord r1, r2;
    for (int t = 1; t <= 5; ++t) {  // the safety stage lets the force rise over a few ticks
        r1 = one.step(t * 1e-3);
        r2 = two.step(t * 1e-3);
    }
    ASSERT_TRUE(r1.contact);
    EXPECT_NEAR(glm::length(r1.force_n), 700.0 * 0.25e-3, 1e-3);
    EXPECT_NEAR(glm::length(r2.force_n - 2.0 * r1.force_n), 0.0, 1e-12);
    EXPECT_EQ(r2.points_in_contact, 2 * r1.points_in_contact);
}

TEST(LoopWorkpiecesChoice, ChosenHeldThroughAStrokeAndScheduled) {
    TwoPlanes w;
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg = plane_config();
    cfg.op = ToolOp::kPaint;  // no cuts: A stays where the tool touches it
    cfg.engage_mask = 1u;
    HapticLoop loop(dev, w.channels(), cfg);
    EXPECT_FALSE(loop.choose_workpiece(2));
    EXPECT_FALSE(loop.choose_workpiece(-2));
    EXPECT_EQ(loop.chosen_workpiece(), -1);
    // Touching A (from above), engaged: A is carved. Choosing B meanwhile waits for the stroke's end.
    dev.state.pose.position = Vec3(0.012, 0.012, 0.016);
    TickRecord r = loop.step(0.0);
    dev.state.buttons = 1u;
    dev.state.pose.position = Vec3(0.012, 0.012, 0.0115);
    r = loop.step(1e-3);
    EXPECT_EQ(r.workpiece, 0);
    EXPECT_TRUE(r.contact);
    ASSERT_TRUE(loop.choose_workpiece(1));
    r = loop.step(2e-3);
    EXPECT_EQ(r.workpiece, 0) << "the target changed during a stroke";
    // Released: the chosen B is the target although the tool touches A.
    dev.state.buttons = 0u;
    r = loop.step(3e-3);
    r = loop.step(4e-3);
    EXPECT_EQ(r.workpiece, 1);
    EXPECT_TRUE(r.contact);  // A is still felt
    // Automatic again: the touched A.
    ASSERT_TRUE(loop.choose_workpiece(-1));
    r = loop.step(5e-3);
    EXPECT_EQ(r.workpiece, 0);
    // A replay's schedule chooses by device time, at once even within a stroke: B from the start, A from the third
    // tick on while the tool carves B.
    HapticLoopConfig replay = plane_config();
    ToolChange to_b, to_a;
    to_b.device_t_s = 0.0;
    to_b.workpiece = 1;
    to_a.device_t_s = 5e-3;  // PoseDevice: read n has t_s = n ms: the fifth step
    to_a.workpiece = 0;
    replay.tool_schedule = {to_b, to_a};
    TwoPlanes w2;
    test::PoseDevice dev2(devices::DeviceProfile::phantom_omni());
    HapticLoop replayed(dev2, w2.channels(), replay);
    dev2.state.pose.position = Vec3(0.012, 0.012, 0.016);
    (void)replayed.step(0.0);
    dev2.state.pose.position = Vec3(0.012, 0.012, 0.0115);  // touching A
    r = replayed.step(1e-3);
    EXPECT_TRUE(r.contact);
    EXPECT_EQ(r.workpiece, 1);
    EXPECT_EQ(replayed.chosen_workpiece(), 1);
    dev2.state.pose.position = in_b(w2, Vec3(0.012, 0.012, 0.016));
    (void)replayed.step(2e-3);
    dev2.state.pose.position = in_b(w2, Vec3(0.012, 0.012, 0.0115));  // carving B where it touches it
    r = replayed.step(3e-3);
    ASSERT_EQ(r.workpiece, 1);
    ASSERT_TRUE(r.contact);
    r = replayed.step(4e-3);
    EXPECT_EQ(r.workpiece, 0) << "the schedule's change waited for the stroke's end";
}

TEST(LoopWorkpiecesChoice, TheNearestBoxIsTheTargetWhenNoneIsTouched) {
    TwoPlanes w;
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoop loop(dev, w.channels(), plane_config());
    // The tool in the air, carving nothing there: nearer A's box (x <= 0.032) than B's (x >= 0.068), then B's.
    dev.state.pose.position = Vec3(0.045, 0.016, 0.05);
    TickRecord r = loop.step(0.0);
    EXPECT_EQ(r.workpiece, 0);
    EXPECT_FALSE(r.contact);
    dev.state.pose.position = Vec3(0.06, 0.016, 0.05);
    r = loop.step(1e-3);
    EXPECT_EQ(r.workpiece, 1);
}

TEST(LoopWorkpiecesPlace, PlaceMovesTheTargetAlone) {
    TwoPlanes w;
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg = plane_config();
    cfg.op = ToolOp::kPlace;
    cfg.engage_mask = 1u;
    HapticLoop loop(dev, w.channels(), cfg);
    // Grip B where the tool touches it, move 1 cm along y.
    const Vec3 grip = in_b(w, Vec3(0.012, 0.012, 0.0115));
    dev.state.pose.position = grip;
    (void)loop.step(0.0);
    (void)loop.step(1e-3);
    dev.state.buttons = 1u;
    TickRecord r;
    for (int t = 0; t <= 10; ++t) {
        dev.state.pose.position = grip + Vec3(0.0, 0.001 * t, 0.0);
        r = loop.step((2 + t) * 1e-3);
        EXPECT_EQ(r.workpiece, 1);
        EXPECT_EQ(glm::length(r.force_n), 0.0);
    }
    const LoopView& v = loop.latest_view();
    EXPECT_NEAR(glm::length(v.workpiece_poses[1].position - (w.b.pose.position + Vec3(0.0, 0.01, 0.0))), 0.0, 1e-12);
    EXPECT_EQ(v.workpiece_poses[0].position, Vec3(0.0));
    EXPECT_EQ(v.workpiece_pose.position, Vec3(0.0));  // the first workpiece's
}

// The loop's own thread with a sculpt-thread stand-in draining each workpiece's ring and another thread choosing:
// every tick reaches every workpiece (the same count each, none dropped), and the view follows the choice. Run under
// ThreadSanitizer in CI.
TEST(LoopWorkpiecesThreads, EveryTickReachesEveryWorkpieceWhileAnotherThreadChooses) {
    TwoPlanes w;
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    dev.state.pose.position = Vec3(0.05, 0.016, 0.05);  // in the air between them
    HapticLoop loop(dev, w.channels(), plane_config());
    std::atomic<bool> done{false};
    std::atomic<std::size_t> got_a{0}, got_b{0};
    std::thread drain([&] {
        ToolSample s;
        while (!done.load()) {
            while (w.a.ring.try_pop(s)) got_a.fetch_add(1);
            while (w.b.ring.try_pop(s)) got_b.fetch_add(1);
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        while (w.a.ring.try_pop(s)) got_a.fetch_add(1);
        while (w.b.ring.try_pop(s)) got_b.fetch_add(1);
    });
    loop.start();
    std::thread chooser([&] {
        for (int k = 0; k < 50; ++k) {
            (void)loop.choose_workpiece(k % 3 - 1);  // -1, 0, 1
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        (void)loop.choose_workpiece(1);
    });
    chooser.join();
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (loop.latest_view().target_workpiece != 1 && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    EXPECT_EQ(loop.latest_view().target_workpiece, 1);
    loop.stop();
    done.store(true);
    drain.join();
    const LoopStats st = loop.stats();
    EXPECT_GT(st.ticks, 40u);
    EXPECT_EQ(st.samples_dropped, 0u);
    EXPECT_EQ(got_a.load(), st.ticks);
    EXPECT_EQ(got_b.load(), st.ticks);
}

TEST(LoopWorkpiecesConfig, ListsThatCannotWorkAreRefusedByName) {
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    const auto refusal = [&](const std::vector<LoopWorkpiece>& list) {
        try {
            HapticLoop loop(dev, list, plane_config());
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(no refusal)");
    };
    EXPECT_NE(refusal({}).find("HapticLoop workpieces: 0; must be 1 to 8"), std::string::npos) << refusal({});
    PlanePiece a{Pose{}};
    std::vector<LoopWorkpiece> nine(9, a.channel());
    EXPECT_NE(refusal(nine).find("HapticLoop workpieces: 9"), std::string::npos);
    LoopWorkpiece no_ring = a.channel();
    no_ring.samples = nullptr;
    EXPECT_NE(refusal({a.channel(), no_ring}).find("workpieces[1]: no active surface or no sample ring"),
              std::string::npos);
    LoopWorkpiece bad = a.channel();
    bad.pose.orientation = Quat(2.0, 0.0, 0.0, 0.0);
    EXPECT_NE(refusal({bad}).find("HapticLoopConfig.workpieces[0].pose.orientation |q|"), std::string::npos)
        << refusal({bad});
}

}  // namespace
}  // namespace tridex::haptics
