// bench/bench_islands.hpp - `tridex bench --islands`: the speck search at a stroke's end (compute::find_islands
// through app::SculptHistory) after a deep cut across the bunny, per resolution.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace tridex::bench {

/// One row: one resolution.
struct IslandBenchRow {
    int n = 0;                   ///< lattice cells along the workpiece's longest side
    std::size_t sweeps = 0;      ///< swept segments of the cut
    std::size_t box_nodes = 0;   ///< lattice nodes in the searched box (the cut's swept box grown by r + 2 cells)
    std::size_t nodes = 0;       ///< of those, inside material
    std::size_t pieces = 0;      ///< pieces in the box
    std::size_t specks = 0;      ///< specks removed at the stroke's end
    double speck_volume_m3 = 0.0;  ///< their volume, m^3
    std::size_t parts_before = 0;  ///< parts of the contoured mesh before the removal
    std::size_t parts_after = 0;   ///< and after
    double end_stroke_ms = 0.0;  ///< the search and the removal in SculptHistory::end_stroke, ms
    double search_median_ms = 0.0, search_max_ms = 0.0;  ///< find_islands on the box again, repeated, ms
    /// find_islands on the whole lattice (the worst case: a stroke whose box holds the whole workpiece), median, ms.
    double whole_median_ms = 0.0;
};

/// What to measure.
struct IslandBenchOptions {
    std::vector<int> resolutions{128, 256, 512};  ///< N values
    int repeats = 15;                             ///< find_islands repetitions per N
    std::string mesh;                             ///< workpiece; empty = the bundled bunny
    std::string out = "out/bench";                ///< folder for islands_bench.json
};

/// For each N: the workpiece as the default scene places it (0.12 m stock), and the newcomer's deep cut: a 6 mm
/// ball pressed two radii (the mouse stylus's deepest) below the front surface (probe_top on the Z rays), dragged
/// along x from -45 to +45 mm at y = 0, one stroke through a SculptHistory on the CPU backend with speck removal
/// on. Measures the end of the stroke (search and removal, IslandRemoval::search_ms), then find_islands on the same
/// box `repeats` times on the carved model and on the whole lattice, and counts the contoured mesh's parts with the
/// specks and without them.
/// Prints a table and writes <out>/islands_bench.json ({"rows": [...], "setup": {...}}). Throws tridex::Error on
/// bad options.
std::vector<IslandBenchRow> run_islands_bench(const IslandBenchOptions& options);

}  // namespace tridex::bench
