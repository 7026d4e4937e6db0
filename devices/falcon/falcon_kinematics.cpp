// devices/falcon/falcon_kinematics.cpp - closed-form inverse kinematics, Jacobian, Newton forward kinematics.
#include "devices/falcon/falcon_kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tridex::devices::falcon {

namespace {

// The 3x3 matrix whose columns are the Jacobian rows: G^T.
glm::dmat3 transposed(const JointJacobian& g) { return glm::dmat3(g[0], g[1], g[2]); }

}  // namespace

std::int16_t FalconKinematics::theta_to_encoder(double theta_rad) const {
    const double c = std::round((theta_rad - g_.theta_offset_rad) / g_.rad_per_count);
    return static_cast<std::int16_t>(std::clamp(c, -32768.0, 32767.0));
}

std::optional<FalconAngles> FalconKinematics::inverse(const Vec3& p) const {
    if (!is_finite(p)) return std::nullopt;
    FalconAngles out;
    for (int i = 0; i < 3; ++i) {
        const double cp = std::cos(g_.phi[i]), sp = std::sin(g_.phi[i]);
        const double u = cp * p.x + sp * p.y - g_.r;
        const double v = -sp * p.x + cp * p.y - g_.s;
        const double w = p.z;
        // v = b cos(theta3) - f; the Falcon's legs use the solution in (0, pi).
        const double c3 = (v + g_.f) / g_.b;
        if (!(std::abs(c3) < 1.0)) return std::nullopt;
        const double theta3 = std::acos(c3);
        const double L = g_.d + g_.e + g_.b * std::sin(theta3);
        // (u + c - a cos t1)^2 + (w - a sin t1)^2 = L^2: with t = tan(theta1 / 2), q2 t^2 + q1 t + q0 = 0.
        const double uc = u + g_.c;
        const double k = uc * uc + g_.a * g_.a + w * w - L * L;
        const double q0 = k - 2.0 * g_.a * uc, q1 = -4.0 * g_.a * w, q2 = k + 2.0 * g_.a * uc;
        const double disc = q1 * q1 - 4.0 * q0 * q2;
        if (!(disc >= 0.0) || q2 == 0.0) return std::nullopt;
        const double t = (-q1 - std::sqrt(disc)) / (2.0 * q2);  // the knee-out branch of the Falcon
        const double theta1 = 2.0 * std::atan(t);
        const double theta2 = std::atan2(w - g_.a * std::sin(theta1), uc - g_.a * std::cos(theta1));
        out[i] = LegAngles{theta1, theta2, theta3};
    }
    return out;
}

JointJacobian FalconKinematics::jacobian(const FalconAngles& angles) const {
    JointJacobian g;
    for (int i = 0; i < 3; ++i) {
        const LegAngles& q = angles[i];
        const double den = g_.a * std::sin(q.theta3) * std::sin(q.theta2 - q.theta1);
        // d theta1 / d(u, v, w), then (u, v, w) = R(phi) p + const: d(u, v)/d(x, y) = [[c, s], [-s, c]].
        const double du = std::cos(q.theta2) * std::sin(q.theta3) / den;
        const double dv = std::cos(q.theta3) / den;
        const double dw = std::sin(q.theta2) * std::sin(q.theta3) / den;
        const double cp = std::cos(g_.phi[i]), sp = std::sin(g_.phi[i]);
        g[i] = Vec3(cp * du - sp * dv, sp * du + cp * dv, dw);
    }
    return g;
}

FalconKinematics::Forward FalconKinematics::forward(const Vec3& theta1, const Vec3& guess, double tol_rad,
                                                    int max_iterations) const {
    Forward r;
    Vec3 p = guess;
    auto residual = [&](const Vec3& at, Vec3& res, FalconAngles& a) {
        const std::optional<FalconAngles> ik = inverse(at);
        if (!ik) return false;
        a = *ik;
        res = Vec3(a[0].theta1, a[1].theta1, a[2].theta1) - theta1;
        return true;
    };
    Vec3 res;
    FalconAngles a;
    if (!residual(p, res, a)) {
        p = home_m();
        if (!residual(p, res, a)) return r;
    }
    double err = std::max({std::abs(res.x), std::abs(res.y), std::abs(res.z)});
    for (r.iterations = 0; r.iterations < max_iterations && err > tol_rad; ++r.iterations) {
        // G dp = -res  <=>  dp = -(G^T)^-T res; G^T has the rows as columns.
        const glm::dmat3 gt = transposed(jacobian(a));
        if (std::abs(glm::determinant(gt)) < 1e-30) break;
        const Vec3 step = -(glm::transpose(glm::inverse(gt)) * res);
        // Damped: halve the step until the residual falls (or the point is reachable at all).
        double lambda = 1.0;
        bool moved = false;
        for (int h = 0; h < 20; ++h, lambda *= 0.5) {
            Vec3 res2;
            FalconAngles a2;
            const Vec3 p2 = p + lambda * step;
            if (!residual(p2, res2, a2)) continue;
            const double err2 = std::max({std::abs(res2.x), std::abs(res2.y), std::abs(res2.z)});
            if (err2 < err || h == 19) {
                p = p2, res = res2, a = a2, err = err2;
                moved = true;
                break;
            }
        }
        if (!moved) break;
    }
    r.position = p;
    r.residual_rad = err;
    r.converged = err <= tol_rad;
    return r;
}

std::optional<Vec3> FalconKinematics::force_to_torque(const Vec3& p, const Vec3& force_n) const {
    const std::optional<FalconAngles> a = inverse(p);
    if (!a) return std::nullopt;
    const glm::dmat3 gt = transposed(jacobian(*a));
    if (!(std::abs(glm::determinant(gt)) > 1e-30)) return std::nullopt;
    // tau = J^T F, J = G^-1: tau = G^-T F = (G^T)^-1 F.
    const Vec3 tau = glm::inverse(gt) * force_n;
    if (!is_finite(tau)) return std::nullopt;
    return tau;
}

std::optional<Vec3> FalconKinematics::torque_to_force(const Vec3& p, const Vec3& torque_nm) const {
    const std::optional<FalconAngles> a = inverse(p);
    if (!a) return std::nullopt;
    const Vec3 f = transposed(jacobian(*a)) * torque_nm;
    if (!is_finite(f)) return std::nullopt;
    return f;
}

std::array<std::int16_t, 3> torque_to_command(const Vec3& torque_nm, std::int16_t max_command, bool* clamped) {
    if (clamped) *clamped = false;
    if (!is_finite(torque_nm)) return {0, 0, 0};
    Vec3 c = -kCommandPerNm * torque_nm;
    const double largest = std::max({std::abs(c.x), std::abs(c.y), std::abs(c.z)});
    const double limit = std::max<double>(0.0, max_command);
    if (largest > limit) {
        c *= limit / largest;
        if (clamped) *clamped = true;
    }
    std::array<std::int16_t, 3> out{};
    for (int i = 0; i < 3; ++i) out[i] = static_cast<std::int16_t>(std::clamp(std::round(c[i]), -limit, limit));
    return out;
}

Vec3 command_to_torque(const std::array<std::int16_t, 3>& command) {
    return Vec3(command[0], command[1], command[2]) * (-1.0 / kCommandPerNm);
}

}  // namespace tridex::devices::falcon
