// haptics/local_surface.hpp - the surface near the HIP as a quadratic height field fitted to the dexel ends of one
// ray set, and the point of it nearest the HIP: the contact's normal and depth on curved surfaces to the accuracy a
// flat triangle cannot give.
#pragma once

#include "core/active_surface.hpp"
#include "core/math.hpp"

namespace tridex::haptics::contact {

/// The point of the local surface nearest a point, and the surface's outward unit normal there (world m).
struct SurfacePoint {
    Vec3 point_m{0.0};  ///< the foot point on the fitted surface, m
    Vec3 normal{0.0};   ///< outward unit normal at it
};

/// Fits a cubic height field h(u, v) (a quadratic when only 10 to 12 rays qualify; least squares; u, v across the
/// plane (q0_m, n), h along n) to the interval ends of the 4 x 4 window rays around centre_m's projection that continue the
/// plane (q0_m, n) (m; n outward unit) on the rays of set `a`: on each ray the end of the same kind (exit when `exits`, else entry) within
/// a window spacing of the plane. Then finds the fitted surface's point nearest p_m (a few projections onto the
/// tangent plane) and its normal, oriented like n. When that point lies more than 1.5 spacings from centre_m's
/// projection, it is stored in `out` all the same and false is returned (fit again around it). Returns false,
/// leaving `out` alone, when fewer than 10 rays
/// qualify, the plane is steeper than 72 degrees to the rays, a fitted end misses the fit by more than a tenth of
/// a spacing (an edge or another sheet in the patch); the caller then keeps the plane. Allocation-free.
bool nearest_on_local_surface(const ActiveSurface& s, int a, const Vec3& p_m, const Vec3& centre_m, const Vec3& q0_m,
                              const Vec3& n, bool exits, SurfacePoint& out);

}  // namespace tridex::haptics::contact
