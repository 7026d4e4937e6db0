// bench/accuracy/bench_accuracy_plot.hpp - PNG plots of `tridex bench --accuracy` through gnuplot (when installed).
#pragma once

#include <string>
#include <vector>

#include "bench/accuracy/bench_accuracy.hpp"

namespace tridex::bench::accuracy {

/// For each program with geometry change (not paint): writes accuracy_<program>.dat (one block per
/// method/path: max_error_m, time_per_segment_s, n) and accuracy_<program>.gp into `out`, and runs
/// `gnuplot` on it to make accuracy_<program>.png (time per segment against max vertex error, log-log,
/// one line per method and path). Returns the PNG paths written; returns none (and prints why) when
/// gnuplot is not on PATH or fails. Throws tridex::Error when a data file cannot be written.
std::vector<std::string> write_accuracy_plots(const std::vector<AccuracyRow>& rows, const std::string& out);

}  // namespace tridex::bench::accuracy
