// bench/bench_shared.hpp - `tridex bench --shared`: a shared session's host and one joiner in this process over the link
// shim at several one-way delays with loss (docs/benchmarks/shared.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/duration_histogram.hpp"

namespace tridex::bench {

/// What to measure.
struct SharedBenchOptions {
    std::vector<double> delays_ms{0.0, 10.0, 50.0, 150.0};  ///< one-way delays, ms (0..1000)
    double loss = 0.01;        ///< loss of unreliable datagrams, [0, 0.5)
    double stroke_s = 2.0;     ///< each groove's length, s (0.2..60)
    int resolution = 96;       ///< the box's cells along a side
    std::string out = "out/bench";  ///< folder for shared_bench.json
};

/// One delay: latencies (sample pushed -> mesh with its cut published, ms), bytes per second, digests.
struct SharedBenchRow {
    double delay_ms = 0.0;
    DurationHistogram own_host = DurationHistogram::latency();       ///< the host's own cut, at the host
    DurationHistogram own_join = DurationHistogram::latency();       ///< the joiner's own cut, at the joiner
    DurationHistogram other_at_host = DurationHistogram::latency();  ///< the joiner's cut, at the host
    DurationHistogram other_at_join = DurationHistogram::latency();  ///< the host's cut, at the joiner
    double host_out_bps = 0.0;  ///< bytes per second the host sent the joiner
    double join_out_bps = 0.0;  ///< bytes per second the joiner sent the host
    bool digests_equal = false; ///< both models equal at the end, and the joiner's check of the host's final digest
    std::uint64_t lost = 0;     ///< unreliable datagrams the shim dropped
};

/// Runs every delay: both sites carve a groove at once, then the joiner alone, then the host alone, each at 1 kHz on
/// the wall clock; prints the table and writes shared_bench.json. Throws tridex::Error on an option out of range.
std::vector<SharedBenchRow> run_shared_bench(const SharedBenchOptions& o);

}  // namespace tridex::bench
