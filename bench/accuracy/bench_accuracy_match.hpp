// bench/accuracy/bench_accuracy_match.hpp - `tridex bench --accuracy`: tridex against OpenVDB at matched error.
#pragma once

#include <string>
#include <vector>

#include "bench/accuracy/bench_accuracy.hpp"

namespace tridex::bench::accuracy {

/// One OpenVDB run and, for one tridex path, the fastest tridex run of the same program (any N) whose
/// maximum vertex error is at most the OpenVDB run's.
struct MatchedRun {
    std::string program;      ///< program name
    std::string path;         ///< tridex path ("cpu-1t", "cpu", "gpu")
    int openvdb_n = 0;        ///< N of the OpenVDB run
    double openvdb_max_error_m = 0.0;  ///< its max vertex error, m
    double openvdb_time_s = 0.0;       ///< its time per segment, s
    int tridex_n = 0;         ///< N of the matched tridex run (0: no tridex run of this path is as accurate)
    double tridex_max_error_m = 0.0;   ///< its max vertex error, m (0 when unmatched)
    double tridex_time_s = 0.0;        ///< its time per segment, s (0 when unmatched)
    double ratio = 0.0;       ///< openvdb_time_s / tridex_time_s (> 1: tridex faster); 0 when unmatched
};

/// Pairs every OpenVDB row of `rows` with, per tridex path present for that program, the fastest tridex
/// row (smallest time_per_segment_s, ties: smaller N) of the same program whose max_error_m is at most
/// the OpenVDB row's. Rows with a non-positive time are ignored. Output order: the OpenVDB rows' order,
/// paths in order of first appearance. Pure; O(rows^2).
std::vector<MatchedRun> match_openvdb(const std::vector<AccuracyRow>& rows);

/// Worst (smallest) ratio over the matched runs of one program and path; 0 when any OpenVDB run of them
/// has no tridex run as accurate (unmatched), -1 when there is no run of that program and path.
double worst_ratio(const std::vector<MatchedRun>& matched, const std::string& program, const std::string& path);

/// Prints the matched runs and the worst ratio per program and path.
void print_matched(const std::vector<MatchedRun>& matched);

}  // namespace tridex::bench::accuracy
