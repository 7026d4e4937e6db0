// renderer/scene/arrow_mesh.hpp - unit cylinder and cone, the shaft and head of the force arrow.
#pragma once

#include "core/tri_mesh.hpp"

namespace tridex::renderer {

/// A closed cylinder of radius 1 m around the +z axis from z = 0 to z = 1 m, `segments` (>= 3) sides,
/// capped at both ends; outward (counter-clockwise) triangles, 4 * segments triangles. Side vertices are
/// separate from cap vertices so the sides shade smoothly and the caps flat.
/// Throws tridex::Error when segments < 3.
TriMesh unit_cylinder(int segments);

/// A closed cone with a base disk of radius 1 m in z = 0 and its apex at (0, 0, 1 m), `segments` (>= 3)
/// sides; outward triangles, 2 * segments triangles (one apex vertex per side, so the side normals point
/// sideways, not along the axis). Throws tridex::Error when segments < 3.
TriMesh unit_cone(int segments);

}  // namespace tridex::renderer
