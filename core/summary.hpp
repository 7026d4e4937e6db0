// core/summary.hpp - order statistics of timing samples for reports and benchmarks.
#pragma once

#include <vector>

namespace tridex {

/// Median, 99th percentile, maximum and mean of a sample (nearest-rank percentiles); zeros when empty.
struct Summary {
    double median = 0.0;
    double p99 = 0.0;
    double max = 0.0;
    double mean = 0.0;
};

/// Summarises `values` (any unit; the result has the same unit). Takes a copy to sort. The values must
/// be finite (timings are); a NaN makes the order, and so the result, unspecified.
Summary summarize(std::vector<double> values);

}  // namespace tridex
