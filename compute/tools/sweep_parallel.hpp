// compute/tools/sweep_parallel.hpp - a batch of swept Booleans on all CPU cores (the multi-threaded CPU path).
#pragma once

#include <span>

#include "compute/tools/boolean.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// Applies `batch` to `model` with `threads` std::threads (threads <= 0: std::thread::hardware_concurrency(),
/// at least 1); the result equals applying the sweeps one by one with apply_sweep, bit for bit.
///
/// Method: every sweep is validated first (to_grid_sweep; sweeps with op kNone are skipped). Per ray set,
/// the rows (v) of the union of the sweeps' footprints (sweep_footprint) are handed out to the threads
/// (one row at a time from a shared counter; the calling thread works too). Each ray of a row gets, IN
/// BATCH ORDER, the sweeps whose footprint holds it (apply_sweep_to_ray), so no two threads touch the
/// same ray and each ray sees the same operations in the same order as the sequential path. Afterwards the
/// tiles around sweep_bounds of each sweep that changed a ray are marked dirty (as apply_sweep does).
///
/// Returns the sums apply_sweep would return over the batch: rays_visited = footprint rays summed over
/// sweeps, rays_changed = (ray, sweep) pairs where the sweep changed the ray.
/// Cost: O(sum over sweeps of footprint rays x stamps x intervals per ray) / threads, plus
/// O(rows x sweeps) to list each row's sweeps, plus starting threads - 1 std::threads (tens of us).
/// Throws tridex::Error (model unchanged) when a sweep is invalid (to_grid_sweep); an exception inside a
/// worker (std::bad_alloc) is rethrown after all threads have joined (the model is then partly updated).
/// Source: Peng et al., tri-dexel Booleans with the tool's swept volume.
BooleanStats apply_sweeps_parallel(TriDexel& model, std::span<const Sweep> batch, int threads);

}  // namespace tridex::compute
