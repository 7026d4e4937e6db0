// Tests of the head pose providers: fixed, scripted (lerp + slerp), tracker slot with timeout, keyboard/mouse.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

#include "core/error.hpp"
#include "renderer/camera/head_pose.hpp"

namespace tridex::renderer {
namespace {

const double kPi = std::acos(-1.0);
constexpr double kTol = 1e-12;

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

/// The rotation angle (rad) between two unit quaternions.
double angle_between(const Quat& a, const Quat& b) { return 2.0 * std::acos(std::min(1.0, std::abs(glm::dot(a, b)))); }

Quat about_y(double rad) { return glm::angleAxis(rad, Vec3(0.0, 1.0, 0.0)); }

TEST(HeadPose, FixedHeadNeverMoves) {
    const Pose p{Vec3(0.1, 1.6, 2.0), about_y(0.3)};
    FixedHead h(p);
    for (double t : {0.0, 1.0, 1e6}) {
        EXPECT_EQ(h.head_at(t).position, p.position);
        EXPECT_EQ(h.head_at(t).orientation, p.orientation);
    }
    EXPECT_THROW(FixedHead(Pose{Vec3(std::nan(""), 0.0, 0.0)}), Error);
    EXPECT_THROW(FixedHead(Pose{Vec3(0.0), Quat(2.0, 0.0, 0.0, 0.0)}), Error);
}

TEST(HeadPose, ScriptedHeadInterpolatesPositionAndSlerpsOrientation) {
    ScriptedHead h({{1.0, Pose{Vec3(0.0, 1.5, 2.0), Quat(1.0, 0.0, 0.0, 0.0)}},
                    {3.0, Pose{Vec3(0.4, 1.5, 1.0), about_y(kPi / 2)}},
                    {4.0, Pose{Vec3(0.4, 1.7, 1.0), about_y(kPi / 2)}}});
    // Clamped before the first and after the last waypoint.
    expect_vec(h.head_at(0.0).position, Vec3(0.0, 1.5, 2.0), kTol);
    expect_vec(h.head_at(9.0).position, Vec3(0.4, 1.7, 1.0), kTol);
    // A quarter of the first segment: a quarter of the way, a quarter of the 90 degree turn.
    const Pose q = h.head_at(1.5);
    expect_vec(q.position, Vec3(0.1, 1.5, 1.75), kTol);
    EXPECT_NEAR(angle_between(q.orientation, about_y(kPi / 8)), 0.0, 1e-7);
    // Exactly at a waypoint.
    expect_vec(h.head_at(3.0).position, Vec3(0.4, 1.5, 1.0), kTol);
    expect_vec(h.head_at(3.5).position, Vec3(0.4, 1.6, 1.0), kTol);
}

TEST(HeadPose, ScriptedHeadTakesTheShortArcAndLoops) {
    // -q is the same rotation as q: slerp must not go the long way round (270 degrees).
    const Quat target = -about_y(kPi / 2);
    ScriptedHead h({{0.0, Pose{Vec3(0.0), Quat(1.0, 0.0, 0.0, 0.0)}}, {2.0, Pose{Vec3(1.0, 0.0, 0.0), target}}}, true);
    EXPECT_NEAR(angle_between(h.head_at(1.0).orientation, about_y(kPi / 4)), 0.0, 1e-7);
    // Period 2 s: t = 5.5 is t = 1.5 of the script; t = -0.5 is t = 1.5 too.
    expect_vec(h.head_at(5.5).position, Vec3(0.75, 0.0, 0.0), kTol);
    expect_vec(h.head_at(-0.5).position, Vec3(0.75, 0.0, 0.0), kTol);
}

TEST(HeadPose, ScriptedHeadRefusesBadScripts) {
    const Pose p{};
    EXPECT_THROW(ScriptedHead({}), Error);
    EXPECT_THROW(ScriptedHead({{0.0, p}}, true), Error);
    try {
        ScriptedHead({{0.0, p}, {1.0, p}, {1.0, p}});
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("waypoint 2"), std::string::npos) << e.what();
    }
    EXPECT_THROW(ScriptedHead({{0.0, p}, {std::numeric_limits<double>::infinity(), p}}), Error);
    EXPECT_THROW(ScriptedHead({{0.0, Pose{Vec3(0.0), Quat(0.5, 0.0, 0.0, 0.0)}}}), Error);
    EXPECT_NO_THROW(ScriptedHead({{0.0, p}}));
}

TEST(HeadPose, TrackerHeadFallsBackWhenStaleAndSaysSo) {
    const Pose fallback{Vec3(0.0, 0.0, 0.6)};
    TrackerHead h(fallback, 0.125);  // times below are exact binary fractions: ages compare exactly
    expect_vec(h.head_at(0.0).position, fallback.position, 0.0);
    EXPECT_FALSE(h.status().tracked);
    EXPECT_NE(h.status().note.find("no tracker sample"), std::string::npos);

    h.push(Pose{Vec3(0.05, 0.02, 0.55), about_y(0.1)}, 1.0);
    h.push(Pose{Vec3(0.06, 0.02, 0.55), Quat(2.0, 0.0, 0.0, 0.0)}, 1.25);  // newest; orientation normalised
    const Pose p = h.head_at(1.3125);
    expect_vec(p.position, Vec3(0.06, 0.02, 0.55), 0.0);
    EXPECT_NEAR(p.orientation.w, 1.0, kTol);
    EXPECT_TRUE(h.status().tracked);
    EXPECT_EQ(h.status().age_s, 0.0625);
    EXPECT_TRUE(h.head_at(1.375).position == Vec3(0.06, 0.02, 0.55));  // age exactly the timeout: still fresh
    EXPECT_TRUE(h.head_at(0.5).position == Vec3(0.06, 0.02, 0.55));    // sample "from the future": age 0
    EXPECT_EQ(h.status().age_s, 0.0);

    const Pose stale = h.head_at(1.5);
    expect_vec(stale.position, fallback.position, 0.0);
    EXPECT_FALSE(h.status().tracked);
    EXPECT_EQ(h.status().age_s, 0.25);
    EXPECT_EQ(h.status().fallbacks, 1u);
    EXPECT_NE(h.status().note.find("0.25 s old (timeout 0.125 s); using the fallback head pose"), std::string::npos)
        << h.status().note;
    h.head_at(1.75);
    EXPECT_EQ(h.status().fallbacks, 1u);  // counts switches, not frames

    h.push(Pose{Vec3(std::nan(""), 0.0, 0.0)}, 1.4);
    h.push(Pose{Vec3(0.0), Quat(0.0, 0.0, 0.0, 0.0)}, 1.4);
    EXPECT_EQ(h.rejected(), 2u);
    EXPECT_FALSE(h.head_at(1.4).position == Vec3(0.0));
    EXPECT_FALSE(h.status().tracked);
    expect_vec(h.head_at(std::nan("")).position, fallback.position, 0.0);
    EXPECT_THROW(TrackerHead(fallback, 0.0), Error);
}

TEST(HeadPose, TrackerHeadHandsOffWholeSamplesAcrossThreads) {
    TrackerHead h(Pose{Vec3(0.0, 0.0, 1.0)}, 1e9);
    std::atomic<bool> done{false};
    std::thread driver([&] {
        for (int i = 1; i <= 200000; ++i) {
            const double x = i * 1e-6;
            h.push(Pose{Vec3(x, 2.0 * x, 3.0 * x)}, x);
        }
        done = true;
    });
    double last_x = 0.0;
    int reads = 0;
    bool consistent = true, monotonic = true;
    while (!done || reads < 10) {
        const Pose p = h.head_at(1.0);
        if (h.status().tracked) {
            consistent = consistent && p.position.y == 2.0 * p.position.x && p.position.z == 3.0 * p.position.x;
            monotonic = monotonic && p.position.x >= last_x;
            last_x = p.position.x;
        }
        ++reads;
    }
    driver.join();
    EXPECT_TRUE(consistent);
    EXPECT_TRUE(monotonic);
    EXPECT_DOUBLE_EQ(h.head_at(1.0).position.x, 0.2);  // the newest sample after the driver stops
}

TEST(HeadPose, KeyboardMovesTheHeadAtItsSpeedInItsYawFrame) {
    KeyboardMouseHead h(Pose{Vec3(0.0, 0.0, 0.6)}, 0.3, 0.002);
    expect_vec(h.head_at(10.0).position, Vec3(0.0, 0.0, 0.6), 0.0);  // first call: no motion
    h.key(MoveKey::kForward, true);
    expect_vec(h.head_at(11.0).position, Vec3(0.0, 0.0, 0.3), kTol);  // 1 s forward (-z) at 0.3 m/s
    h.key(MoveKey::kRight, true);  // forward + right: along the diagonal, still 0.3 m/s
    const double d = 0.3 * 0.5 / std::sqrt(2.0);
    expect_vec(h.head_at(11.5).position, Vec3(d, 0.0, 0.3 - d), kTol);
    h.key(MoveKey::kForward, false);
    h.key(MoveKey::kRight, false);
    expect_vec(h.head_at(12.0).position, Vec3(d, 0.0, 0.3 - d), kTol);
    // Turn right by 90 degrees (yaw -pi/2): forward is now +x; up is world +y.
    h.mouse_turn((kPi / 2) / 0.002, 0.0);
    h.key(MoveKey::kForward, true);
    h.key(MoveKey::kUp, true);
    const double e = 0.3 * 0.25 / std::sqrt(2.0);
    expect_vec(h.head_at(12.25).position, Vec3(d + e, e, 0.3 - d), kTol);
    EXPECT_NEAR(angle_between(h.head_at(12.25).orientation, about_y(-kPi / 2)), 0.0, 1e-7);
    // Going back in time moves nothing.
    expect_vec(h.head_at(12.0).position, Vec3(d + e, e, 0.3 - d), kTol);
    h.reset();
    expect_vec(h.head_at(13.0).position, Vec3(0.0, 0.0, 0.6), 0.0);
}

TEST(HeadPose, MousePitchIsClampedAndLimitsHoldTheHead) {
    Aabb limits;
    limits.add(Vec3(-0.5, -0.3, 0.2));
    limits.add(Vec3(0.5, 0.3, 1.0));
    KeyboardMouseHead h(Pose{Vec3(0.0, 0.0, 0.6), about_y(0.4)}, 0.3, 0.01, limits);
    EXPECT_NEAR(angle_between(h.head_at(0.0).orientation, about_y(0.4)), 0.0, 1e-7);  // home yaw kept
    h.mouse_turn(0.0, -1000.0);  // 10 rad up: clamped to 89 degrees
    const Vec3 gaze = h.head_at(0.0).orientation * Vec3(0.0, 0.0, -1.0);
    EXPECT_NEAR(std::asin(gaze.y), 89.0 * kPi / 180.0, 1e-9);
    h.mouse_turn(std::nan(""), 1.0);  // ignored
    h.reset();
    h.key(MoveKey::kBack, true);  // backwards (+z rotated by 0.4 rad) for 10 s: stops at the box
    const Vec3 p = h.head_at(10.0).position;
    EXPECT_DOUBLE_EQ(p.z, 1.0);
    EXPECT_DOUBLE_EQ(p.x, 0.5);
    EXPECT_THROW(KeyboardMouseHead(Pose{Vec3(0.0, 0.0, 5.0)}, 0.3, 0.002, limits), Error);
    EXPECT_THROW(KeyboardMouseHead(Pose{}, 0.0), Error);
    EXPECT_THROW(KeyboardMouseHead(Pose{}, 0.3, -1.0), Error);
}

}  // namespace
}  // namespace tridex::renderer
