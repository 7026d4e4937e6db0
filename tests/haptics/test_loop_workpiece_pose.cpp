// A posed workpiece: the haptic loop meets its surface in the model frame, so a tool at P(x) against the posed
// surface feels P's turn of what a tool at x feels against the unposed one, and the samples the sculpt thread gets
// are the same model-frame samples.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "haptics/haptic_loop.hpp"
#include "loop_fixture.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

constexpr double kH = 1e-3;  // lattice cell, m

HapticLoopConfig plane_config() { return test::plain_plane_config(); }

struct LoopRun {
    std::vector<TickRecord> records;
    std::vector<ToolSample> samples;
};

// Ticks a loop whose tool is at model points `path` (each placed in the world by `pose`), against the half-space
// z < 10.25 mm of the model frame.
LoopRun run_path(const Pose& pose, const std::vector<Vec3>& path, const Quat& tool_turn) {
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *test::z_plane(kH, 10.25f));
    SpscRing<ToolSample> ring(4096);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg = plane_config();
    cfg.workpiece_pose = pose;
    HapticLoop loop(dev, surface, ring, cfg);
    LoopRun run;
    for (std::size_t t = 0; t < path.size(); ++t) {
        dev.state.pose.position = pose.apply(path[t]);  // scaling 1, no offset: the device frame is the world
        dev.state.pose.orientation = pose.orientation * tool_turn;
        run.records.push_back(loop.step(static_cast<double>(t) * 1e-3));
    }
    ToolSample s;
    while (ring.try_pop(s)) run.samples.push_back(s);
    return run;
}

TEST(LoopWorkpiecePose, APosedSurfaceFeelsTheTurnedForceAndSamplesStayInTheModelFrame) {
    // Above the plane, then 0.75 mm into it (the 2 mm ball's bottom at 9.5 mm), then sliding along it.
    std::vector<Vec3> path{Vec3(0.012, 0.012, 0.016)};
    for (int k = 0; k < 20; ++k) path.push_back(Vec3(0.012 + 2e-4 * k, 0.012, 0.0115));
    const Quat tool_turn = glm::angleAxis(0.3, glm::normalize(Vec3(1.0, 1.0, 0.0)));
    const LoopRun unposed = run_path(Pose{}, path, tool_turn);
    const Pose pose{Vec3(0.1, -0.2, 0.3), glm::angleAxis(glm::radians(90.0), Vec3(1.0, 0.0, 0.0)) *
                                              glm::angleAxis(glm::radians(30.0), Vec3(0.0, 0.0, 1.0))};
    const LoopRun posed = run_path(pose, path, tool_turn);
    ASSERT_EQ(unposed.records.size(), posed.records.size());
    ASSERT_TRUE(unposed.records.back().contact);
    EXPECT_NEAR(glm::length(unposed.records.back().force_n), 700.0 * 0.75e-3, 0.05);
    for (std::size_t t = 0; t < path.size(); ++t) {
        const TickRecord& a = unposed.records[t];
        const TickRecord& b = posed.records[t];
        EXPECT_EQ(a.contact, b.contact) << "tick " << t;
        // The world's force is the model's turned; the HIP and proxy are the model's placed.
        EXPECT_NEAR(glm::length(b.force_n - pose.rotate(a.force_n)), 0.0, 1e-9) << "tick " << t;
        EXPECT_NEAR(glm::length(b.hip_m - pose.apply(a.hip_m)), 0.0, 1e-12) << "tick " << t;
        EXPECT_NEAR(glm::length(b.proxy_m - pose.apply(a.proxy_m)), 0.0, 1e-12) << "tick " << t;
        EXPECT_NEAR(glm::length(b.points[0].proxy_m - pose.apply(a.points[0].proxy_m)), 0.0, 1e-12);
        EXPECT_EQ(a.points[0].collision_id, b.points[0].collision_id);  // the model's ray set, whatever the pose
    }
    // In the world the plane's normal is the model's +z turned: the force points that way.
    const Vec3 f = posed.records.back().force_n;
    EXPECT_GT(glm::dot(glm::normalize(f), pose.rotate(Vec3(0.0, 0.0, 1.0))), 0.999);
    // The sculpt thread gets the same samples: model-frame positions, surface points and orientations.
    ASSERT_EQ(unposed.samples.size(), posed.samples.size());
    ASSERT_GT(posed.samples.size(), 10u);
    for (std::size_t i = 0; i < posed.samples.size(); ++i) {
        const ToolSample& a = unposed.samples[i];
        const ToolSample& b = posed.samples[i];
        EXPECT_NEAR(glm::length(b.position - a.position), 0.0, 1e-12) << "sample " << i;
        EXPECT_NEAR(glm::length(b.surface_m - a.surface_m), 0.0, 1e-12) << "sample " << i;
        EXPECT_GT(std::abs(glm::dot(b.orientation, a.orientation)), 1.0 - 1e-12) << "sample " << i;
        EXPECT_EQ(a.op, b.op);
    }
}

TEST(LoopWorkpiecePose, PlaceMovesAndTurnsTheWorkpieceWithTheEngagedToolAndCarvesNothing) {
    TripleBuffer<ActiveSurface> surface;
    test::publish(surface, *test::z_plane(kH, 10.25f));
    SpscRing<ToolSample> ring(4096);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg = plane_config();
    cfg.op = ToolOp::kPlace;
    cfg.engage_mask = 1u;  // placing while button 0 is held
    const Pose start{Vec3(0.01, 0.0, 0.0), Quat(1.0, 0.0, 0.0, 0.0)};
    cfg.workpiece_pose = start;
    HapticLoop loop(dev, surface, ring, cfg);
    EXPECT_EQ(loop.latest_view().workpiece_pose.position, start.position);  // before the first tick too
    // The tool inside the plane (it would be felt), not engaged: nothing moves.
    const Pose grip{Vec3(0.022, 0.012, 0.0105), Quat(1.0, 0.0, 0.0, 0.0)};
    dev.state.pose.position = grip.position;
    TickRecord r = loop.step(0.0);
    r = loop.step(1e-3);
    EXPECT_EQ(loop.latest_view().workpiece_pose.position, start.position);
    // Engaged: the workpiece follows the tool's move and turn rigidly, and nothing is felt of it.
    dev.state.buttons = 1u;
    r = loop.step(2e-3);
    const Pose moved{grip.position + Vec3(0.005, -0.003, 0.002), glm::angleAxis(glm::radians(40.0), Vec3(0.0, 1.0, 0.0))};
    for (int t = 1; t <= 10; ++t) {
        dev.state.pose.position = glm::mix(grip.position, moved.position, t / 10.0);
        dev.state.pose.orientation = glm::slerp(grip.orientation, moved.orientation, t / 10.0);
        r = loop.step((2 + t) * 1e-3);
        EXPECT_EQ(glm::length(r.force_n), 0.0) << "tick " << t;
        EXPECT_FALSE(r.contact);
        EXPECT_EQ(r.op, ToolOp::kPlace);
    }
    const Pose expect = moved * grip.inverse() * start;
    const Pose now = loop.latest_view().workpiece_pose;
    EXPECT_NEAR(glm::length(now.position - expect.position), 0.0, 1e-12);
    EXPECT_GT(std::abs(glm::dot(now.orientation, expect.orientation)), 1.0 - 1e-12);
    // The grip held: the tool sits at the same point of the model as when it took hold.
    EXPECT_NEAR(glm::length(now.inverse().apply(r.hip_m) - start.inverse().apply(grip.position)), 0.0, 1e-12);
    // Released: the pose stays; the samples all carried no operation.
    dev.state.buttons = 0u;
    r = loop.step(13e-3);
    dev.state.pose.position += Vec3(0.01, 0.0, 0.0);
    r = loop.step(14e-3);
    EXPECT_NEAR(glm::length(loop.latest_view().workpiece_pose.position - expect.position), 0.0, 1e-12);
    ToolSample s;
    std::size_t samples = 0;
    while (ring.try_pop(s)) {
        ++samples;
        EXPECT_EQ(s.op, ToolOp::kNone);
    }
    EXPECT_GT(samples, 10u);
}

// A placement that ends is reported with its poses; setting the pose back (its undo) takes effect at the next valid
// tick the tool holds nothing, is kept with that tick's device time, and a second loop given it as a schedule takes
// it at the same tick.
TEST(LoopWorkpiecePose, APlacementEndsInTheViewAndASetPoseIsTakenKeptAndReplayed) {
    const Pose start{Vec3(0.01, 0.0, 0.0), Quat(1.0, 0.0, 0.0, 0.0)};
    const Pose grip{Vec3(0.022, 0.012, 0.0105), Quat(1.0, 0.0, 0.0, 0.0)};
    const auto run = [&](const std::vector<PoseChange>& schedule, bool set_live, std::vector<PoseChange>& taken,
                         std::vector<Pose>& poses) {
        TripleBuffer<ActiveSurface> surface;
        test::publish(surface, *test::z_plane(kH, 10.25f));
        SpscRing<ToolSample> ring(4096);
        test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
        HapticLoopConfig cfg = plane_config();
        cfg.op = ToolOp::kPlace;
        cfg.engage_mask = 1u;
        cfg.workpiece_pose = start;
        cfg.pose_schedule = schedule;
        HapticLoop loop(dev, surface, ring, cfg);
        dev.state.pose.position = grip.position;
        for (int t = 0; t < 30; ++t) {
            dev.state.buttons = t >= 2 && t < 12 ? 1u : 0u;  // held from tick 2, let go at tick 12
            if (t >= 2 && t < 12) dev.state.pose.position = grip.position + Vec3(0.001 * (t - 1), 0.0, 0.0);
            if (set_live && t == 8) {
                EXPECT_TRUE(loop.set_workpiece_pose(0, start));  // asked while held: waits
            }
            loop.step(t * 1e-3);
            poses.push_back(loop.latest_view().workpiece_pose);
        }
        const Placement& p = loop.latest_view().placement;  // the newest that ended: the one
        EXPECT_EQ(p.serial, 1u);
        EXPECT_EQ(p.before.position, start.position);
        EXPECT_GT(p.after.position.x - start.position.x, 0.005);
        EXPECT_GE(p.at_samples, 12u);  // the samples before the release's
        EXPECT_LE(p.at_samples, 13u);
        taken = loop.pose_changes();
        EXPECT_EQ(loop.pose_changes_taken(), taken.size());
        EXPECT_FALSE(loop.set_workpiece_pose(1, start));  // no second workpiece
        EXPECT_FALSE(loop.set_workpiece_pose(0, Pose{Vec3(0.0), Quat(2.0, 0.0, 0.0, 0.0)}));
        EXPECT_FALSE(loop.set_workpiece_pose(0, Pose{Vec3(std::nan(""), 0.0, 0.0), Quat(1.0, 0.0, 0.0, 0.0)}));
    };
    std::vector<PoseChange> live;
    std::vector<Pose> live_poses;
    run({}, true, live, live_poses);
    ASSERT_EQ(live.size(), 1u);
    // The tick that let go took it (device time = (tick + 1) ms).
    const auto at = static_cast<std::size_t>(std::lround(live[0].device_t_s * 1e3)) - 1;
    ASSERT_GE(at, 12u);
    ASSERT_LE(at, 13u);
    EXPECT_GT(live_poses[at - 1].position.x, start.position.x + 0.005);
    EXPECT_EQ(live_poses[at].position, start.position);  // back where it was gripped
    EXPECT_EQ(live[0].tick, at);
    std::vector<PoseChange> again;
    std::vector<Pose> again_poses;
    run(live, false, again, again_poses);
    ASSERT_EQ(again.size(), 1u);
    EXPECT_EQ(again[0].tick, live[0].tick);
    EXPECT_EQ(again[0].device_t_s, live[0].device_t_s);
    for (std::size_t t = 0; t < live_poses.size(); ++t) EXPECT_EQ(again_poses[t].position, live_poses[t].position) << t;
}

TEST(LoopWorkpiecePose, ANonFiniteOrNonUnitPoseIsRefusedByName) {
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring(64);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    for (const Pose& bad : {Pose{Vec3(std::nan(""), 0.0, 0.0), Quat(1.0, 0.0, 0.0, 0.0)},
                            Pose{Vec3(0.0), Quat(2.0, 0.0, 0.0, 0.0)}}) {
        HapticLoopConfig cfg = plane_config();
        cfg.workpiece_pose = bad;
        try {
            HapticLoop loop(dev, surface, ring, cfg);
            ADD_FAILURE() << "a bad pose was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("workpiece_pose"), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace tridex::haptics
