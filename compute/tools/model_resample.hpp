// compute/tools/model_resample.hpp - changing a model's resolution: the solid re-sampled onto a finer or coarser
// lattice over the same box, its materials kept (docs/resample.md explains the choices and gives the accuracy).
#pragma once

#include <cstddef>
#include <vector>

#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// Smallest and largest resolution (cells along the lattice's longest axis) a model may be re-sampled to: the range a
/// session accepts for --resolution.
inline constexpr int kResampleMinResolution = 8;
inline constexpr int kResampleMaxResolution = 4096;

/// The resolution of a lattice: its cell count along its longest axis (the N of Lattice::around).
int lattice_resolution(const Lattice& lattice);

/// The lattice of `resolution` cells along the longest axis of `old` covering the same box: spacing
/// h' = h * N / N' (N = lattice_resolution(old)), each other axis ceil(cells * N' / N) cells, centred on the old box
/// (grown by less than one new cell where the old length is not a whole number of new cells). When N' / N or N / N' is
/// a power of two every node of the coarser lattice is a node of the finer one. `resolution` == N gives `old` bit for
/// bit. Throws tridex::Error when resolution is outside [kResampleMinResolution, kResampleMaxResolution].
Lattice resampled_lattice(const Lattice& old, int resolution);

/// Bytes a model on `target` would take, estimated as TriDexel::empty does for the rays (vector headers) plus the
/// intervals of `model` scaled by the ratio of the two lattices' ray counts (a surface's intervals grow with the rays).
std::size_t resample_bytes_estimate(const TriDexel& model, const Lattice& target);

/// How a ray of the new lattice was made (ResampleStats counts them).
enum class ResampledRay {
    kCopied,   ///< it lies on an old ray of its set: that ray's intervals, depths mapped
    kBlended,  ///< its 2 or 4 nearest old rays hold matching intervals: their ends blended (bilinear)
    kField     ///< the nearest old rays disagree: crossings of the old model's blended node field (linear roots),
               ///< ends next to a flat face across the ray put back on it
};

/// What resample_model did. Volumes from dexel_volume_m3; the surface move is measured apart, by
/// measure_surface_move (compute/contour/surface_move.hpp: it contours both models).
struct ResampleStats {
    int resolution_before = 0;            ///< cells along the longest axis, before
    int resolution_after = 0;             ///< cells along the longest axis, after
    double cell_before_m = 0.0;           ///< old spacing, m
    double cell_after_m = 0.0;            ///< new spacing, m
    double volume_before_m3 = 0.0;        ///< the old model's volume, m^3
    double volume_after_m3 = 0.0;         ///< the new model's volume, m^3
    double max_surface_move_m = 0.0;      ///< largest distance of either surface from the other, m
    double max_surface_move_cells = 0.0;  ///< the same in cells of the coarser of the two lattices
    /// The measure's own floor, m: the largest distance of either model's interval ends from its own contour (sharp
    /// edges and corners, which the contour cuts); a move below it is not a move.
    double surface_move_floor_m = 0.0;
    std::size_t bytes_after = 0;   ///< estimated size of the new model (resample_bytes_estimate), bytes
    std::size_t rays_copied = 0;   ///< new rays made as ResampledRay::kCopied
    std::size_t rays_blended = 0;  ///< ... as kBlended
    std::size_t rays_field = 0;    ///< ... as kField
    bool identical = false;        ///< the resolution did not change: the model was copied bit for bit
};

/// One ray of the new model: set `axis`, node (u, v) of `target` (u along (axis+1)%3, v along (axis+2)%3), re-sampled
/// from `model` (whose lattice covers the box `target` was made from by resampled_lattice). `out` (replaced) gets
/// sorted, disjoint, non-touching intervals in `target`'s grid units, clipped to its lattice; each end's material is
/// the old solid's there (the matching or nearest old interval end). Returns how the ray was made. O(intervals of the
/// nearest old rays), plus O(cells along the ray x intervals of the rays through its nodes) for kField.
ResampledRay resample_ray(const TriDexel& model, const Lattice& target, int axis, int u, int v,
                          std::vector<Interval>& out);

/// `model` re-sampled onto resampled_lattice(model.lattice, resolution), every tile marked dirty (kWhole); the same
/// resolution returns a bit-for-bit copy (tiles included). Fills `stats` when not null (all but the surface move).
/// Throws tridex::Error, before allocating, when the
/// resolution is out of range or the estimated size exceeds `max_bytes` (the message names the resolution, the MiB it
/// would take and the MiB available). O(new rays x intervals per ray), rows of rays on every core (the task pool;
/// the result does not depend on the split).
TriDexel resample_model(const TriDexel& model, int resolution, std::size_t max_bytes, ResampleStats* stats = nullptr);

}  // namespace tridex::compute
