// bench/bench_contour.hpp - `tridex bench --contour`: the re-contour after each step of a carving stroke, with
// the dirty marks of the swept box and whole tiles, of the swept box and partial tiles, and of the changed
// interval ends and partial tiles (the session's), in one run.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace tridex::bench {

/// One row: one resolution and one way of marking what to re-contour.
struct ContourBenchRow {
    int n = 0;              ///< lattice cells along the workpiece's longest side
    std::string marks;      ///< "swept box, whole tiles", "swept box, partial tiles" or "changed ends, partial tiles"
    std::size_t steps = 0;  ///< carving steps (one sweep and one Contourer::update each)
    std::size_t idle_steps = 0;                           ///< ... that changed no ray (nothing to re-contour)
    double tiles_per_step = 0.0;                          ///< tiles re-contoured per step (mean)
    double partial_per_step = 0.0;                        ///< ... of which partial (mean)
    double cells_per_step = 0.0;                          ///< non-uniform cells visited per step (mean)
    double ms_median = 0.0, ms_p99 = 0.0, ms_mean = 0.0;  ///< Contourer::update per step, ms (p99: nearest rank)
    double ratio_to_whole = 0.0;  ///< ms_mean of the first row of this N (swept box, whole tiles) over this row's
    bool same_mesh = false;       ///< the final mesh equals the first row's, bit for bit
};

/// What to measure.
struct ContourBenchOptions {
    std::vector<int> resolutions{128, 256};  ///< N values
    std::string mesh;                        ///< workpiece; empty = the bundled bunny
    std::string out = "out/bench";           ///< folder for contour_bench.json
};

/// For each N: the workpiece as the default scene places it (0.12 m stock) and the default scene's stroke (a 6 mm
/// ball 4 mm below the front surface, dragged along x from -45 to +45 mm in 0.5 mm steps). Every step applies one
/// sweep on the CPU and re-contours, timed, in three runs from the same model: marking the sweep's swept box and
/// re-contouring dirty tiles whole (the way before partial tiles), marking the swept box with partial tiles, and
/// marking the changed interval ends with partial tiles (what a session does). Prints a table and writes
/// <out>/contour_bench.json ({"rows": [...], "setup": {...}}). Throws tridex::Error on bad options (N < 16).
std::vector<ContourBenchRow> run_contour_bench(const ContourBenchOptions& options);

}  // namespace tridex::bench
