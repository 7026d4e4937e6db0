// compute/mesh/mesh_weld.hpp - turning a triangle soup into an indexed closed mesh, and checking it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// Merges vertices whose positions are exactly equal (bitwise, with -0 == +0), renumbers the
/// triangles, drops triangles that then repeat a vertex index, and drops unused vertices.
/// Keeps vertex order of first use. O(V + T) expected (hash map). No tolerance: nearly coincident
/// vertices stay apart, so welding never changes geometry. `source`, when given, gets per output vertex the index
/// of the soup vertex it was made from (the first one at that position), to carry per-vertex attributes over.
TriMesh weld_exact(const TriMesh& soup, std::vector<std::uint32_t>* source = nullptr);

/// Requires `mesh` to be a closed, consistently oriented, edge-manifold triangle mesh enclosing a
/// non-zero volume, then makes its triangles face outwards (flips every triangle when the signed
/// volume is negative). `name` is used in messages. Throws tridex::Error "<name>: <reason>" for:
/// no triangles, open mesh ("mesh is not closed: N boundary edges"), non-manifold edges (count),
/// inconsistent orientation (count of edges used twice in the same direction), zero volume.
void require_closed_outward(TriMesh& mesh, const std::string& name);

}  // namespace tridex::compute
