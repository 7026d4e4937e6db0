// compute/tools/clay_smooth.hpp - smooth: relaxes the surface under the tool by a Laplacian of the shared node
// field, keeping the volume.
#pragma once

#include <span>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/clay_field.hpp"
#include "compute/tools/clay_kernel.hpp"
#include "compute/tools/sweep.hpp"

namespace tridex::compute {

/// Step of the Laplacian flow per application (stable for <= 1/6 with the 6-neighbour Laplacian).
inline constexpr float kClaySmoothRate = 0.15f;

/// Smooth of one clay sweep (to_clay_grid_sweep; the tool a ball of radius R = sweep.radius cells). It acts once,
/// at the motion's end b, and only when the motion crosses a half-cell plane (floor(2 a) != floor(2 b) on some
/// axis), so the smoothing per unit of path is the same whatever the sample rate, and a tool held still does
/// nothing; and only when the tool touches (phi(b) <= R + 0.5 cell). Better than a height field along each set:
/// one step of the Laplacian flow of the shared node field phi (mean-curvature motion of the surface, isotropic
/// and the same for the three sets): s0(q) = kClaySmoothRate * w(q) * (sum of the 6 neighbours' phi - 6 phi(q)),
/// weighted with Popescu's falloff w = 1 - (d/r)^2 of the distance d to the contact point within the radius of
/// influence r = kClayInfluence * R (section 3.3), on nodes with |phi| < 2 cells. The volume is kept by an offset
/// s1 = w on the same nodes, its weight beta solved (clay_resample). A plane (phi linear) has a zero Laplacian and
/// stays where it is, up to float rounding of phi. The contact, the field's box and region and the beta solve run on
/// the host; the field and the re-sampling on `kernel` (the CPU reference by default; every kernel gives the same
/// model bit for bit).
ClayStats clay_smooth(TriDexel& model, const GridSweep& sweep, std::vector<RayImage>* before = nullptr,
                      ClayKernel& kernel = clay_cpu_kernel());

/// Smooth of several consecutive smooth sweeps of one ball as one operation: each sweep's act (as clay_smooth:
/// once per half-cell plane crossed, while touching), its contact found against `model` as it is before the group;
/// the node field built once over a capsule around the contact points, the acts' Laplacian steps taken one after
/// another on that field (act k steps psi = phi + s0 as the acts before it left it: the same flow as acting sweep
/// by sweep, without re-sampling the rays and rebuilding phi between the acts), one volume offset s1 = the largest
/// falloff and one beta, one re-sampling. One sweep gives clay_smooth's result bit for bit. The result differs
/// slightly from smoothing sweep by sweep (there phi is rebuilt from the re-sampled rays and the volume kept per
/// act), so a caller that must repeat a session groups the same sweeps the same way (apply_clay_batch). Throws
/// tridex::Error when the sweeps' radii differ; an empty span, or acts that all miss the surface, change nothing.
ClayStats clay_smooth_group(TriDexel& model, std::span<const GridSweep> sweeps, std::vector<RayImage>* before = nullptr,
                            ClayKernel& kernel = clay_cpu_kernel());

}  // namespace tridex::compute
