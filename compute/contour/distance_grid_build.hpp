// compute/contour/distance_grid_build.hpp - a closed mesh's signed distance field on a regular grid, for feeling it.
#pragma once

#include <cstddef>

#include "core/distance_grid.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// The signed distance field of a closed, outward-oriented mesh (m, any frame) on a grid of spacing cell_m that
/// covers the mesh's bounding box grown by margin_m on every side (rounded out to whole cells), negative where a node
/// lies inside the solid. Each node holds its distance (Ericson 5.1.5) to the triangle found nearest: the triangles
/// within a cell of it are measured, the nearest one is carried to the nodes beyond (closest-feature propagation, as
/// in Bridson's level-set construction), then each node walks over the mesh to a nearer triangle around its
/// triangle's vertices while there is one. That finds the nearest triangle wherever the distance falls toward it over
/// the mesh (a convex or gently curved region); in a deep fold it can stop at a triangle slightly farther. Inside is decided by the scan conversion of the same mesh onto a lattice
/// whose nodes are the grid's (scan_convert: exact winding along the Z rays), so the sign agrees with what a
/// workpiece made of the mesh holds. Runs on every core; the result does not depend on the number of threads.
/// O(triangles + nodes) point-triangle distances.
/// Throws tridex::Error when cell_m or margin_m is not finite and positive (margin may be 0), the mesh is empty or
/// not finite, or the grid would need more than max_bytes (the message gives both sizes and the node counts).
DistanceGrid build_distance_grid(const TriMesh& mesh_m, double cell_m, double margin_m, std::size_t max_bytes);

}  // namespace tridex::compute
