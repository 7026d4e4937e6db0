// haptics/forces/force_shading.hpp - vertex normals at dexel ends and their blend (force shading).
#pragma once

#include "core/active_surface.hpp"
#include "core/math.hpp"

namespace tridex::haptics {

/// Largest depth step between an end and the same-type end of a neighbouring window ray that still
/// counts as the same surface sheet when estimating a vertex normal, in cells per window ray spacing
/// (a slope of 3 cells per cell, 72 degrees from the ray set's plane; steeper surfaces are better seen
/// by another ray set). The limit in grid units is kShadingMaxStepCells * the window's stride.
constexpr double kShadingMaxStepCells = 3.0;

/// Outward unit normal of the surface at one dexel end: the end at depth_cells (grid units) on the ray
/// at window-local (iu, iv) of ray set `axis` (0 = X, 1 = Y, 2 = Z) of snapshot `s`, an exit end (solid
/// below, outward +axis) when exit_end, else an enter end (outward -axis). The surface is treated as a
/// height field over the ray set's window: its slope along u and v is the central difference of the
/// nearest same-type ends of the neighbouring window rays divided by their spacing
/// (ActiveSurface::window_spacing_cells; one-sided when one neighbour is missing, empty or more than
/// kShadingMaxStepCells per spacing away, zero when both are), and n ~ s*(e_axis - g_u*e_u - g_v*e_v),
/// s = +1 for exit ends, -1 for enter ends (u = axis (a+1)%3, v = axis (a+2)%3, as ActiveSurface).
/// Exact for planes (up to float rounding of the depths), at any window stride. Returns +-e_axis when
/// the indices are outside the window's filled rays. Allocation-free, at most 4 rays x kMaxIntervals
/// ends read.
/// Source: Popescu, Burdea, Bouzit, "VR Simulation Modeling for a Haptic Glove", 3.2 (vertex normals
/// for force shading); the height-field gradient is our estimate for dexel data.
Vec3 dexel_end_normal(const ActiveSurface& s, int axis, int iu, int iv, double depth_cells, bool exit_end);

/// Force-shading normal: the unit vector along sum_k weight[k]*normal[k] over the three vertices of the
/// active triangle, with weights the HIP's barycentric coordinates (non-negative, summing to 1), so the
/// normal varies continuously over the triangle and equals the shared vertex normals on its edges: the
/// force direction does not jump between neighbouring triangles (Popescu et al. 3.2, distance-weighted
/// vertex normals; Morgenbesser & Srinivasan 1996 force shading). Returns zero when the sum vanishes.
Vec3 blend_normals(const Vec3 normal[3], const double weight[3]);

/// v rotated by the smallest rotation that takes unit vector `from` to unit vector `to`
/// (Rodrigues' formula). Used to carry the tangential (friction) force from the active triangle's plane
/// into the shaded frame with its length kept. Returns v unchanged when from . to <= -1 + 1e-12 (opposite).
Vec3 rotate_between(const Vec3& from, const Vec3& to, const Vec3& v);

}  // namespace tridex::haptics
