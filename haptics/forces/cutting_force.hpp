// haptics/forces/cutting_force.hpp - reaction force of a ball tool removing material (specific cutting force).
#pragma once

#include "core/math.hpp"

namespace tridex::haptics {

/// Engaged chip cross-section A (m^2) of a ball tool of radius r (m) cutting at depth d (m) below the
/// surface, across the feed direction: the circular segment of the ball's great circle below the
/// surface, A = r^2*acos((r - d)/r) - (r - d)*sqrt(2*r*d - d^2). Returns 0 for d <= 0 or r <= 0 and
/// pi*r^2 for d >= 2r (the whole ball engaged). NaN inputs give 0.
double chip_area_m2(double radius_m, double depth_m);

/// Cutting reaction of the specific-cutting-force model of machining mechanics, F_c = k_c * A
/// (Altintas, "Manufacturing Automation", 2nd ed., ch. 2: the cutting force is the specific cutting
/// pressure times the uncut chip area), for a ball tool of radius r (m) engaged at depth d (m) with
/// velocity v (m/s) against a surface of outward unit normal n:
///   F = -k_c * A(r, d) * min(1, |v| / v_fade) * v/|v|,
/// i.e. directed against the tool's motion and faded in linearly with speed up to v_fade (m/s), so
/// that a tool at rest (or jittering by sensor noise) feels no chatter. No force when the tool moves
/// out of the material (v.n > 0), is at rest, or is not engaged (d <= 0, r <= 0). k_c in N/m^2 (finite
/// >= 0), v_fade > 0. Returns zero on any non-finite input.
Vec3 cutting_force(double k_c_n_per_m2, double radius_m, double depth_m, const Vec3& velocity_m_s,
                   const Vec3& normal, double fade_speed_m_s);

}  // namespace tridex::haptics
