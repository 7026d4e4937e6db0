// haptics/menu_detent.cpp - the pie menu's detent force and slice index.
#include "haptics/menu_detent.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::haptics {

namespace {

constexpr int kMaxSlices = 32;
constexpr double kAxisTolerance = 1e-6;

// The first field of `m` that breaks check_menu_detent's rules (the stiffness cap aside) and why; nullptr when none.
const char* bad_field(const MenuDetent& m, const char** why) {
    const auto fail = [&](const char* field, const char* rule) {
        *why = rule;
        return field;
    };
    if (!is_finite(m.centre_m)) return fail("centre_m", "must be finite");
    if (!(is_finite(m.right) && std::abs(glm::length(m.right) - 1.0) <= kAxisTolerance))
        return fail("right", "must be a finite unit vector");
    if (!(is_finite(m.up) && std::abs(glm::length(m.up) - 1.0) <= kAxisTolerance))
        return fail("up", "must be a finite unit vector");
    if (!(std::abs(glm::dot(m.right, m.up)) <= kAxisTolerance)) return fail("up", "must be orthogonal to right");
    if (m.slices < 1 || m.slices > kMaxSlices) return fail("slices", "must be in 1..32");
    if (!(std::isfinite(m.dead_radius_m) && m.dead_radius_m > 0.0))
        return fail("dead_radius_m", "must be finite and > 0 m");
    if (!(std::isfinite(m.amplitude_n) && m.amplitude_n >= 0.0))
        return fail("amplitude_n", "must be finite and >= 0 N");
    return nullptr;
}

// The HIP's in-plane coordinates (x along right, y along up), m; false when the detent does not apply (closed,
// bad settings, non-finite HIP, or inside the dead radius).
bool in_ring(const MenuDetent& m, const Vec3& hip_m, double& x, double& y, double& rho) {
    const char* why = nullptr;
    if (!m.open || !is_finite(hip_m) || bad_field(m, &why) != nullptr) return false;
    const Vec3 d = hip_m - m.centre_m;
    x = glm::dot(d, m.right);
    y = glm::dot(d, m.up);
    rho = std::hypot(x, y);
    return std::isfinite(rho) && rho > m.dead_radius_m;
}

}  // namespace

void check_menu_detent(const MenuDetent& m, double max_stiffness_n_per_m) {
    if (!(max_stiffness_n_per_m > 0.0))
        throw Error("MenuDetent: max_stiffness_n_per_m = " + format_number(max_stiffness_n_per_m) + " must be > 0 N/m");
    const char* why = nullptr;
    if (const char* field = bad_field(m, &why)) throw Error(std::string("MenuDetent.") + field + " " + why);
    const double k = m.amplitude_n * m.slices / m.dead_radius_m;
    if (!(k <= max_stiffness_n_per_m))
        throw Error("MenuDetent.amplitude_n = " + format_number(m.amplitude_n) + " N: the detent's stiffness " +
                    "amplitude_n * slices / dead_radius_m = " + format_number(k) + " N/m exceeds the cap " +
                    format_number(max_stiffness_n_per_m) +
                    " N/m (lower amplitude_n or slices, or raise dead_radius_m)");
}

Vec3 menu_detent_force(const MenuDetent& m, const Vec3& hip_m) {
    double x = 0.0, y = 0.0, rho = 0.0;
    if (!in_ring(m, hip_m, x, y, rho)) return Vec3(0.0);
    const double fade = std::min(1.0, (rho - m.dead_radius_m) / m.dead_radius_m);
    const double theta = std::atan2(y, x);
    const double f_theta = -m.amplitude_n * fade * std::sin(m.slices * (theta - 0.5 * std::numbers::pi));
    const Vec3 e_theta = (-y * m.right + x * m.up) / rho;
    return f_theta * e_theta;
}

int menu_detent_slice(const MenuDetent& m, const Vec3& hip_m) {
    double x = 0.0, y = 0.0, rho = 0.0;
    if (!in_ring(m, hip_m, x, y, rho)) return -1;
    constexpr double kTwoPi = 2.0 * std::numbers::pi;
    double clockwise = 0.5 * std::numbers::pi - std::atan2(y, x);  // from 12 o'clock, clockwise, rad
    if (clockwise < 0.0) clockwise += kTwoPi;
    const double width = kTwoPi / m.slices;
    const int k = static_cast<int>(std::floor(clockwise / width + 0.5));
    return k % m.slices;
}

}  // namespace tridex::haptics
