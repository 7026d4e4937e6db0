// Tests of devices/scripted_path: exact waypoints, exact constant speed on uniform lines, C1 velocity,
// holding outside the time range, and input checks.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "devices/scripted_path.hpp"

namespace tridex::devices {
namespace {

constexpr double kTol = 1e-12;  // m or m/s: double rounding of a few operations on values ~0.1

void expect_near(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

ScriptedPath curve() {
    return ScriptedPath({0.0, 0.3, 0.5, 1.2, 1.5},
                        {Vec3(0.0), Vec3(0.05, 0.01, 0.0), Vec3(0.02, 0.04, -0.01), Vec3(-0.03, 0.0, 0.02),
                         Vec3(0.0, -0.02, 0.0)});
}

TEST(ScriptedPath, PassesThroughEveryWaypoint) {
    const ScriptedPath p = curve();
    for (std::size_t i = 0; i < p.size(); ++i) expect_near(p.position_at(p.times()[i]), p.positions()[i], kTol);
    EXPECT_DOUBLE_EQ(p.start_s(), 0.0);
    EXPECT_DOUBLE_EQ(p.end_s(), 1.5);
    EXPECT_DOUBLE_EQ(p.duration(), 1.5);
}

TEST(ScriptedPath, UniformLineHasConstantVelocityInside) {
    // Waypoints every 0.1 s along (1, 2, -2)/3 * 0.1 m/s: interior segments are exactly linear.
    std::vector<double> t;
    std::vector<Vec3> p;
    const Vec3 v = Vec3(1.0, 2.0, -2.0) / 3.0 * 0.1;
    for (int i = 0; i <= 10; ++i) {
        t.push_back(0.1 * i);
        p.push_back(Vec3(0.01, 0.0, 0.02) + v * (0.1 * i));
    }
    const ScriptedPath path(t, p);
    for (double s = 0.1; s <= 0.9; s += 0.0137) {
        expect_near(path.position_at(s), Vec3(0.01, 0.0, 0.02) + v * s, kTol);
        expect_near(path.velocity_at(s), v, kTol);
    }
    // Starts and ends at rest (zero end tangents): |v| grows like 6 * (dt / h) * |v_line| near the ends,
    // so 1e-9 s from either end it is below 1e-7 m/s.
    expect_near(path.velocity_at(1e-9), Vec3(0.0), 1e-7);
    expect_near(path.velocity_at(1.0 - 1e-9), Vec3(0.0), 1e-7);
}

TEST(ScriptedPath, VelocityIsTheDerivativeOfPosition) {
    const ScriptedPath p = curve();
    const double h = 1e-6;  // central difference error ~ h^2 * |x'''| ~ 1e-12 * 10 m/s^3
    for (double t = 0.01; t < 1.5; t += 0.0731) {
        const Vec3 fd = (p.position_at(t + h) - p.position_at(t - h)) / (2.0 * h);
        expect_near(p.velocity_at(t), fd, 1e-7);
    }
    // C1 at an interior waypoint: the velocity from both sides agrees.
    expect_near(p.velocity_at(0.5 - 1e-10), p.velocity_at(0.5 + 1e-10), 1e-7);
    // Catmull-Rom tangent at waypoint 2: (p3 - p1) / (t3 - t1).
    expect_near(p.velocity_at(0.5), (p.positions()[3] - p.positions()[1]) / 0.9, kTol);
}

TEST(ScriptedPath, HoldsOutsideItsTimeRange) {
    const ScriptedPath p = curve();
    expect_near(p.position_at(-1.0), p.positions().front(), 0.0);
    expect_near(p.position_at(7.0), p.positions().back(), 0.0);
    expect_near(p.velocity_at(-1.0), Vec3(0.0), 0.0);
    expect_near(p.velocity_at(7.0), Vec3(0.0), 0.0);
    expect_near(p.position_at(std::numeric_limits<double>::quiet_NaN()), p.positions().front(), 0.0);
    const ScriptedPath h = ScriptedPath::hold(Vec3(0.1, 0.2, 0.3));
    expect_near(h.position_at(0.5), Vec3(0.1, 0.2, 0.3), 0.0);
    expect_near(h.velocity_at(0.5), Vec3(0.0), 0.0);
    EXPECT_EQ(h.duration(), 0.0);
}

TEST(ScriptedPath, RejectsBadWaypoints) {
    EXPECT_THROW(ScriptedPath({}, {}), Error);
    EXPECT_THROW(ScriptedPath({0.0, 1.0}, {Vec3(0.0)}), Error);
    EXPECT_THROW(ScriptedPath({0.0, 1.0, 1.0}, {Vec3(0.0), Vec3(1.0), Vec3(2.0)}), Error);
    EXPECT_THROW(ScriptedPath({0.0, 1.0}, {Vec3(0.0), Vec3(std::nan(""))}), Error);
    EXPECT_THROW(ScriptedPath({0.0, std::numeric_limits<double>::infinity()}, {Vec3(0.0), Vec3(1.0)}), Error);
    try {
        ScriptedPath({0.0, 2.0, 1.0}, {Vec3(0.0), Vec3(1.0), Vec3(2.0)});
        FAIL() << "no throw";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("t_s[2]"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace tridex::devices
