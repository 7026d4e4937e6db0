// compute/tools/clay_push.hpp - plastic push and pull: the tool dents the surface it presses (push) or draws the
// surface it touches out after it (pull), with Popescu's falloff within a radius of influence; the volume moved
// comes back as a rim around the dent (push) or is taken from a moat around the bump (pull).
#pragma once

#include <span>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/clay_field.hpp"
#include "compute/tools/clay_kernel.hpp"
#include "compute/tools/sweep.hpp"

namespace tridex::compute {

/// Smallest penetration (cells) a push stamp acts on; shallower contacts wait until the tool goes deeper.
inline constexpr float kClayMinStep = 0.25f;
/// How close (cells) the tool must be to the surface where a pull's motion starts for the surface to follow it.
inline constexpr float kClayPullGrip = 0.5f;
/// Largest surface displacement (cells) one pull stamp applies: a whole piece of motion (kClayPieceCells), so that a
/// fast hand does not outrun the surface and lose its grip.
inline constexpr float kClayPullMaxStep = 2.0f;
/// Largest surface displacement (cells) one push stamp applies; a deeper press is followed over several segments.
inline constexpr float kClayMaxStep = 1.0f;
/// Largest surface displacement (cells) one stamp of a group of n push sweeps applies (clay_push_group): n
/// kClayMaxStep, at most this, so that a spot the tool presses over several sweeps of a group sinks as far as it
/// would pushed sweep by sweep, while the field's offset stays well inside its search distance.
inline constexpr float kClayGroupMaxStep = 3.0f;

/// Spacing of a push group's contacts along the tool's path, as a multiple of the tool radius R: between two contacts
/// h apart the dent's envelope sags by at most delta * (h / 2r)^2 (r = kClayInfluence * R), well under a cell.
inline constexpr float kClayStampSpacing = 0.25f;

/// Spacing (cells) of a push group's contacts along the tool's path for a ball of radius R cells:
/// max(0.5, kClayStampSpacing * R).
float clay_stamp_spacing(float radius_cells);

/// Distance (cells) from grid point c to the nearest interval end of any ray of the three sets within `search` cells
/// (`search` when there is none): the distance to the sampled surface, exact at the samples, so at most a few
/// hundredths of a cell above the true distance for a tool a few cells away. O(rays within search x intervals).
float clay_surface_distance(const TriDexel& model, float cx, float cy, float cz, float search);

/// The contact of a ball of radius R (cells) centred at grid point c with the solid: phi(c) (cells from the
/// surface: inside, trilinear in the node field; outside, clay_surface_distance), the penetration delta = R - phi(c),
/// and the contact point
/// p* = c - max(phi(c), 0) * grad(phi)/|grad(phi)| (the surface point under the tool: Popescu's interaction point).
struct ClayContact {
    float phi = 0.0f;
    float delta = 0.0f;
    float point[3] = {0.0f, 0.0f, 0.0f};
    float normal[3] = {0.0f, 0.0f, 0.0f};  ///< grad(phi)/|grad(phi)| at the centre (outward); 0 when phi is flat there
};

/// How deep (cells, along -normal from the contact point) a node may lie and still be moved by a clay stamp that
/// displaces the surface by `delta` at distance `d` from the contact point: delta + 2 cells + d/2 (the near sheet of
/// a surface curving away with radius >= d). Deeper nodes belong to another sheet (the far side of a thin part) and
/// keep their value, so a push does not thin a plate from behind.
inline float clay_sheet_depth(float delta, float d) { return delta + 2.0f + 0.5f * d; }

/// The node box of clay sweeps: the union of their grid boxes lo..hi (GridSweep::lo, hi from to_clay_grid_sweep),
/// inside which their operation may change nodes. An empty span gives an empty box.
ClayBox clay_sweeps_box(std::span<const GridSweep> sweeps);

/// The contact of a ball (grid centre cx, cy, cz; radius r_cells) with `model`, from a 4 x 4 x 4 node field around
/// the centre.
ClayContact clay_contact(const TriDexel& model, float cx, float cy, float cz, float r_cells);

/// Plastic push of one clay sweep (to_clay_grid_sweep; the tool a ball of radius R = sweep.radius cells).
/// Interaction points: the ball at stamps f = (k+1)/stamps of the motion (k = 0..stamps-1, at most half a cell
/// apart), thinned to one per clay_stamp_spacing(R) of motion (the last always kept). For each stamp m in contact,
/// delta_m = min(R - phi(c_m), kClayMaxStep) (stamps with delta_m < kClayMinStep do nothing). Popescu, Burdea, Bouzit, "Virtual Reality Simulation Modeling for a Haptic Glove", section 3.3: a
/// surface point at distance d from the interaction point p*_m moves by delta_m * k with k = 1 - (d/r)^2 within the
/// radius of influence r = kClayInfluence * R, and where several interaction points act the largest displacement
/// wins: s_dent(q) = max_m delta_m * (1 - (d_m/r)^2). The displaced volume reappears as a rim on the annulus
/// r <= d_m <= r + w (w = kClayRimWidth * r): s_rim(q) = -beta * max_m delta_m * (4x(1-x))^2, x = (d_m - r)/w,
/// at points no dent moves, with beta solved so that the box's volume is unchanged (clay_resample). The surface
/// moves along its normal (phi' = phi + s, see clay_field.hpp for how the three sets stay one solid).
/// Nodes with |phi| >= |s| + 2 cells keep their value (the surface cannot reach them). The stamps, the field's box
/// and region and the beta solve run on the host; the field and the re-sampling on `kernel` (the CPU reference by
/// default; every kernel gives the same model bit for bit).
ClayStats clay_push(TriDexel& model, const GridSweep& sweep, std::vector<RayImage>* before = nullptr,
                    ClayKernel& kernel = clay_cpu_kernel());

/// Plastic push of several consecutive push sweeps of one ball as one operation: the interaction points along all
/// the sweeps' motion (their stamps in order, thinned to one per clay_stamp_spacing(R) of motion, the group's last
/// stamp always kept), their contacts all found against `model` as it is before the group, one displacement field
/// (the largest displacement over all of them wins, as over one sweep's stamps: Popescu 3.3's several interaction
/// points; a stamp moves the surface at most min(n kClayMaxStep, kClayGroupMaxStep) for n sweeps) and one rim with
/// one beta. The field's box is limited to the union of the sweeps' lo..hi. Costs about as
/// much as one clay_push over the group's extent, so a short group of short sweeps costs a fraction of pushing them
/// one by one. The result differs from pushing them one by one (each sweep's contacts there see the dents of the
/// ones before it), so a caller that must repeat a session groups the same sweeps the same way (apply_clay_batch).
/// Throws tridex::Error when the sweeps' radii differ; an empty span changes nothing.
ClayStats clay_push_group(TriDexel& model, std::span<const GridSweep> sweeps, std::vector<RayImage>* before = nullptr,
                          ClayKernel& kernel = clay_cpu_kernel());

/// Plastic pull of one clay sweep (ToolOp::kPull; the inverse of clay_push, as Freeform's tug or Blender's grab
/// along the normal): the touched surface follows the tool as it draws away. Only when the ball touches the surface
/// at the motion's start (R - phi(a) >= -kClayPullGrip), each stamp m (as clay_push) whose ball has drawn a gap
/// g_m = phi(c_m) - R >= kClayMinStep away from the surface moves the surface under it outward by
/// delta_m = min(g_m, kClayPullMaxStep) with the same falloff (Popescu 3.3: delta_m * (1 - (d_m/r)^2) within r =
/// kClayInfluence * R, the largest winning), so the surface catches up with the ball and never passes it; the added
/// volume is taken back from a moat on the annulus r..r + w (the rim's profile, inward), beta solved as in clay_push.
/// A tool held still, moving along the surface or pressing into it changes nothing; a tool that lost contact does
/// not grab again until it touches. Pushing a flat face in by D and pulling the same spot back out by D returns the
/// face to within about a cell. Runs on `kernel` as clay_push.
ClayStats clay_pull(TriDexel& model, const GridSweep& sweep, std::vector<RayImage>* before = nullptr,
                    ClayKernel& kernel = clay_cpu_kernel());

}  // namespace tridex::compute
