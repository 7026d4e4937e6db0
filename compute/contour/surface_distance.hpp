// compute/contour/surface_distance.hpp - unsigned distance from points to a triangle surface, and the sampled
// two-sided distance between two surfaces (how far a simplified tile mesh strays from the full one).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// Closest point to p on the triangle (a, b, c) (any shape; a degenerate triangle gives the closest point on
/// its segments). Region tests on the barycentric coordinates (Ericson, "Real-Time Collision Detection",
/// 2005, section 5.1.5). Units as the inputs.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Nearest-triangle queries on one mesh: its triangles bucketed in a uniform grid of about `bucket` (same
/// units as the positions) per side, searched in growing shells around the query until no unseen triangle
/// can be nearer. Exact (up to double rounding) for any query point. Keeps a pointer to nothing: the
/// triangles are copied. Not thread-safe (distance() keeps scratch state); one per thread.
class TriangleGrid {
public:
    /// Buckets `mesh`'s triangles (indices must be < positions.size()). bucket <= 0 or not finite: one
    /// bucket per side of a 16-bucket grid over the mesh's box. An empty mesh gives a grid whose distance()
    /// is +infinity.
    TriangleGrid(const TriMesh& mesh, double bucket);
    /// Unsigned distance from p to the nearest triangle (+infinity when the mesh has none). With enough > 0 the
    /// search stops at the first triangle no farther than `enough` and returns that triangle's distance (at most
    /// `enough`, not necessarily the nearest); the result is exact whenever it exceeds `enough`.
    double distance(const Vec3& p, double enough = 0.0);

private:
    std::vector<std::array<Vec3, 3>> tris_;
    std::vector<std::array<Vec3, 2>> boxes_;  // per triangle: lo, hi
    Vec3 lo_{0.0};
    double bucket_ = 1.0;
    std::array<int, 3> dims_{1, 1, 1};
    std::vector<std::uint32_t> start_;  // per bucket: first entry in items_ (CSR, size buckets + 1)
    std::vector<std::uint32_t> items_;  // triangle indices
    std::vector<std::uint32_t> seen_;   // per triangle: query stamp of its last visit
    std::uint32_t stamp_ = 0;
    std::uint32_t hint_ = 0;  // the nearest triangle of the last query: queries come in nearby runs
};

/// Largest distance from any of `points` to `surface`'s triangles (0 for no points, +infinity when the surface
/// has no triangles and there are points). Exact: each point's search stops as soon as it cannot raise the
/// largest distance found so far.
double max_distance(std::span<const Vec3> points, TriangleGrid& surface);

/// The largest of `worst` and the distances to `grid`'s triangles of every step-th point of `points` (counted across
/// calls by `k`, which it advances by the points' count) and of the six points of `points` extreme along x, y and z (a
/// thin feature a coarser surface missed sticks out there: an ear's tip, a fin's edge), units as the inputs. step 0
/// counts as 1. Each search stops as soon as it cannot raise the result.
double sampled_distance(std::span<const Vec3> points, TriangleGrid& grid, std::size_t step, std::size_t& k,
                        double worst);

/// Points spread over every triangle of `mesh`: the vertices of a regular subdivision of each triangle whose
/// sub-edges are at most `spacing` long (spacing > 0, same units as the positions), each mesh vertex once. For a
/// sampled distance between surfaces.
std::vector<Vec3> surface_samples(const TriMesh& mesh, double spacing);

}  // namespace tridex::compute
