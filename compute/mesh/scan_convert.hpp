// compute/mesh/scan_convert.hpp - filling a tri-dexel model from a closed triangle mesh.
#pragma once

#include "compute/model/tridexel.hpp"
#include "core/progress.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// Fixed-point resolution of scan conversion: projected vertex coordinates are snapped to multiples
/// of 2^-kSnapBits cells before the exact inside tests.
constexpr int kSnapBits = 16;

/// Fills all three ray sets of `model` (which must be empty, as made by TriDexel::empty) with the
/// solid bounded by the closed, outward-oriented mesh `mesh_m` (world metres), then marks dirty every
/// tile holding an interval end (TriDexel::mark_dirty of each end point). Source: Peng et al.,
/// tri-dexel model built by ray casting along three axes.
///
/// Crossings are exact and counted once: vertex coordinates across each ray set are snapped to a
/// fixed-point grid of 2^-16 cell (integers), the 2D point-in-triangle orientation tests are done in
/// exact integer arithmetic, and a ray exactly on a projected edge or vertex is treated as if it were
/// at (u + eps, v + eps^2) (symbolic perturbation), so every ray is in general position: a ray through
/// a shared edge or vertex hits exactly one of the triangles around it (or, on a silhouette fold,
/// both or neither, with opposite signs). Triangles seen edge-on (zero projected area after snapping)
/// contribute nothing. The depth at a crossing is the barycentric blend of the vertex depths with
/// weights from the unsnapped triangle (double; the exact snapped weights when snapping made the
/// triangle edge-on or flipped), clamped to the triangle's depth range, stored as float grid units.
/// Per ray, crossings are sorted (equal depths merged), the winding number is accumulated (+1 entering, -1 leaving, from the triangle's projected orientation),
/// and the spans where it is > 0 become intervals; spans touching after rounding to float are merged,
/// empty ones dropped, and intervals are clipped to the lattice, [0, cells[axis]].
///
/// Consequence: a ray at node (u, v) counts as inside a lattice-aligned face region [u0, u1) x [v0, v1),
/// so a box whose faces lie on lattice nodes gets exactly its volume, ray by ray.
/// Runs on every core (the task pool, compute/parallel/task_pool.hpp: triangles in fixed chunks, then rays in
/// fixed chunks); the result does not depend on the number of threads.
/// Complexity O(T + nodes covered by the triangles' projections + crossings) for T triangles.
/// Throws tridex::Error when the model is not empty, a triangle index is out of range, a position is
/// not finite, or the mesh lies more than 2^40 cells from the lattice origin. `progress` (core/progress.hpp) hears
/// the fraction done, on the calling thread, a few dozen times per ray set.
void scan_convert(const TriMesh& mesh_m, TriDexel& model, const ProgressFn& progress = {});

}  // namespace tridex::compute
