// bench/bench_sculpt.hpp - `tridex bench --sculpt`: swept-Boolean throughput and latency of the CPU (one
// thread, all cores) and GPU (per segment, batched) sculpting paths against resolution and tool size.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tridex::bench {

/// One benchmark row: one path carving one stroke prefix at one resolution and tool radius.
struct SculptBenchRow {
    int n = 0;                  ///< lattice cells along each side
    double radius_cells = 0.0;  ///< ball radius, cells
    std::string path;           ///< "cpu-1t", "cpu", "gpu", "gpu-batched", "clay-push", "clay-smooth", "gpu-clay-push" or "gpu-clay-smooth"
    int batch = 1;              ///< segments per step (per apply call)
    std::size_t segments = 0;   ///< segments carved
    std::size_t steps = 0;      ///< apply calls
    double boolean_s = 0.0;     ///< summed wall time of the apply calls, s
    double contour_s = 0.0;     ///< summed wall time of re-contouring the dirty tiles (CPU Contourer), s
    std::size_t tiles_contoured = 0;      ///< tiles re-contoured, summed over steps
    double segments_per_s = 0.0;          ///< segments / boolean_s
    double rays_per_s = 0.0;              ///< footprint rays visited (summed over segments) / boolean_s
    double tiles_contoured_per_s = 0.0;   ///< tiles_contoured / contour_s
    double latency_ms = 0.0;              ///< median over steps: apply + re-contour of its dirty tiles, ms
    double step_ms_median = 0.0;          ///< median over steps: the apply call alone, ms
    /// Mean over steps: the process's CPU time (every thread's, the task pool's and the Vulkan driver's workers'
    /// too) during the apply call, ms; less sensitive to other processes' load than the wall times.
    double step_cpu_ms = 0.0;
    double rays_per_segment = 0.0;        ///< median footprint rays of one segment (all three sets)
    std::uint64_t gpu_ray_tiles = 0;      ///< GPU rows: ray tiles dispatched (GpuSculptStats); 0 on CPU rows
    std::uint64_t gpu_retried_rays = 0;   ///< GPU rows: rays redone on the host (spill pool full / long rays)
    /// Clay rows: the model's volume (the mean of the three sets' interval lengths, the measure the clay tools
    /// keep) after the row less before, cells^3, and that per 1,000 segments; 0 on the other rows.
    double volume_change_cells3 = 0.0;
    double volume_drift_per_1000_cells3 = 0.0;
    double volume_before_cells3 = 0.0;  ///< clay rows: the workpiece's volume before the row, cells^3
    /// Clay rows: lattice nodes on whose inside/outside status the three ray sets disagree (clay_set_disagreement)
    /// in the node box of the row's sweeps, before and after the row; 0 on the other rows.
    std::size_t disagreement_before = 0;
    std::size_t disagreement_after = 0;
    /// GPU sculpt rows: mean ms per submission (GpuSculptStats) spent before submitting, from recording until the
    /// fence signalled, and after it; 0 on other rows.
    double gpu_prepare_ms = 0.0, gpu_submit_ms = 0.0, gpu_finish_ms = 0.0;
    std::string model_hash;               ///< FNV-1a 64 of every interval after the row (hex); equal
                                          ///< hashes = identical models when `segments` are equal
    std::vector<double> step_s;           ///< each apply call's wall time, s, in stroke order (not in the JSON)
};

/// Wall time (s) `row` took for the stroke's first `segments` segments: its first ceil(segments / batch) apply
/// calls; the whole row's boolean_s when it carved fewer.
double seconds_for_segments(const SculptBenchRow& row, std::size_t segments);

/// What to measure.
struct SculptBenchOptions {
    std::vector<int> resolutions{256, 512, 1024};  ///< N values (cells per side, >= 24)
    std::vector<double> radii_cells{2.0, 8.0};     ///< ball radii, cells (> 0, <= N/8)
    int batch = 64;                 ///< segments per apply call of the "cpu" and "gpu-batched" paths
    int threads = 0;                ///< "cpu" path threads; 0 = every core (compute::pool_slots)
    double min_boolean_s = 0.5;     ///< a row runs until its apply calls took this long, s ...
    double max_row_s = 4.0;         ///< ... or its wall time (with contouring) reaches this, s ...
    int max_segments = 65536;       ///< ... or the stroke (this many segments) is used up
    bool gpu = true;                ///< run the GPU rows when a Vulkan device exists
    /// Paths to run, any of "cpu-1t", "cpu", "gpu", "gpu-batched", "clay-push", "clay-smooth", "gpu-clay-push",
    /// "gpu-clay-smooth" (each at most once; the clay paths only when asked for); the parallel-path lines need a single-thread path, the gpu-batched /
    /// cpu line "cpu" and "gpu-batched", the clay ratios "cpu-1t".
    std::vector<std::string> paths{"cpu-1t", "cpu", "gpu", "gpu-batched"};
    std::string out = "out/bench";  ///< folder for sculpt_bench.json
};

/// For each N: a workpiece box covering grid [4, N-4]^3 of an N^3-cell lattice (0.3 m per side, so
/// cell = 0.3/N m), scan-converted (scan_convert of box_mesh) and contoured once. For each radius r: a
/// stroke of a ball (subtract) carving a random-walk groove 3.37 cells deep into the top face (z = N-4),
/// segments 0.5..1 cell long (a haptic tick's motion), the same walk shape at every N. Each path starts
/// from a copy of the workpiece and its mesh and carves the stroke from its start, step by step:
/// "cpu-1t" = apply_sweep per segment; "cpu" = apply_sweeps_parallel per `batch` segments; "gpu" =
/// GpuSculptor::apply per segment; "gpu-batched" = per `batch` segments; "clay-push" / "clay-smooth" = the same
/// stroke as ToolOp::kPush / kSmooth through compute::apply_clay per segment (the CPU reference, one thread; the
/// ball presses 3.37 cells in, so push dents at its 1-cell step); "gpu-clay-push" / "gpu-clay-smooth" = the same
/// through apply_clay on the GPU clay kernel (compute/gpu/gpu_clay.hpp: field and re-sampling in Vulkan compute,
/// the same model bit for bit, so the same model_hash as the CPU clay row). After each step the dirty
/// tiles are re-contoured on the CPU (Contourer; GPU contouring is not built yet: "contour": "cpu").
/// GPU rows are skipped, with a printed reason, when no Vulkan device exists or options.gpu is false.
/// Prints a table; each parallel path's ("cpu" on several threads, "gpu", "gpu-batched") segments_per_s
/// against the best single-thread path's ("cpu-1t", or "cpu" on one thread) at the same N and radius; the
/// ratios gpu-batched / cpu segments_per_s and step_ms_median N_max / N_min; writes
/// sculpt_bench.json (a list of rows) and sculpt_bench_setup.json (workpiece, stroke, device and a "memory"
/// record: GPU slab bytes per set and N, interval storage at N = 1024) into options.out; returns the rows.
/// Throws tridex::Error on bad options (resolutions, radii, batch, max_segments, paths: empty, out of range,
/// unknown or repeated) or an unwritable folder.
std::vector<SculptBenchRow> run_sculpt_bench(const SculptBenchOptions& options);

}  // namespace tridex::bench
