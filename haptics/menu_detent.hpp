// haptics/menu_detent.hpp - the haptic side of an in-scene pie (marking) menu: a light detent that pulls the hand
// toward the centre of the slice it points at, so crossing a slice border is felt as a bump.
#pragma once

#include "core/math.hpp"

namespace tridex::haptics {

/// The open menu's geometry as the haptic loop feels it (world frame, SI units). Checked by check_menu_detent().
struct MenuDetent {
    bool open = false;              ///< false: no detent, carving as usual
    Vec3 centre_m{0.0};             ///< ring centre, world m (finite)
    Vec3 right{1.0, 0.0, 0.0};      ///< unit in-plane axis of the ring pointing to 3 o'clock, world
    Vec3 up{0.0, 1.0, 0.0};         ///< unit in-plane axis pointing to 12 o'clock, world (orthogonal to right)
    /// Number of slices, 1..32. Slice k is centred at the angle theta_k = 90 deg - k * 360 deg / slices, measured
    /// from `right` towards `up`: slice 0 at 12 o'clock, the following ones clockwise (seen with right to the right
    /// and up upwards).
    int slices = 8;
    double dead_radius_m = 0.015;   ///< no force (and no slice) this close to the centre in the plane, m (> 0)
    double amplitude_n = 0.3;       ///< peak tangential detent force, N (>= 0)
};

/// Checks every field of `m` (whether open or not): finite centre_m; right and up unit (within 1e-6) and orthogonal
/// (|right . up| <= 1e-6); slices in 1..32; dead_radius_m finite and > 0; amplitude_n finite and >= 0; and the
/// passivity bound amplitude_n * slices / dead_radius_m <= max_stiffness_n_per_m (N/m, > 0; +infinity for none),
/// see menu_detent_force(). Throws tridex::Error "MenuDetent.<field> ..." naming the first field at fault
/// (max_stiffness_n_per_m itself when it is NaN or <= 0).
void check_menu_detent(const MenuDetent& m, double max_stiffness_n_per_m);

/// The detent force on the HIP at hip_m (world m), world N. With d = hip - centre, x = d . right, y = d . up,
/// rho = sqrt(x^2 + y^2) and theta = atan2(y, x) (the component of d along the ring's normal is ignored):
///   F = -amplitude_n * g(rho) * sin(slices * (theta - theta_0)) * e_theta,
/// e_theta = (-y * right + x * up) / rho the unit direction of increasing theta, theta_0 = 90 deg, and the fade
/// g = 0 for rho <= dead_radius_m, (rho - dead) / dead up to 2 * dead, 1 beyond. The force is restoring: it points
/// toward the centre of the slice the HIP is in (stable equilibrium there, F = 0), is zero exactly at the slice
/// borders (unstable equilibrium), and peaks at amplitude_n * g midway between, so crossing a border is felt as
/// a bump. It never has a radial or normal component.
/// Passivity: near a slice centre the tangential stiffness is amplitude_n * slices / rho (N/m) at full amplitude;
/// over the fade the largest is amplitude_n * slices / (2 * dead_radius_m), at rho = 2 * dead. check_menu_detent
/// bounds the formula at rho = dead_radius_m, amplitude_n * slices / dead_radius_m, twice that (and no less than the
/// fade's radial slope amplitude_n / dead_radius_m).
/// Returns zero when the menu is closed, hip_m is not finite, or `m` fails check_menu_detent's field rules (the
/// stiffness cap is the caller's). Allocation-free, never throws (the haptic thread calls it).
Vec3 menu_detent_force(const MenuDetent& m, const Vec3& hip_m);

/// The slice (0..slices-1) whose angular range [theta_k - 180 deg / slices, theta_k + 180 deg / slices] holds the
/// HIP's direction in the ring's plane (see menu_detent_force; a point exactly on a border belongs to the slice
/// clockwise of it). Returns -1 when the menu is closed, hip_m is not finite, m fails check_menu_detent's field
/// rules, or rho <= dead_radius_m. Allocation-free, never throws.
int menu_detent_slice(const MenuDetent& m, const Vec3& hip_m);

}  // namespace tridex::haptics
