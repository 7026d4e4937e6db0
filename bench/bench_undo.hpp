// bench/bench_undo.hpp - `tridex bench --undo`: per-stroke undo and redo latency of a real sculpt thread, on the
// CPU and GPU sculpting paths.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace tridex::bench {

/// One row: one resolution on one sculpting path, `strokes` grooves carved, then each undone and redone once.
struct UndoBenchRow {
    int n = 0;                         ///< lattice cells along the workpiece's longest side
    std::string path;                  ///< "cpu" or "gpu" (where the Booleans and the write-backs ran)
    std::size_t strokes = 0;           ///< strokes carved (undo steps the history held)
    std::size_t segments = 0;          ///< swept segments per stroke
    double rays_median = 0.0;          ///< rays written back per undo, median
    double undo_median_ms = 0.0, undo_p95_ms = 0.0, undo_max_ms = 0.0;  ///< per undo (SculptStats::undo_ms), ms
    double redo_median_ms = 0.0, redo_max_ms = 0.0;                     ///< per redo, ms
    /// Per undo and redo, median: history write-back + active-surface publish, and dirty-tile re-contour, ms.
    double restore_median_ms = 0.0, contour_median_ms = 0.0;
    double history_bytes_per_stroke = 0.0;  ///< the history's bytes after the redos / strokes held
    double target_ms = 0.0;            ///< 16 (one 60 Hz frame) at N = 256; 0 = no target for this N
    /// Every undo and redo (max) within target_ms; false when there is no target or no undo or redo was timed.
    bool target_met = false;
};

/// What to measure.
struct UndoBenchOptions {
    std::vector<int> resolutions{256, 512};        ///< N values
    std::vector<std::string> paths{"cpu", "gpu"};  ///< sculpting paths
    int strokes = 8;                               ///< grooves carved, then undone and redone
    int segments = 300;                            ///< swept segments per groove
    std::string mesh;                              ///< workpiece; empty = the bundled bunny
    std::string out = "out/bench";                 ///< folder for undo_bench.json
};

/// For each N and path: the workpiece scan-converted (0.3 m stock, as the demo), contoured on the CPU, and a real
/// SculptThread (the CPU reference or the GPU Boolean backend, Vulkan validation off; CPU contouring, as a session
/// on lavapipe) fed `strokes` grooves across the workpiece's top (an 8 mm ball 3 mm deep following the surface,
/// `segments` segments each, tool lifted between grooves). When they are applied, every stroke is undone
/// (SculptRequest::kUndo), then every one redone, and SculptStats::undo_ms gives each one's latency: history write
/// back + active-surface extraction + dirty-tile re-contour. Prints a table and writes <out>/undo_bench.json
/// ({"rows": [...], "setup": {...}}). GPU rows are skipped, with the reason printed, without a Vulkan device.
/// Throws tridex::Error on bad options.
std::vector<UndoBenchRow> run_undo_bench(const UndoBenchOptions& options);

}  // namespace tridex::bench
