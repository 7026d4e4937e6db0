// Tests of devices/scripted_orientation and devices/rotation_vector: exact waypoints, slerp at constant
// angular velocity along the shortest arc, holding outside the time range, input checks naming the index,
// and the log/exp maps round-tripping.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "devices/rotation_vector.hpp"
#include "devices/scripted_orientation.hpp"

namespace tridex::devices {
namespace {

constexpr double kPi = 3.14159265358979323846;

Quat about(const Vec3& axis, double angle) { return glm::angleAxis(angle, glm::normalize(axis)); }

// Same rotation (q or -q).
void expect_same_rotation(const Quat& a, const Quat& b, double tol) {
    EXPECT_NEAR(std::abs(glm::dot(a, b)), 1.0, tol) << "a = (" << a.w << ", " << a.x << ", " << a.y << ", " << a.z
                                                    << ") b = (" << b.w << ", " << b.x << ", " << b.y << ", " << b.z << ")";
}

TEST(RotationVector, RoundTripsAndTakesTheShortArc) {
    for (const Vec3& v : {Vec3(0.3, -0.2, 0.1), Vec3(0.0, 0.0, 3.0), Vec3(1e-9, 0.0, 0.0), Vec3(-2.0, 1.0, 0.5)}) {
        const Vec3 r = rotation_vector(quat_from_rotation_vector(v));
        EXPECT_NEAR(glm::length(r - v), 0.0, 1e-12);
        EXPECT_NEAR(glm::length(rotation_vector(-quat_from_rotation_vector(v)) - v), 0.0, 1e-12);  // -q: same
    }
    // 1.5 pi about z is -0.5 pi about z the short way.
    EXPECT_NEAR(glm::length(rotation_vector(about(Vec3(0, 0, 1), 1.5 * kPi)) - Vec3(0.0, 0.0, -0.5 * kPi)), 0.0, 1e-12);
    EXPECT_EQ(rotation_vector(Quat(1.0, 0.0, 0.0, 0.0)), Vec3(0.0));
    EXPECT_EQ(quat_from_rotation_vector(Vec3(0.0)), Quat(1.0, 0.0, 0.0, 0.0));
    // It agrees with GLM's axis-angle.
    EXPECT_NEAR(glm::length(rotation_vector(about(Vec3(1, 2, 3), 0.7)) - 0.7 * glm::normalize(Vec3(1, 2, 3))), 0.0, 1e-12);
}

ScriptedOrientation turn() {
    return ScriptedOrientation({0.0, 1.0, 3.0},
                               {Quat(1.0, 0.0, 0.0, 0.0), about(Vec3(0, 0, 1), 0.6), about(Vec3(1, 0, 0), 0.4)});
}

TEST(ScriptedOrientation, PassesThroughEveryWaypointAndHoldsOutside) {
    const ScriptedOrientation p = turn();
    for (std::size_t i = 0; i < p.size(); ++i) expect_same_rotation(p.orientation_at(p.times()[i]), p.orientations()[i], 1e-14);
    expect_same_rotation(p.orientation_at(-1.0), Quat(1.0, 0.0, 0.0, 0.0), 0.0);
    expect_same_rotation(p.orientation_at(std::numeric_limits<double>::quiet_NaN()), Quat(1.0, 0.0, 0.0, 0.0), 0.0);
    expect_same_rotation(p.orientation_at(10.0), about(Vec3(1, 0, 0), 0.4), 1e-15);
    EXPECT_EQ(p.angular_velocity_at(-1.0), Vec3(0.0));
    EXPECT_EQ(p.angular_velocity_at(10.0), Vec3(0.0));
}

TEST(ScriptedOrientation, SlerpsAtConstantAngularVelocity) {
    const ScriptedOrientation p = turn();
    // First segment: 0.6 rad about z in 1 s.
    expect_same_rotation(p.orientation_at(0.25), about(Vec3(0, 0, 1), 0.15), 1e-15);
    EXPECT_NEAR(glm::length(p.angular_velocity_at(0.5) - Vec3(0.0, 0.0, 0.6)), 0.0, 1e-12);
    // The angular velocity is the derivative of the orientation (device frame: dq/dt q^-1).
    for (double t : {0.3, 1.7, 2.5}) {
        const double e = 1e-6;
        const Vec3 w = rotation_vector(p.orientation_at(t + e) * glm::conjugate(p.orientation_at(t - e))) / (2.0 * e);
        EXPECT_NEAR(glm::length(w - p.angular_velocity_at(t)), 0.0, 1e-6) << t;
    }
}

TEST(ScriptedOrientation, TakesTheShortWayWhateverTheSign) {
    // -q for the second waypoint: still a 0.5 rad turn, not 2 pi - 0.5.
    const ScriptedOrientation p({0.0, 1.0}, {Quat(1.0, 0.0, 0.0, 0.0), -about(Vec3(0, 1, 0), 0.5)});
    EXPECT_NEAR(glm::length(p.angular_velocity_at(0.5) - Vec3(0.0, 0.5, 0.0)), 0.0, 1e-12);
}

void expect_error(std::vector<double> t, std::vector<Quat> q, const std::string& needle) {
    try {
        ScriptedOrientation p(std::move(t), std::move(q));
        FAIL() << "no error, expected " << needle;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

TEST(ScriptedOrientation, RejectsBadWaypoints) {
    const Quat id(1.0, 0.0, 0.0, 0.0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    expect_error({}, {}, "no waypoints");
    expect_error({0.0, 1.0}, {id}, "entries");
    expect_error({0.0, nan}, {id, id}, "t_s[1]");
    expect_error({0.0, 1.0, 1.0}, {id, id, id}, "t_s[2]");
    expect_error({0.0, 1.0}, {id, Quat(nan, 0.0, 0.0, 0.0)}, "orientations[1]");
    expect_error({0.0, 1.0}, {id, Quat(2.0, 0.0, 0.0, 0.0)}, "orientations[1]");
    EXPECT_NO_THROW(ScriptedOrientation::hold(about(Vec3(1, 1, 0), 0.3)));
}

}  // namespace
}  // namespace tridex::devices
