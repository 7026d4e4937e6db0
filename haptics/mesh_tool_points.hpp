// haptics/mesh_tool_points.hpp - a haptic interaction mesh over a closed mesh tool's own surface.
#pragma once

#include "core/tri_mesh.hpp"
#include "haptics/tool_points.hpp"

namespace tridex::haptics {

/// Candidate surface samples mesh_surface_points chooses from (area-weighted, low-discrepancy).
constexpr int kMeshPointCandidates = 4096;

/// `count` contact points on the surface of `mesh_m` (the tool's mesh in the tool frame of
/// core/tool_shape.hpp, m, CCW from outside), each with the outward unit normal of the triangle it lies on,
/// radius 0: a haptic interaction mesh over the tool (Popescu, Burdea, Bouzit 3.1), so that touch and the
/// mesh tool's cut agree. Deterministic: kMeshPointCandidates points spread over the surface by area (the
/// triangle from a base-2 van der Corput number over the cumulative areas, the place in it from base-3 and
/// base-5 radical inverses with the square-root warp), then farthest-point sampling among them, starting
/// from the tool's tip (the vertex lowest along the tool axis, -y, with its area-weighted vertex normal).
/// Cost O(count * kMeshPointCandidates + triangles). Throws tridex::Error when count is not in
/// [1, kMaxToolPoints], the mesh has no triangle of non-zero area, an index is out of range, or a position
/// is not finite.
ToolPoints mesh_surface_points(const TriMesh& mesh_m, int count);

}  // namespace tridex::haptics
