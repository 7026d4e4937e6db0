// bench/accuracy/bench_accuracy_coarse.hpp - `tridex bench --accuracy`: the coarse group levels of a carved model
// (compute/contour/coarse_levels.hpp, contoured from every 2nd, 4th, 8th or 16th ray) against the exact solid.
#pragma once

#include <cstddef>
#include <vector>

#include "bench/accuracy/bench_accuracy_exact.hpp"
#include "compute/model/tridexel.hpp"
#include "core/math.hpp"

namespace tridex::bench::accuracy {

/// The coarse levels of one group depth of one carved model, measured against the exact solid. A group's error is
/// two-sided: the largest |sdf| at the vertices of its level's own triangles (the coarse contour of its box), and
/// the largest distance from an exact-surface sample inside its box to its level (own triangles, ring and skirt). A
/// level with no triangles of its own (only a ring of its neighbours' and a skirt, TileLodLevel::own_triangles 0) is
/// measured by the samples alone: its skirt lies inside the surface by design.
struct CoarseLevelErrors {
    int depth = 0;               ///< group depth d: the levels read every 2^d-th ray (stride 2^d)
    int stride = 0;              ///< 2^d
    double coarse_cell_m = 0.0;  ///< the coarse lattice's spacing: stride x the model's cell, m
    /// Groups measured: those whose level has triangles of its own or whose box holds exact-surface samples (a level
    /// of only a ring and a skirt with no surface in its box is drawn but has nothing to measure).
    std::size_t groups = 0;
    std::size_t triangles = 0;   ///< the levels' own triangles, summed (rings and skirts not counted)
    double max_vertex_m = 0.0;   ///< largest |sdf| at an own triangle's vertex over every group, m
    double max_surface_m = 0.0;  ///< largest distance from an exact-surface sample to its group's level, m
    Vec3 worst_vertex{0.0};      ///< the own vertex with the largest |sdf|, world m
    Vec3 worst_sample{0.0};      ///< the exact-surface sample farthest from its group's level, world m
    double group_p50_m = 0.0;    ///< median of the groups' two-sided errors (the upper one for an even count), m
    double group_p90_m = 0.0;    ///< 90th percentile of the groups' errors, m
    double group_max_m = 0.0;    ///< largest group error (max of max_vertex_m and max_surface_m), m
    /// Groups whose error exceeds the estimate a coarse-first start-up draws a level with before its tiles are in
    /// (TileSurfaceCache::kStartupErrorCoarseCells coarse cells).
    std::size_t over_startup_estimate = 0;
    /// Groups whose error exceeds the distance from the model's own surface points in their box to their level
    /// (compute::dexel_surface_error: what a coarse-first start-up takes as a finest-depth level's error before its
    /// tiles are in) by more than half a fine cell, and the largest excess of any group, m.
    std::size_t over_dexel_estimate = 0;
    double dexel_excess_max_m = 0.0;
    /// Groups whose error exceeds the level's own estimate (CoarseLevelOptions::error_coarse_cells coarse cells).
    std::size_t over_level_estimate = 0;
    /// Exact-surface samples in a group box whose level has no triangles (surface the coarse rays missed whole).
    std::size_t samples_without_level = 0;
};

/// Builds the coarse group levels of `model` at each of `depths` (1..6, CoarseGroupLevels with every depth
/// contoured whole) and measures every group's level against `exact`, using `samples` (points on the exact surface,
/// world m; those outside the model's lattice are ignored). Parallel over groups on `threads` (>= 1) threads.
/// Returns one entry per depth, in the order given. Throws tridex::Error for a depth outside 1..6 or threads < 1.
std::vector<CoarseLevelErrors> coarse_level_errors(const compute::TriDexel& model, const ExactSolid& exact,
                                                   const std::vector<Vec3>& samples, const std::vector<int>& depths,
                                                   int threads);

}  // namespace tridex::bench::accuracy
