// renderer/primitive_meshes.hpp - small closed meshes for the tool ball and the workspace box.
#pragma once

#include "core/aabb.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::renderer {

/// A UV sphere of radius 1 m at the origin: `rings` latitude bands (>= 2) and `segments` longitude
/// sectors (>= 3); closed, outward (counter-clockwise) triangles, 2 * segments * (rings - 1) triangles.
/// Throws tridex::Error on too few rings or segments.
TriMesh unit_sphere(int rings, int segments);

/// The 12 outward triangles of `box` (8 shared corners). Throws tridex::Error when the box is empty.
TriMesh box_mesh(const Aabb& box);

}  // namespace tridex::renderer
