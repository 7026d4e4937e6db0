// bench/bench_haptics.hpp - `tridex bench --haptics`: haptic tick compute time against model
// resolution and number of contact points.
#pragma once

#include <string>
#include <vector>

namespace tridex::bench {

/// One benchmark row: per-tick contact computation at one resolution and point count.
struct HapticsBenchRow {
    int n = 0;               ///< lattice cells along the workpiece's longest side
    int points = 0;          ///< contact points on the tool
    double median_us = 0.0;  ///< per-tick compute time, us (of the best of 3 timed repeats of the same walk)
    double p99_us = 0.0;
    double max_us = 0.0;
    double contact_fraction = 0.0;  ///< share of ticks with at least one point in contact
    int stride = 1;                 ///< active-surface window stride chosen for the tool (lattice rays per window ray)
};

/// What to measure.
struct HapticsBenchOptions {
    std::string mesh;                                  ///< workpiece; empty = the bundled bunny
    std::vector<int> resolutions{128, 256, 512, 1024}; ///< N values
    std::vector<int> points{1, 2, 16, 64};             ///< point counts
    int ticks = 20000;                                 ///< timed ticks per row (after 1000 warm-up ticks)
    std::string out = "out/bench";                     ///< folder for haptics_bench.json
};

/// For each N: scan-converts the workpiece (0.3 m stock); for each tool, publishes the active surface
/// centred on the walk's centre (balls: the tool centre r - 1 mm above the surface; the 2-point wand: held
/// upright, its bottom tip 1 mm in) with the window sized for the tool (tool extent + the walk's +-3 mm),
/// then times MultiPointRenderer::update (god-object per point, sum of forces and torques) over a fixed
/// pseudo-random walk of tool poses that comes down from 10 mm above, presses into and slides over the
/// surface while swinging +-0.3 rad at 1.5 Hz, the same walk for every row. Writes haptics_bench.json (a list
/// of rows) into options.out, prints a table with the ratio of the slowest to the fastest N and of the last
/// to the first N per point count, and returns the rows. Throws tridex::Error on a bad mesh, an unwritable
/// folder, or bad options (empty lists, a resolution outside [16, 4096], points outside [1, 64], ticks < 100).
std::vector<HapticsBenchRow> run_haptics_bench(const HapticsBenchOptions& options);

}  // namespace tridex::bench
