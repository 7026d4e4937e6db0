// compute/runtime/active_surface_publish.hpp - copying the dexels near the tool into the haptic cache.
#pragma once

#include <cstdint>

#include "compute/model/tridexel.hpp"
#include "core/active_surface.hpp"

namespace tridex::compute {

/// How far (m) the tool may move from the window centre before the next publish, added to the tool's
/// half extent when sizing the window: 3 mm (30 ms of sculpt-thread latency at 0.1 m/s).
constexpr double kDefaultMotionMarginM = 0.003;

/// Copies into `out` (core/active_surface.hpp) the rays of each set in a window of at most
/// ActiveSurface::kWindow x kWindow rays centred on centre_m, sampling every stride-th lattice ray.
/// The stride is ActiveSurface::stride_for(tool_extent_m / 2 + motion_margin_m, cell): the smallest
/// that makes the window cover every point within half the tool's extent plus the margin (m, per axis)
/// of centre_m, 1 when the lattice is coarse enough. tool_extent_m (m, >= 0) is the diameter of a ball
/// about centre_m holding the whole tool: 2r for a ball of radius r, the points' span plus 2r for a
/// multi-point tool (tool_extent_m()); 0 with a zero margin = stride 1 (every ray, the old window).
/// Placement per axis: ActiveSurface::window_first() (the strided ray nearest centre_m minus kWindow/2
/// strides, clamped so the window stays inside the lattice). Each ray's intervals are copied in grid
/// units of the lattice. When a ray has more than kMaxIntervals intervals, keeps the kMaxIntervals
/// consecutive intervals nearest centre_m along the ray (distance from the centre's depth to an
/// interval, 0 inside it) and sets that window's `truncated`. Fills origin_m, cell_m, nodes, centre_m;
/// sets out.sequence = sequence; zeroes the counts of unused window slots.
/// Allocation-free and O(kWindow^2 x (kMaxIntervals + log intervals per ray)) per set, whatever the
/// model size. Throws tridex::Error (before touching `out`) when centre_m is not finite or
/// tool_extent_m / motion_margin_m is negative or not finite.
/// Source: Peng et al., active triangle built from the dexel points around the HIP.
void extract_active_surface(const TriDexel& model, const Vec3& centre_m, double tool_extent_m, std::uint64_t sequence,
                            ActiveSurface& out, double motion_margin_m = kDefaultMotionMarginM);

/// Diameter (m) of the ball about the tool centre that holds a tool whose contact points lie within
/// max_point_distance_m (m) of its centre, each carrying a ball of radius radius_m (m):
/// 2 * (max_point_distance_m + radius_m). A single ball tool: tool_extent_m(0, r) = 2r; the 5-DOF wand
/// of half length h: tool_extent_m(h, 0). Negative or non-finite inputs count as 0.
double tool_extent_m(double max_point_distance_m, double radius_m);

}  // namespace tridex::compute
