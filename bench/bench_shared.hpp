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
    /// Late joins: minutes of one person's sculpting whose stream a joiner replays (1..60; empty: none).
    std::vector<double> join_minutes{1.0, 10.0};
};

/// What a joiner arriving after `minutes` of sculpting receives and does before it goes live.
struct LateJoinRow {
    double minutes = 0.0;
    std::uint64_t samples = 0;      ///< samples in the stream
    std::uint64_t bytes = 0;        ///< the stream's messages, bytes (the starting model's .tdx not included)
    double replay_s = 0.0;          ///< applying the stream to the starting model (the host's rules), s
    double contour_s = 0.0;         ///< contouring the model after it, s
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

/// Times late joins after each of o.join_minutes of scripted sculpting (a ball circling over the box's top face at
/// 1 kHz, a stroke every 10 s), printing a table; the rows also go into shared_late_join.json. Throws tridex::Error for
/// minutes outside 1..60.
std::vector<LateJoinRow> run_late_join_bench(const SharedBenchOptions& o);

}  // namespace tridex::bench
