// bench/bench_persistence.hpp - `tridex bench --persistence`: saving and loading the model file (.tdx) of a
// carved workpiece: time, file size against the model's size in memory.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace tridex::bench {

/// One row: one resolution, saved and loaded once (after a warm-up save).
struct PersistenceBenchRow {
    int n = 0;                      ///< lattice cells along the workpiece's longest side
    std::size_t intervals = 0;      ///< intervals in the three ray sets
    std::size_t segments = 0;       ///< stroke segments carved before saving
    double removed_m3 = 0.0;        ///< volume the stroke removed (dexel volumes), m^3
    double save_s = 0.0;            ///< compute::save_tdx wall time (encode, zstd, write, fsync, rename), s
    double load_s = 0.0;            ///< compute::load_tdx wall time (read, zstd, checks, model), s
    std::size_t file_bytes = 0;     ///< size of the .tdx file
    std::size_t memory_bytes = 0;   ///< the CPU model's rays and intervals in memory (cpu_model_bytes), bytes
    double ratio = 0.0;             ///< file_bytes / memory_bytes
    bool identical = false;         ///< the loaded model equals the saved one bit for bit
};

/// What to measure.
struct PersistenceBenchOptions {
    std::vector<int> resolutions{256, 512};  ///< N values
    std::string mesh;                        ///< workpiece; empty = the bundled bunny
    std::string out = "out/bench";           ///< folder for persistence_bench.json and the .tdx files
};

/// For each N: the workpiece scan-converted (0.3 m stock, as the demo) and carved by the demo's stroke (an 8 mm
/// ball swept between plan_stroke's waypoints, on the CPU), then saved to <out>/bench_N.tdx and loaded back; prints a table
/// and writes <out>/persistence_bench.json ({"rows": [...], "setup": {...}}). Throws tridex::Error on bad input.
std::vector<PersistenceBenchRow> run_persistence_bench(const PersistenceBenchOptions& options);

}  // namespace tridex::bench
