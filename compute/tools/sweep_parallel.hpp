// compute/tools/sweep_parallel.hpp - a batch of swept Booleans on all CPU cores on the task pool (the multi-threaded CPU path).
#pragma once

#include <span>

#include "compute/tools/boolean.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// Applies `batch` to `model` on the persistent task pool (compute/parallel/task_pool.hpp) with
/// pool_slots(threads) threads (threads <= 0: every core); the result equals applying the sweeps one by one
/// with apply_sweep, bit for bit, for every thread count.
///
/// Method: every sweep is validated first (to_grid_sweep; sweeps with op kNone are skipped). Per ray set,
/// the union of the sweeps' footprints (sweep_footprint) is cut into tiles of 8 x 8 rays, and each tile
/// lists the sweeps whose footprint meets it, in batch order; the tiles are the tasks. Each ray of a tile
/// gets, IN BATCH ORDER, the sweeps whose footprint holds it (apply_sweep_to_ray), so no two tasks touch
/// the same ray and each ray sees the same operations in the same order as the sequential path. A batch of
/// any size gives about (footprint rays / 64) tasks, so small tools and short batches use every core too.
/// Afterwards the cells around the interval ends each sweep changed are marked dirty, one box per sweep (the
/// same marks as apply_sweep one by one).
///
/// Returns the sums apply_sweep would return over the batch: rays_visited = footprint rays summed over
/// sweeps, rays_changed = (ray, sweep) pairs where the sweep changed the ray.
/// Cost: O(sum over sweeps of footprint rays x stamps x intervals per ray) / threads, plus O(sum over sweeps
/// of the ray tiles they meet) to list each tile's sweeps; no thread is started (the pool's workers persist).
/// Throws tridex::Error (model unchanged) when a sweep is invalid (to_grid_sweep); an exception inside a
/// task (std::bad_alloc) is rethrown after the running tasks end (the model is then partly updated).
/// Source: Peng et al., tri-dexel Booleans with the tool's swept volume.
BooleanStats apply_sweeps_parallel(TriDexel& model, std::span<const Sweep> batch, int threads);

}  // namespace tridex::compute
