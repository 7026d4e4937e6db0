// app/stats.hpp - order statistics of timing samples for reports.
#pragma once

#include <vector>

namespace tridex::app {

/// Median, 99th percentile and maximum of a sample (nearest-rank percentiles); zeros when empty.
struct Summary {
    double median = 0.0;
    double p99 = 0.0;
    double max = 0.0;
    double mean = 0.0;
};

/// Summarises `values` (any unit; the result has the same unit). Takes a copy to sort.
Summary summarize(std::vector<double> values);

}  // namespace tridex::app
