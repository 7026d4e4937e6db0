// renderer/scene/primitive_meshes.hpp - the UV sphere drawn as the tool ball (the workspace box is core's box_mesh).
#pragma once

#include "core/aabb.hpp"
#include "core/primitives.hpp"  // box_mesh, shared with compute/ tests
#include "core/tri_mesh.hpp"

namespace tridex::renderer {

/// A UV sphere of radius 1 m at the origin: `rings` latitude bands (>= 2) and `segments` longitude
/// sectors (>= 3); closed, outward (counter-clockwise) triangles, 2 * segments * (rings - 1) triangles.
/// Throws tridex::Error on too few rings or segments.
TriMesh unit_sphere(int rings, int segments);

}  // namespace tridex::renderer
