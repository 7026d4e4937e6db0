// compute/tools/clay_grab.hpp - grab (move): the material within a radius of influence of the grabbed point follows the
// tool, with a smooth falloff (Freeform's tug, Blender's grab), as a semi-Lagrangian advection of the clay field.
#pragma once

#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/clay_field.hpp"
#include "compute/tools/clay_kernel.hpp"
#include "compute/tools/sweep.hpp"

namespace tridex::compute {

/// Radius (cells) of a grab's flat core as a multiple of the tool radius R: every point within it of the grabbed
/// point moves by the whole motion (a small object there translates rigidly).
inline constexpr float kClayGrabCore = 2.0f;
/// Radius of influence r of a grab as a multiple of R (Popescu, Burdea, Bouzit, section 3.3): no point at or beyond it
/// from the grabbed point moves.
inline constexpr float kClayGrabInfluence = 4.0f;
/// How close (cells) the ball must be to material where a grab's motion starts for the material to follow it.
inline constexpr float kClayGrabGrip = 0.5f;
/// Longest motion (cells) one field step of a grab applies; a longer motion goes in equal steps, each re-reading the
/// model. A step of |v| keeps the map x -> x - u(x) one-to-one while |v| * max|w'| < 1, which also needs |v| < R/2.
inline constexpr float kClayGrabStepCells = 2.0f;

/// The falloff w(d) of a grab at distance d (cells) from the grabbed point, for core radius c and radius of
/// influence r (c < r): 1 for d <= c, (1 - t^2)^2 with t = (d - c) / (r - c) for c < d < r (zero slope at both
/// ends), 0 for d >= r. Popescu, Burdea, Bouzit, section 3.3 (a falloff within a radius of influence), with a flat
/// core. Float arithmetic in this order (the GPU kernel repeats it).
inline float clay_grab_falloff(float d, float c, float r) {
    if (!(d > c)) return 1.0f;
    if (!(d < r)) return 0.0f;
    const float t = (d - c) / (r - c);
    const float q = 1.0f - t * t;
    return q * q;
}

/// The volume change (cells^3) of a grab step's motion itself: the divergence of u = w v summed over the field's
/// movable nodes inside material, sum_x inside(x) * w'(d) * (v . (x - anchor)) / d, with inside(x) = clamp(0.5 -
/// phi(x), 0, 1) (first order in |v|: the stretching or squeezing between core and r; 0 for a body wholly in the
/// core or beyond r). field.phi must be built. In double, on the host.
double clay_grab_volume_change(const TriDexel& model, const ClayField& field, const ClayGrabParams& params);

/// Grab of one clay sweep (ToolOp::kGrab; to_clay_grid_sweep, the tool a ball of radius R = sweep.radius cells,
/// moving a -> b). Only when the ball touches material where its motion starts (R - phi(a) >= -kClayGrabGrip,
/// clay_contact) does it grip, at the contact point p (the surface point under the ball; the ball's centre when it
/// is inside material). The material then moves with u(x) = w(|x - p|) (b - a), w = clay_grab_falloff with core
/// kClayGrabCore * R and radius of influence kClayGrabInfluence * R: all sheets within r move (a whole small object
/// in the core translates by b - a). The motion goes in equal steps of at most min(kClayGrabStepCells, R / 2) cells,
/// the grabbed point moving with each; each step builds the field (kernel.grab_field) and re-samples all three ray
/// sets (kernel.resample) with beta solved so that the volume changes by the motion's own divergence
/// (clay_grab_volume_change; field.volume_target) and not by the re-sampling's rounding of a curved surface (which
/// alone would shrink a small sphere by a few percent per step): a rigid translation keeps the volume, a cap drawn
/// out of a larger body adds what the stretching between core and radius of influence adds. Where the moved material
/// meets other material: everything within r moves with the falloff and the map x -> x - u(x) is one-to-one, so
/// material ahead of the core is pushed on and compressed in the band between core and r, never overlapped; once the
/// gap between two surfaces is under a cell the field cannot keep it and they fuse, like clay (and stay fused when the
/// tool goes back). Material beyond r stays where it is. A tool held still or not touching changes nothing.
/// Appends old ray images to `before` when not null. Throws tridex::Error on a kernel's device failure.
ClayStats clay_grab(TriDexel& model, const GridSweep& sweep, std::vector<RayImage>* before = nullptr,
                    ClayKernel& kernel = clay_cpu_kernel());

}  // namespace tridex::compute
