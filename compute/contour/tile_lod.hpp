// compute/contour/tile_lod.hpp - coarser levels of detail of one tile's mesh, with their borders kept so
// tiles at different levels still meet edge to edge.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// One simplified level of a tile's mesh.
struct TileLodLevel {
    TriMesh mesh;                         ///< the level's triangles and only the vertices they use, world m, CCW from outside
    std::vector<std::uint8_t> materials;  ///< per mesh vertex: the full mesh's material id (empty when it had none)
    /// Per mesh vertex: the full mesh's area-weighted unit normal at that vertex (core vertex_normals), so a
    /// level is shaded as the full mesh is.
    std::vector<Vec3> normals;
    /// Distance between this level and the full mesh, m (TileLodOptions::measure): meshoptimizer's error
    /// estimate (the default), or an upper bound of the two-sided (Hausdorff) distance: the largest exact
    /// distance from samples of either surface to the other (surface_samples, spacing s =
    /// TileLodOptions::sample_spacing_cells) plus s / sqrt(3). Every point of a surface lies within s / sqrt(3)
    /// of one of its samples (no point of a triangle is farther than its longest edge / sqrt(3) from a corner)
    /// and the distance to a surface changes by at most the distance moved, so that bound holds for every
    /// point, not only the samples.
    double error_m = 0.0;
    /// A coarse group level's (CoarseGroupLevels::level) leading triangles that are the group's own, its coarse
    /// tile's contour, before the ring and the skirt that close it against neighbours drawn at other levels. 0: the
    /// level is drawn whole (a simplified level, or one with no triangles of its own).
    std::size_t own_triangles = 0;
    /// With own_triangles: the neighbouring groups of the same depth whose own triangles continue the open border of
    /// this level's own triangles (their coarse tile's mesh holds one of its vertices), one bit per neighbour at group
    /// offset (dx, dy, dz) in -1..1, bit neighbour_bit(dx, dy, dz) (never the group's own, 13).
    std::uint32_t joins = 0;
};

/// The bit of the neighbour at group offset (dx, dy, dz), each in -1..1, in TileLodLevel::joins: 9 (dz + 1) +
/// 3 (dy + 1) + (dx + 1), 0..26; 13 is the group itself.
constexpr int neighbour_bit(int dx, int dy, int dz) { return 9 * (dz + 1) + 3 * (dy + 1) + (dx + 1); }

/// How TileLodLevel::error_m is measured.
enum class LodErrorMeasure {
    /// meshoptimizer's own error of each simplification (result_error: the square root of the largest
    /// area-weighted mean squared distance of a collapsed vertex to the planes of the triangles merged into
    /// it, Garland and Heckbert's quadrics), summed over the simplifications that led to the level and
    /// times TileLodOptions::estimate_factor. An estimate, not a bound (a collapse across a crease can stray
    /// further from a small face than the mean says); free, since meshoptimizer computes it anyway.
    kEstimate,
    /// The sampled two-sided distance bound (TileLodLevel::error_m): exact up to the samples' spacing, and
    /// about 100 times the cost of the simplification itself. For tests and for checking the estimate.
    kSampledBound,
};

/// How the levels are made.
struct TileLodOptions {
    double cell_m = 0.0;  ///< lattice spacing, m (> 0): the unit of the error targets and of the sampling
    /// Error targets of the levels, cells, ascending: level k is simplified (from the previous level) until
    /// meshoptimizer's error estimate, added to the estimates of the simplifications before it (and the base
    /// error), would pass error_cells[k] (a geometric series: each level can be drawn twice as far off).
    std::vector<double> error_cells{0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0};
    /// A level is kept only when it has at most this fraction of the previous kept level's triangles (else the
    /// next larger target is tried), in (0, 1).
    double keep_fraction = 0.8;
    /// How each level's error_m is measured.
    LodErrorMeasure measure = LodErrorMeasure::kEstimate;
    /// kEstimate: the factor (>= 1) on meshoptimizer's estimate, a margin for the gap between its mean
    /// squared distance and the largest distance.
    double estimate_factor = 1.5;
    /// kSampledBound: spacing of the surface samples of the error bound, cells (> 0): each level's error_m includes
    /// spacing / sqrt(3) for the points between samples, and the bound's cost grows as 1 / spacing^2.
    double sample_spacing_cells = 0.3;
    /// Meshes with fewer triangles get no levels.
    std::size_t min_triangles = 16;
    /// Levels over groups of tiles (TileSurfaceCache, build_group_lod): groups of 2x2x2 tiles, groups of 2x2x2
    /// of those, ... up to 2^group_depth tiles along each axis; 0 = levels per tile only.
    int group_depth = 3;
    /// A depth-d group is simplified from each child's (tile's or smaller group's) coarsest level whose error is
    /// at most group_part_cells * 2^(d - 1) cells (its full surface when none is), so the groups of a depth
    /// cost about as much as the levels they start from, not the full surface; their errors add up.
    double group_part_cells = 0.25;
};

/// The coarser levels of `mesh` (one tile's triangles with the vertices they use, as
/// compute::TileSurface::mesh), coarsest last; empty when the mesh is too small or does not simplify.
/// Borders: the tile mesh's open border (its edges used by one of its triangles; the neighbouring tiles use
/// them too) and the strip of triangles touching a border vertex are kept as they are; the rest is simplified
/// by edge collapses (meshoptimizer's meshopt_simplify, quadric error metric after Garland and Heckbert,
/// "Surface Simplification Using Quadric Error Metrics", 1997) with meshopt_SimplifyLockBorder on that rest,
/// so the vertices where it meets the strip stay too. No border vertex gains or loses an edge, so any mix of
/// levels across tiles meets along the full-resolution border edges: watertight, and manifold whenever this
/// tile's level is (checked; a level that is not ends the list). (Locking only the border vertices is not
/// enough: a collapse can join two border vertices by a new edge that a neighbour tile has too.)
/// Each level is simplified from the previous one; vertices keep their positions (levels use a subset of the
/// full mesh's vertices), so a flat face keeps only its border strip and the vertices next to it, at no error.
/// `materials` is empty or one id per vertex. Throws tridex::Error when options.cell_m is not finite and > 0,
/// error_cells is not ascending and positive, keep_fraction is outside (0, 1), estimate_factor < 1 or
/// sample_spacing_cells <= 0, materials has
/// the wrong size, or an index is out of range.
/// Cost: O(T log T) per level for T triangles (a few microseconds per triangle in all); kSampledBound adds
/// about 11 samples per cell of surface and level, each a nearest-triangle query in a bucket grid.
std::vector<TileLodLevel> build_tile_lod(const TriMesh& mesh, std::span<const std::uint8_t> materials,
                                         const TileLodOptions& options);

/// Reorders `mesh`'s triangles (each keeps its corners in order, so winding is kept; vertices are not moved) so
/// that consecutive triangles share vertices (meshoptimizer's meshopt_optimizeVertexCache, after Forsyth's
/// linear-speed vertex cache optimisation): a GPU that shades each vertex once per small window of indices
/// (a post-transform cache, or a CPU Vulkan's de-duplication per batch of indices) shades fewer vertices.
/// Throws tridex::Error when an index is out of range. O(T) for T triangles.
void order_for_vertex_cache(TriMesh& mesh);

/// build_tile_lod for a mesh that itself stands for a surface within base_error_m (m, >= 0; e.g. the coarser
/// levels of several tiles merged into one group): the same levels, each with error_m = its error to `mesh` +
/// base_error_m (the triangle inequality of the Hausdorff distance; with kEstimate the targets count
/// base_error_m too), and shaded with `normals` (empty, or one
/// unit normal per vertex; empty: vertex_normals(mesh)). Throws as build_tile_lod, and when normals has the
/// wrong size or base_error_m is negative or not finite.
std::vector<TileLodLevel> build_lod_levels(const TriMesh& mesh, std::span<const std::uint8_t> materials,
                                           std::span<const Vec3> normals, double base_error_m,
                                           const TileLodOptions& options);

}  // namespace tridex::compute
