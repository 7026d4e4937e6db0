// tests/devices/test_falcon_reference.cpp - the Falcon driver's kinematics against a reference computed here by
// other methods, from the published geometry typed in below (libnifalcon, include/falcon/core/FalconGeometry.h at
// commit f7c727a; r and s as corrected in 935a31e): each leg's motor angle by circle-circle intersection (not the
// driver's half-angle quadratic), the grip position by a Newton solve on those angles with a finite-difference
// Jacobian in long double, and the force a torque makes from that finite-difference Jacobian. Position within
// 0.1 mm and force direction within 1 degree over the whole workspace; the old constants are measured against it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "devices/device_profiles.hpp"
#include "devices/falcon/falcon_kinematics.hpp"

namespace tridex::devices::falcon {
namespace {

using LD = long double;
struct V3 {
    LD x = 0, y = 0, z = 0;
};

// libnifalcon FalconGeometry.h (f7c727a), metres.
constexpr LD kA = 0.060L, kB = 0.1025L, kC = 0.01443L, kD = 0.01125L, kE = 0.01125L, kF = -0.025L, kR = 0.0400L,
             kS = -0.02309L;
constexpr LD kPi = 3.141592653589793238462643383279502884L;
const std::array<LD, 3> kPhi = {kPi / 2 + kPi / 12, -kPi / 6 + kPi / 12, -5 * kPi / 6 + kPi / 12};

// Motor angle of leg i at grip position p: the knee lies on the circle of radius a about the leg's base in its
// (u, w) plane, and at distance L = d + e + b sin(theta3) from the point Q = (u + c, w); theta1 is the direction of
// Q minus the angle at the base of the triangle (base, knee, Q), the Falcon's branch (the knee out).
bool reference_theta1(const V3& p, int i, LD& theta1) {
    const LD u = std::cos(kPhi[i]) * p.x + std::sin(kPhi[i]) * p.y - kR;
    const LD v = -std::sin(kPhi[i]) * p.x + std::cos(kPhi[i]) * p.y - kS;
    const LD c3 = (v + kF) / kB;
    if (!(std::fabs(c3) < 1)) return false;
    const LD L = kD + kE + kB * std::sqrt(1 - c3 * c3);
    const LD qx = u + kC, qz = p.z;
    const LD dist = std::sqrt(qx * qx + qz * qz);
    const LD cos_beta = (kA * kA + dist * dist - L * L) / (2 * kA * dist);
    if (!(std::fabs(cos_beta) <= 1)) return false;
    theta1 = std::atan2(qz, qx) - std::acos(cos_beta);
    return true;
}

bool reference_angles(const V3& p, std::array<LD, 3>& t) {
    for (int i = 0; i < 3; ++i)
        if (!reference_theta1(p, i, t[i])) return false;
    return true;
}

// d theta1 / d p by central differences (rows = legs), rad/m.
bool reference_jacobian(const V3& p, std::array<std::array<LD, 3>, 3>& g) {
    const LD h = 1e-7L;
    for (int axis = 0; axis < 3; ++axis) {
        V3 lo = p, hi = p;
        LD* l = axis == 0 ? &lo.x : axis == 1 ? &lo.y : &lo.z;
        LD* hh = axis == 0 ? &hi.x : axis == 1 ? &hi.y : &hi.z;
        *l -= h;
        *hh += h;
        std::array<LD, 3> a{}, b{};
        if (!reference_angles(lo, a) || !reference_angles(hi, b)) return false;
        for (int leg = 0; leg < 3; ++leg) g[leg][axis] = (b[leg] - a[leg]) / (2 * h);
    }
    return true;
}

// Solves M x = y (3x3) by Cramer's rule; false when singular.
bool solve3(const std::array<std::array<LD, 3>, 3>& m, const std::array<LD, 3>& y, std::array<LD, 3>& x) {
    const auto det = [](const std::array<std::array<LD, 3>, 3>& a) {
        return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    };
    const LD d = det(m);
    if (std::fabs(d) < 1e-30L) return false;
    for (int c = 0; c < 3; ++c) {
        auto mc = m;
        for (int r = 0; r < 3; ++r) mc[r][c] = y[r];
        x[c] = det(mc) / d;
    }
    return true;
}

// The grip position whose motor angles are `want`: Newton on the reference angles from `p`, each step halved until
// the largest angle error falls (a full step from the rest pose can leave the legs' reach near the corners).
bool reference_forward(const std::array<LD, 3>& want, V3& p) {
    const auto error = [&](const V3& at, LD& err) {
        std::array<LD, 3> t{};
        if (!reference_angles(at, t)) return false;
        err = std::max({std::fabs(want[0] - t[0]), std::fabs(want[1] - t[1]), std::fabs(want[2] - t[2])});
        return true;
    };
    LD err = 0;
    if (!error(p, err)) return false;
    for (int it = 0; it < 100 && err > 1e-14L; ++it) {
        std::array<LD, 3> t{};
        std::array<std::array<LD, 3>, 3> g{};
        if (!reference_angles(p, t) || !reference_jacobian(p, g)) return false;
        std::array<LD, 3> dp{};
        if (!solve3(g, {want[0] - t[0], want[1] - t[1], want[2] - t[2]}, dp)) return false;
        bool moved = false;
        for (LD lambda = 1; lambda > 1e-6L && !moved; lambda /= 2) {
            const V3 q{p.x + lambda * dp[0], p.y + lambda * dp[1], p.z + lambda * dp[2]};
            LD e2 = 0;
            if (error(q, e2) && e2 < err) p = q, err = e2, moved = true;
        }
        if (!moved) return false;
    }
    return err <= 1e-14L;
}

V3 to_ld(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 to_d(const V3& v) { return Vec3(static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)); }

// The force a torque makes at p by the reference: F = G^T tau.
Vec3 reference_force(const std::array<std::array<LD, 3>, 3>& g, const Vec3& tau) {
    V3 f;
    for (int leg = 0; leg < 3; ++leg) {
        f.x += g[leg][0] * tau[leg];
        f.y += g[leg][1] * tau[leg];
        f.z += g[leg][2] * tau[leg];
    }
    return to_d(f);
}

double angle_deg(const Vec3& a, const Vec3& b) {
    return glm::degrees(std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)));
}

// Points on a 9^3 grid over the Falcon profile's workspace box.
template <class F>
void over_workspace(F&& f) {
    const Aabb box = novint_falcon().workspace_m;
    const int n = 8;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            for (int k = 0; k <= n; ++k) f(box.lo + (box.hi - box.lo) * Vec3(i, j, k) / double(n));
}

// The errors of one geometry against the reference over the workspace: positions from the reference motor angles,
// and force directions from the reference's torques for unit forces along x, y, z and a diagonal.
struct Errors {
    double max_position_m = 0, mean_position_m = 0, max_force_deg = 0, centre_force_deg = 0, max_angle_rad = 0;
    double max_render_deg = 0, centre_render_deg = 0;  // the driver renders F: what the reference device pushes
    int points = 0;
};

Errors measure(const FalconKinematics& k) {
    Errors e;
    double sum = 0;
    over_workspace([&](const Vec3& p) {
        std::array<LD, 3> t{};
        std::array<std::array<LD, 3>, 3> g{};
        ASSERT_TRUE(reference_angles(to_ld(p), t) && reference_jacobian(to_ld(p), g)) << p.x << " " << p.y << " " << p.z;
        const Vec3 theta(static_cast<double>(t[0]), static_cast<double>(t[1]), static_cast<double>(t[2]));
        if (const auto a = k.inverse(p))
            for (int i = 0; i < 3; ++i) e.max_angle_rad = std::max(e.max_angle_rad, std::abs((*a)[i].theta1 - theta[i]));
        const FalconKinematics::Forward fk = k.forward(theta, FalconKinematics::home_m());
        const double err = fk.converged ? glm::length(fk.position - p) : 1.0;
        e.max_position_m = std::max(e.max_position_m, err);
        sum += err;
        ++e.points;
        // The torque the reference needs for force F at p, then the force the driver says that torque makes where
        // it believes the grip is.
        for (const Vec3& f : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), glm::normalize(Vec3(1, -1, 1))}) {
            std::array<LD, 3> tau{};
            std::array<std::array<LD, 3>, 3> gt{};
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) gt[r][c] = g[c][r];
            ASSERT_TRUE(solve3(gt, {f.x, f.y, f.z}, tau));
            const Vec3 torque(static_cast<double>(tau[0]), static_cast<double>(tau[1]), static_cast<double>(tau[2]));
            ASSERT_LT(angle_deg(reference_force(g, torque), f), 1e-6);  // the reference agrees with itself
            const auto felt = k.torque_to_force(fk.converged ? fk.position : p, torque);
            const double deg = felt ? angle_deg(*felt, f) : 180.0;
            e.max_force_deg = std::max(e.max_force_deg, deg);
            // The other way, as the driver renders a force: its motor torques for F where it believes the grip is,
            // and the force those torques make on the reference device where the grip really is.
            const auto tau_driver = k.force_to_torque(fk.converged ? fk.position : p, f);
            const double render_deg = tau_driver ? angle_deg(reference_force(g, *tau_driver), f) : 180.0;
            e.max_render_deg = std::max(e.max_render_deg, render_deg);
            if (glm::length(p - novint_falcon().workspace_m.centre()) < 1e-9) {
                e.centre_force_deg = std::max(e.centre_force_deg, deg);
                e.centre_render_deg = std::max(e.centre_render_deg, render_deg);
            }
        }
    });
    e.mean_position_m = sum / std::max(1, e.points);
    return e;
}

TEST(FalconReference, TheDriverMatchesThePublishedGeometryOverTheWorkspace) {
    const Errors e = measure(FalconKinematics{});
    std::printf("falcon vs reference (libnifalcon f7c727a geometry, %d points): position max %.3g mm mean %.3g mm, "
                "force direction max %.3g deg (centre %.3g deg), rendered force max %.3g deg (centre %.3g deg), motor "
                "angle max %.3g rad\n",
                e.points, e.max_position_m * 1e3, e.mean_position_m * 1e3, e.max_force_deg, e.centre_force_deg,
                e.max_render_deg, e.centre_render_deg, e.max_angle_rad);
    EXPECT_LT(e.max_position_m, 1e-4);
    EXPECT_LT(e.max_force_deg, 1.0);
    EXPECT_LT(e.max_render_deg, 1.0);
    EXPECT_LT(e.max_angle_rad, 1e-9);
}

TEST(FalconReference, TheReferenceRoundTripsAndTheOldConstantsAreMeasurablyWrong) {
    // The reference's own forward solve recovers the grip from its angles.
    over_workspace([&](const Vec3& p) {
        std::array<LD, 3> t{};
        ASSERT_TRUE(reference_angles(to_ld(p), t));
        V3 q = to_ld(FalconKinematics::home_m());
        ASSERT_TRUE(reference_forward(t, q));
        EXPECT_LT(glm::length(to_d(q) - p), 1e-9);
    });
    // The superseded constants (libnifalcon before 935a31e and c = 0.014) put the grip and the force elsewhere.
    FalconGeometry old;
    old.c = 0.014;
    old.r = 0.037233758;
    old.s = -0.027330909;
    const Errors e = measure(FalconKinematics{old});
    std::printf("falcon old constants vs reference: position max %.3g mm mean %.3g mm, force direction max %.3g deg "
                "(centre %.3g deg), rendered force max %.3g deg (centre %.3g deg)\n",
                e.max_position_m * 1e3, e.mean_position_m * 1e3, e.max_force_deg, e.centre_force_deg, e.max_render_deg,
                e.centre_render_deg);
    EXPECT_GT(e.max_position_m, 1e-3);
    EXPECT_GT(e.max_force_deg, 1.0);
    EXPECT_GT(e.max_render_deg, 1.0);
}

}  // namespace
}  // namespace tridex::devices::falcon
