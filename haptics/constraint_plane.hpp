// haptics/constraint_plane.hpp - the god-object's constraint plane: the active triangle of three dexel points
// under the HIP, the search over the ray sets, and the search again from outside material when the proxy lags.
#pragma once

#include <cstdint>

#include "core/active_surface.hpp"
#include "core/math.hpp"

namespace tridex::haptics::contact {

/// Axes ordered by |dir| component, largest first, into `order`; `fallback` (0..2) first when dir is zero.
void axis_order(const Vec3& dir, int fallback, int order[3]);

/// The active triangle on one ray set: three dexel ends (window-local ray indices, depth in grid units, end
/// type, interval material), their world points (m), the outward unit normal and the HIP's barycentric
/// coordinates in the triangle's cover. Source: Peng et al., active triangle from three dexel points.
struct Triangle {
    int iu[3], iv[3];                ///< window-local rays of the three ends
    double depth[3];                 ///< depth of each end along the set's axis, grid units
    bool exit[3];                    ///< each end is an interval's exit (else its entry)
    std::uint8_t material[3];        ///< material id of each end's interval
    Vec3 q[3];                       ///< the three dexel points, world m
    Vec3 n;                          ///< outward unit normal of the constraint plane
    Vec3 on;                         ///< a point of the constraint plane, m: q[0], or the refined foot point
    double w[3];                     ///< barycentric weights of the HIP's projection
};

/// The active triangle of ray set `a` (0..2) under `hip` (m): the half of the window cell holding the HIP's
/// projection, on each of its rays the interval end nearest `reference` (m) along the ray, within the locality
/// reach (3 window spacings + 2 x the HIP-reference lateral distance + extra_reach_cells). False (t undefined)
/// when the window does not cover the HIP, a ray is empty, an end is out of reach, or the points are degenerate.
bool active_triangle(const ActiveSurface& s, int a, const Vec3& hip, const Vec3& reference, double extra_reach_cells,
                     Triangle& t);

/// What the god-object kept from its last update that the plane search reads (world m).
struct LastContact {
    bool in_contact;     ///< the last update was in contact
    Vec3 normal;         ///< its contact normal (unit, or zero)
    Vec3 contact_point;  ///< the last contact point, m
    int axis;            ///< ray set of the last contact
    bool has_plane;      ///< the last contact came from a plane (plane_q, plane_n, plane_axis)
    Vec3 plane_q;        ///< a point of that plane, m
    Vec3 plane_n;        ///< its outward unit normal
    int plane_axis;      ///< its ray set
};

/// The constraint plane of an update: found, its triangle, the HIP's depth behind it (m, > 0 when found), its ray
/// set; kept when it is last tick's plane (no triangle of its own).
struct PlaneSearch {
    Triangle tri{};       ///< the active triangle (all three points on the kept plane when kept)
    bool found = false;   ///< a plane holds the HIP back
    bool kept = false;    ///< it is last tick's plane
    double depth = 0.0;   ///< radius - signed distance of the HIP from the plane, m
    int axis = -1;        ///< its ray set, -1 when none
    bool feature = false; ///< a ball's tangent plane at a convex edge or corner (convex_contact.hpp): no face shading
};

/// How far (window spacings) the previous proxy may lie behind a candidate plane and still count as having been
/// outside it: absorbs the small changes between neighbouring active triangles of one curved surface.
inline constexpr double kCrossingToleranceCells = 0.25;

/// Steps 1-4 of GodObject (god_object.hpp), the triangle's plane refined to the tangent plane of the fitted local
/// surface at its point nearest the HIP (local_surface.hpp) where the fit holds: the first ray set, in order of alignment with the approach, whose
/// active triangle under the HIP (m) has the HIP behind it (depth > 0 for a ball of radius radius_m) while `proxy`
/// (m) was not behind it (within a quarter window spacing); while in contact and inside material, then the
/// triangle under the last contact point. For a ball (radius_m > 0) with no such plane, or with a triangle the local
/// surface does not fit or a plane that leaves material the ball touches unexplained, the tangent plane of a convex
/// edge or corner when the ball meets one (convex_contact.hpp). Failing all that, last tick's plane while the HIP is
/// still behind it.
PlaneSearch search_plane(const ActiveSurface& surface, const Vec3& hip, const Vec3& proxy, double radius_m,
                         const LastContact& last);

/// The search again for a proxy that lags the HIP in contact (a hand faster than the proxy's path over a curved
/// surface, a HIP moved to another face, material added or removed under a resting tool): search_plane from
/// references lifted out of material, first along the last contact normal `last_normal` (kept when its plane faces
/// the same way, so the far face of a thin wall is never taken), then along the six axis directions, each lifted
/// past the material the rays of that axis hold the HIP in. Of the planes found whose proposed proxy
/// (hip + depth * n) leaves the whole tool out of material, the one nearest the HIP (least depth). Zilles &
/// Salisbury's god-object rests on the surface point nearest the HIP; this finds it on the snapshot without the
/// proxy's history. When `only_free` is false an axis candidate must also face the same way as last_normal, so a
/// hand pressed into a thin wall or a tube's wall keeps the side it entered. A candidate holding the HIP deeper than
/// the radius plus the HIP's nearest way out of material along an axis (exit_distance_m; 0 outside) plus a window
/// spacing is refused: the surface nearest the HIP is no farther than that, so such a plane is a face beyond it (the
/// workpiece's far side). Not found when no candidate qualifies (the guard then keeps the proxy out of material).
PlaneSearch reacquire_plane(const ActiveSurface& surface, const Vec3& hip, double radius_m, const Vec3& last_normal,
                            int last_axis, bool only_free);

}  // namespace tridex::haptics::contact
