// haptics/snapshot_depth.hpp - what an ActiveSurface snapshot says about a point: how deep inside material it
// lies, whether it is clearly out, and how far it is to the surface along an axis.
#pragma once

#include "core/active_surface.hpp"
#include "core/math.hpp"

namespace tridex::haptics::contact {

/// Guard margin, window ray spacings: inside_material() calls a point inside when a reading says it is deeper than
/// this. Points on an active triangle of a smooth surface read a few hundredths of a spacing deep (chord sag);
/// triangles spanning a concave edge reach half a spacing, so a quarter lets the proxy ride the triangles while
/// stopping it before it sinks into material.
inline constexpr double kGuardMarginCells = 0.25;
/// Free margin, window ray spacings: clearly_outside() needs every ray around a point to have it more than this
/// far outside material. A spacing keeps the chord sag and the guard margin of a surface the tool still touches
/// well inside it.
inline constexpr double kFreeMarginCells = 1.0;
/// The value of a depth reading when nothing is known (no window covers the point), window ray spacings.
inline constexpr double kEmpty = 1e9;

/// True when window `w` is usable: at least 2 x 2 rays, at most kWindow per side, stride >= 1.
bool window_ok(const ActiveSurface::Window& w);

/// Largest window ray spacing over the usable windows of `s`, m: the lateral resolution of the snapshot.
double spacing_m(const ActiveSurface& s);

/// Signed distance (grid units) along window ray (iu, iv) of `w` from depth d (grid units) to the nearest interval
/// end: positive inside an interval, negative outside; -kEmpty for an empty ray.
double ray_signed_depth(const ActiveSurface::Window& w, int iu, int iv, double d);

/// Two readings of how deep point p (world m) lies inside material, in window ray spacings (grid units / the
/// window's stride: the snapshot's lateral resolution), from the four rays around p's projection in each ray set:
/// - vouched: a set vouches for the smallest of its four depths (all four rays hold p that far inside); the
///   largest depth any set vouches for. For a face square to a set it is the distance to the face; near edges
///   and on faces at 45 degrees to every set it reads shallow by up to about a spacing, so it never calls a
///   point of a face "inside".
/// - blended: the bilinear blend of the four depths, from each set whose four rays are non-empty and agree
///   within two spacings (one surface sheet; exact for a plane: the distance along the set's axis); the
///   shallowest over those sets. Accurate on smooth faces at any angle; silent near edges.
/// Both are -kEmpty when nothing is known (no window covers p, or no set qualifies).
struct DepthReading {
    double vouched = -kEmpty;  ///< see above, window ray spacings
    double blended = -kEmpty;  ///< see above, window ray spacings
};

/// The DepthReading of world point p_m (m) in snapshot `s`.
DepthReading read_depth(const ActiveSurface& s, const Vec3& p_m);

/// The guard's test: true when either reading of p_m (m) is deeper than kGuardMarginCells.
bool inside_material(const ActiveSurface& s, const Vec3& p_m);

/// True when either reading of p_m (m) holds it inside material at all (> 0, no guard margin): a point just past a
/// face counts.
bool touches_material(const ActiveSurface& s, const Vec3& p_m);

/// True when every usable ray set's window covers p_m (m), its projection lying over the window's rays, and at
/// least one set is usable: p_m lies inside the box the windows share (a set bounds only its two lateral axes).
bool covers(const ActiveSurface& s, const Vec3& p_m);

/// True when p_m (m) is clearly out of material: at least one ray set's window covers it, and in every set that
/// does, each of the four rays around its projection has it more than kFreeMarginCells window spacings outside.
/// False when no window covers p_m (nothing is known there).
bool clearly_outside(const ActiveSurface& s, const Vec3& p_m);

/// True when a tool at `at_m` (m) is clearly out of material (clearly_outside): its centre and, for a ball of
/// radius radius_m > 0 (m), its six points at +-radius along the axes.
bool tool_clearly_free(const ActiveSurface& s, const Vec3& at_m, double radius_m);

/// True when the tool placed at `at_m` (m) has none of the guard's points inside material: its centre and, for a
/// ball of radius radius_m (m), its contact point at_m - offset_m (when with_contact) and its six points at
/// +-radius along the axes.
bool pose_free(const ActiveSurface& s, const Vec3& at_m, double radius_m, const Vec3& offset_m, bool with_contact);

/// True when a ball of radius radius_m (m, >= 0) at `at_m` (m) is free by the snapshot's rays, exactly: its centre
/// is not inside material (inside_material) and no ray of any window within the radius holds material on the ball's
/// chord, the ball taken a quarter window spacing short (the guard's margin: a ball touching a face is free). Between rays a
/// feature narrower than a spacing is not seen. False when no window is usable. Reads every ray under the ball (about
/// (2 r / spacing)^2 per set): for rare ticks, not every tick.
bool ball_free(const ActiveSurface& s, const Vec3& at_m, double radius_m);

/// A free ball centre (ball_free) near the HIP hip_m (m) for a ball of radius radius_m (m, > 0), reachable from the
/// proxy from_m (m) by a straight path that keeps the centre out of material (touches_material, every quarter spacing;
/// so a proxy stays on the side of a thin wall it entered from): the HIP itself, else the nearest of the points at a
/// quarter, half, three quarters and one radius from it along 26 directions (the axes, the face and the corner
/// diagonals), ties going to the direction nearest from_m. When none of the 26 points one radius out is free and
/// `lattice` is set, the nearest free point of free_centre_on_lattice is taken instead (free spots in a concave
/// corner are often smaller than the gaps between the 26 directions). Returns false (out_m untouched) when nothing
/// is found, or on a radius that is not > 0 or a non-finite from_m. At most 105 ball tests when the 26 directions
/// find a free point, up to kLatticeCandidates more when they do not: for rare ticks, not every tick.
bool free_centre_within_radius(const ActiveSurface& s, const Vec3& hip_m, double radius_m, const Vec3& from_m,
                               Vec3& out_m, bool lattice = true);

/// Steps of the lattice searched by free_centre_on_lattice along one radius.
inline constexpr int kLatticeSteps = 6;
/// Points of that lattice within one radius of its centre, the centre excluded.
inline constexpr int kLatticeCandidates = 924;

/// The nearest free ball centre (ball_free, reachable from from_m as in free_centre_within_radius) among the points
/// of a cubic lattice of spacing radius_m / kLatticeSteps around hip_m (m) that lie within one radius of it, tried
/// shell by shell (equal distance), ties going to the point nearest the direction of from_m. Returns false (out_m
/// untouched) when none is free, or on a radius that is not > 0 or non-finite input. Up to kLatticeCandidates ball
/// tests: for rare ticks only.
bool free_centre_on_lattice(const ActiveSurface& s, const Vec3& hip_m, double radius_m, const Vec3& from_m,
                            Vec3& out_m);

/// How far (m) point p_m must move along axis `axis` (0..2) in direction `sign` (+1 or -1) to leave the material
/// the rays of that set around it hold it in: the largest such distance over the four rays around its projection
/// (0 for a ray that does not hold it). Negative when the set's window does not cover p_m.
double exit_distance_m(const ActiveSurface& s, const Vec3& p_m, int axis, int sign);

}  // namespace tridex::haptics::contact
