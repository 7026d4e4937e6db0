// bench/accuracy/bench_accuracy.hpp - `tridex bench --accuracy`: run time against error of the sculpting paths
// (and of an OpenVDB level-set peer) on stroke programs with an exact answer.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace tridex::bench {

/// One row: one method and path running one program at one resolution.
struct AccuracyRow {
    std::string method;              ///< "tridex" or "openvdb"
    std::string path;                ///< "cpu-1t", "cpu" (all cores), "gpu" (tridex) or "cpu-1t" (openvdb)
    int n = 0;                       ///< cells (voxels) along the lattice side
    double cell_m = 0.0;             ///< lattice spacing or voxel size, m
    std::string program;             ///< program name (bench_accuracy_exact.hpp)
    std::size_t segments = 0;        ///< segments applied
    double time_per_segment_s = 0.0; ///< sculpt wall time / segments, s
    double contour_s = 0.0;          ///< meshing after the program (tridex: dirty-tile re-contour), s
    std::size_t memory_bytes = 0;    ///< model bytes after the program
    double volume_m3 = 0.0;          ///< the model's volume (tridex: dexel volume), m^3
    double exact_volume_m3 = 0.0;    ///< reference volume, m^3
    double volume_sigma_m3 = 0.0;    ///< sampling standard error of the reference volume, m^3
    double volume_error_rel = 0.0;   ///< (volume - exact) / exact
    double mean_error_m = 0.0;       ///< mean |sdf| at mesh vertices, m
    double max_error_m = 0.0;        ///< max |sdf| at mesh vertices, m
    double surface_mean_m = 0.0;     ///< mean distance exact-surface sample -> mesh, m
    double surface_max_m = 0.0;      ///< max distance exact-surface sample -> mesh, m
    double hausdorff_m = 0.0;        ///< max of the two one-sided maxima, m
    std::array<double, 3> worst_vertex_cells{};  ///< lattice position (cells) of the max-error vertex
    std::array<double, 3> worst_sample_cells{};  ///< lattice position (cells) of the farthest surface sample
    std::size_t vertices = 0;        ///< mesh vertices
    std::size_t surface_samples = 0; ///< exact-surface samples
    double volume_change_m3 = 0.0;   ///< tridex: dexel volume after - before the program (0 for paint), m^3
};

/// What to run.
struct AccuracyBenchOptions {
    std::vector<int> resolutions{64, 128, 256, 512};  ///< N values (16..1024)
    std::vector<std::string> programs;           ///< empty = all programs; else names from program_names()
    bool cpu_one_thread = true;                  ///< run the "cpu-1t" path (apply_sweep, one thread)
    bool cpu_all_cores = true;                   ///< run the "cpu" path (apply_sweeps_parallel on all cores, batches of 64)
    bool gpu = true;                             ///< run the "gpu" path (GpuSculptor, batches of 64) when Vulkan exists
    bool openvdb = true;                         ///< run the OpenVDB peer when built in
    bool short_programs = false;                 ///< only the first moves of each program (tests)
    double samples_per_cell2 = 1.0;              ///< exact-surface samples per cell^2 of exact surface (at the largest N)
    std::size_t volume_samples = 4000000;        ///< quasi-random points for the reference volume
    double offset_cells = 0.0;                   ///< lattice origin at -offset_cells cells ([0, 1)); 0 puts the cube's
                                                 ///< faces on lattice nodes at N = 64, 128, 256, 0.37 in general position
    int dump_worst = 0;                          ///< > 0: print this many worst vertices of each tridex cpu-1t run
                                                 ///< with their cells' crossings (bench_accuracy_dump.hpp)
    bool plots = true;                           ///< write accuracy_<program>.png via gnuplot when installed
    /// Group depths (1..6) whose coarse levels (read every 2^d-th ray) are measured against the exact solid after
    /// each program's first tridex path (bench_accuracy_coarse.hpp); empty: none.
    std::vector<int> coarse_depths{1, 2, 3, 4};
    std::string out = "out/bench";               ///< folder for bench.json
};

/// For each program, N and path: carves the 0.1 m box workpiece (lattice 0.128 m, N cells) with the
/// program, times the Booleans (per segment) and the re-contour of the dirty tiles, then measures the
/// contoured mesh against the exact solid (ExactSolid): |sdf| at vertices, exact surface samples ->
/// mesh, two-sided Hausdorff, and the dexel volume against the reference volume. Paths: tridex "cpu-1t"
/// (apply_sweep, one thread), tridex "cpu" (apply_sweeps_parallel on std::thread::hardware_concurrency()
/// threads, batches of 64; the same dexels as "cpu-1t" bit for bit), tridex "gpu" (GpuSculptor, batches
/// of 64; skipped without Vulkan), and
/// "openvdb" "cpu-1t" (bench_accuracy_openvdb.hpp) when built with OpenVDB, at the same N. Prints a table
/// (errors in metres and cells), the targets (max vertex error <= 0.45 cells; |volume error| < 0.1 % at
/// N = 256) and, for every OpenVDB run, the fastest tridex run per path whose max error is at most
/// OpenVDB's, with the worst such time ratio per program (bench_accuracy_match.hpp); writes bench.json
/// ({"runs": [...], "matched": [...], "setup": {...}}) into options.out and returns the rows; with
/// options.plots also accuracy_<program>.png (bench_accuracy_plot.hpp). With options.coarse_depths, the coarse group
/// levels of the first tridex path's model at those depths are measured against the exact solid too (printed, and in
/// bench.json "coarse": per program, N and depth, the groups' errors in metres and coarse cells). Throws
/// tridex::Error on bad options (resolutions, offset, unknown program, a coarse depth outside 1..6) or an unwritable
/// folder.
std::vector<AccuracyRow> run_accuracy_bench(const AccuracyBenchOptions& options);

}  // namespace tridex::bench
