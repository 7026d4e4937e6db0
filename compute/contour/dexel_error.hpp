// compute/contour/dexel_error.hpp - how far a surface strays from the tri-dexel model's own surface samples: the
// interval ends of its rays, where each ray crosses the solid's boundary (docs/design/lod.md, "Coarse first at
// start-up").
#pragma once

#include <cstddef>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// The model's surface points in the cells of `box` (inclusive cell range, clamped to the lattice): the ends of every
/// interval of every ray through the box's lattice nodes that lie within the box, world m. The box's far faces
/// belong to the next box (half-open, lo to hi + 1), except the lattice's own last faces. Each is a point of the
/// exact solid's boundary, where that ray crosses it. An empty box gives none.
std::vector<Vec3> dexel_surface_points(const TriDexel& model, const CellBox& box);

/// True when the model has a surface point in the cells of `box` (dexel_surface_points would give one); stops at the
/// first.
bool dexel_surface_in(const TriDexel& model, const CellBox& box);

/// How far `surface` strays from the model's surface in `box`: the largest distance from the model's surface points
/// there (dexel_surface_points) to `surface`'s triangles, sampled (compute::sampled_distance: the six points extreme
/// along x, y and z and about `samples` spread evenly), m. One-sided, from the model's surface to `surface`, as a
/// simplified surface's error against the contour it stands in for is measured. 0 when the box holds no surface
/// point; +infinity when it does and `surface` has no triangles. `bucket_m` sizes the triangle grid
/// (compute::TriangleGrid; a couple of the surface's own cells).
double dexel_surface_error(const TriDexel& model, const CellBox& box, const TriMesh& surface, double bucket_m,
                           std::size_t samples);

}  // namespace tridex::compute
