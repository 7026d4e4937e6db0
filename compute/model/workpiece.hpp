// compute/model/workpiece.hpp - placing a loaded mesh as the workpiece stock in the world.
#pragma once

#include "core/aabb.hpp"
#include "core/math.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// Uniform scale + translation that maps the mesh bounding box `box` (file units) so its longest side
/// is `stock_size_m` (m) and its centre is `centre_m` (m). Returns the 4x4 (input units -> world metres):
/// p' = centre_m + s * (p - box.centre()), s = stock_size_m / longest side.
/// Throws tridex::Error when the box is empty, degenerate (longest side 0) or not finite, or when
/// stock_size_m is not a finite positive number, or centre_m is not finite.
Mat4 fit_to_stock(const Aabb& box, const Vec3& centre_m, double stock_size_m);

/// Applies the 4x4 affine transform `m` (last row must be 0 0 0 1) to every vertex; keeps the
/// triangles, but reverses their winding when det of the linear part is negative, so outward normals
/// stay outward. Throws tridex::Error when m is not finite, not affine, or singular (det == 0).
TriMesh transformed(const TriMesh& mesh, const Mat4& m);

}  // namespace tridex::compute
