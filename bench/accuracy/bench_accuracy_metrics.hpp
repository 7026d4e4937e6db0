// bench/accuracy/bench_accuracy_metrics.hpp - errors of a mesh against an exact solid (bench --accuracy).
#pragma once

#include <vector>

#include "bench/accuracy/bench_accuracy_exact.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::bench::accuracy {

/// Surface errors of a mesh against the exact solid, m.
struct SurfaceErrors {
    double mean_vertex_m = 0.0;   ///< mean |sdf| at the mesh vertices (vertex -> exact surface)
    double max_vertex_m = 0.0;    ///< max |sdf| at the mesh vertices
    double mean_surface_m = 0.0;  ///< mean distance from exact-surface samples to the mesh
    double max_surface_m = 0.0;   ///< max distance from exact-surface samples to the mesh
    double hausdorff_m = 0.0;     ///< max(max_vertex_m, max_surface_m): two-sided, sampled
    Vec3 worst_vertex{0.0};       ///< the vertex with the largest |sdf|, m
    Vec3 worst_sample{0.0};       ///< the exact-surface sample farthest from the mesh, m
    std::size_t vertices = 0;     ///< mesh vertices measured
    std::size_t samples = 0;      ///< exact-surface samples measured
};

/// Distance queries from points to a triangle mesh: a uniform grid of triangle indices (each triangle
/// listed in every grid cell its bounding box touches), searched in growing shells.
class MeshDistance {
public:
    /// Builds the grid with cells of `cell_m` (> 0) metres. The mesh must outlive this object.
    MeshDistance(const TriMesh& mesh, double cell_m);
    /// Unsigned distance from p to the nearest triangle, m (infinity for an empty mesh).
    double distance(const Vec3& p) const;

private:
    const TriMesh& mesh_;
    Vec3 lo_{0.0};
    double cell_ = 1.0;
    int dims_[3] = {1, 1, 1};
    std::vector<std::uint32_t> start_;  // CSR: cell -> [start_[c], start_[c+1]) in tris_
    std::vector<std::uint32_t> tris_;
};

/// Unsigned distance from p to triangle (a, b, c), m (Ericson, closest point on triangle).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Vertex and surface errors of `mesh` against `exact`, using `samples` (points on the exact surface,
/// from ExactSolid::surface_samples) and a triangle grid of `grid_cell_m`. Parallel over points
/// (std::thread, `threads` >= 1); not part of any timing.
SurfaceErrors surface_errors(const TriMesh& mesh, const ExactSolid& exact, const std::vector<Vec3>& samples,
                             double grid_cell_m, int threads);

}  // namespace tridex::bench::accuracy
