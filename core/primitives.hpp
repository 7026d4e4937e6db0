// core/primitives.hpp - closed triangle meshes of simple solids (stock shapes, test bodies).
#pragma once

#include "core/aabb.hpp"
#include "core/math.hpp"
#include "core/tri_mesh.hpp"

namespace tridex {

/// The box `box` (m) as 8 vertices and 12 outward-facing triangles (each face split along the
/// diagonal from its lowest-index corner). Throws tridex::Error when the box is empty, flat or not finite.
TriMesh box_mesh(const Aabb& box);

/// A sphere of radius radius_m centred at centre_m (m): an icosahedron whose faces are split
/// `subdivisions` times into 4, with vertices pushed onto the sphere; 20 * 4^subdivisions outward
/// triangles, all vertices exactly radius_m from the centre (up to rounding). Its volume is below
/// 4/3 pi r^3 (inscribed polyhedron); use signed_volume for its exact volume.
/// Throws tridex::Error when radius_m <= 0, centre_m is not finite, or subdivisions is not in [0, 7].
TriMesh icosphere_mesh(const Vec3& centre_m, double radius_m, int subdivisions);

}  // namespace tridex
