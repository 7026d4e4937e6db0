// core/tri_mesh.hpp - an indexed triangle mesh in world metres, and its topology checks.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/aabb.hpp"
#include "core/math.hpp"

namespace tridex {

/// Indexed triangle mesh. Triangles are counter-clockwise seen from outside (outward normals).
struct TriMesh {
    std::vector<Vec3> positions;                          ///< vertex positions, m
    std::vector<std::array<std::uint32_t, 3>> triangles;  ///< vertex indices per triangle

    /// Bounding box of all vertices (empty box when there are none).
    Aabb bounds() const;
};

/// Edge-use counts of a mesh: an undirected edge used by one triangle is a boundary edge,
/// by more than two a non-manifold edge. A closed 2-manifold has both counts zero.
struct EdgeStats {
    std::size_t edges = 0;             ///< distinct undirected edges
    std::size_t boundary_edges = 0;    ///< used by exactly one triangle
    std::size_t nonmanifold_edges = 0; ///< used by three or more triangles
    std::size_t misoriented_edges = 0; ///< used twice in the same direction (inconsistent winding)
    std::size_t degenerate_triangles = 0;  ///< triangles with a repeated vertex index
};

/// Counts boundary, non-manifold and misoriented edges. O(T log T) for T triangles. Reads indices only,
/// so out-of-range indices are counted like any others. The functions below that read positions require
/// every index < positions.size() (meshes from compute::load_closed_mesh or the contourer satisfy it).
EdgeStats edge_stats(const TriMesh& mesh);

/// Connected components of the mesh: groups of triangles joined through shared vertex indices (a welded mesh
/// such as the contourer's; unwelded copies of a position count apart). 0 for a mesh without triangles. O(T a(T))
/// for T triangles. Every index must be < positions.size().
std::size_t mesh_components(const TriMesh& mesh);

/// Signed volume enclosed by the mesh (divergence theorem, sum of signed tetrahedra), m^3.
/// Positive for a closed mesh with outward normals. Exact up to double rounding.
double signed_volume(const TriMesh& mesh);

/// Area-weighted per-vertex normals (unit length; zero for isolated vertices).
std::vector<Vec3> vertex_normals(const TriMesh& mesh);

}  // namespace tridex
