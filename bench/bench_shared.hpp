// bench/bench_shared.hpp - `tridex bench --shared`: a shared session's host and one joiner in this process over the link
// shim at several one-way delays with loss, then over ENet with the host's haptic loop while random datagrams flood
// its port (docs/benchmarks/shared.md).
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
    /// Each phase of the flood run (a haptic loop beside a real ENet session, quiet then flooded), s (0: skip it;
    /// else 0.5..600).
    double flood_s = 5.0;
};

/// What a joiner arriving after `minutes` of sculpting receives and does before it goes live.
struct LateJoinRow {
    double minutes = 0.0;
    std::uint64_t samples = 0;      ///< samples in the stream
    std::uint64_t bytes = 0;        ///< the stream's messages, bytes (the starting model's .tdx not included)
    double replay_s = 0.0;          ///< applying the stream to the starting model (the host's rules), s
    double contour_s = 0.0;         ///< contouring the model after it, s
    std::uint64_t model_bytes = 0;  ///< the model as it stands after the stream, as a .tdx file (zstd sections), bytes
    /// The undo history's before-images after the stream (the host's rules and budget), bytes: what a joiner sent the
    /// model as it stands would need besides, to follow undos of strokes made before it joined.
    std::uint64_t history_bytes = 0;
    std::uint64_t packed_history_bytes = 0;  ///< the history as the welcome carries it (zstd), bytes
    double snapshot_s = 0.0;   ///< the host's snapshot: the model copied, the history saved, the .tdx written, packed, s
    double join_load_s = 0.0;  ///< the joiner's load of the .tdx and the history, and its contour, s
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

/// One phase of the flood run: a fresh shared session over ENet on the loopback, a 1 kHz haptic loop at the host
/// carving, the joiner carving a groove, and (in the flood phase) random datagrams sent at the host's port.
struct SharedFloodRow {
    std::string phase;              ///< "quiet" or "flood"
    double seconds = 0.0;           ///< the phase's wall time, s
    std::size_t ticks = 0;          ///< the host's haptic ticks
    double period_p99_ms = 0.0;     ///< a bound of the haptic period's 99th percentile (its histogram's bin), ms
    double worst_ms = 0.0;          ///< the longest haptic period, ms
    std::size_t over_5ms = 0;       ///< haptic periods over 5 ms
    std::size_t overruns = 0;       ///< haptic ticks that ended after the next deadline
    std::size_t samples_dropped = 0;  ///< haptic samples the host's ring had no room for
    bool cyclictest_ran = false;    ///< cyclictest ran beside the phase and gave its figure
    double cyclictest_max_ms = 0.0; ///< its largest wake-up latency (SCHED_OTHER, 1 ms interval), ms
    std::uint64_t flooded = 0;      ///< datagrams the flood sent (sendto succeeded)
    std::uint64_t hub_datagrams = 0;  ///< datagrams the hub's socket received
    std::uint64_t hub_foreign = 0;  ///< of them, from an address of no peer of the hub (ENet discards them)
    std::uint64_t kernel_drops = 0; ///< datagrams the kernel dropped at the hub's socket (its buffer full)
    std::uint64_t sealed_refused = 0;  ///< datagrams both sealed links refused (host's of the joiner, joiner's)
    std::uint64_t peers_refused = 0;   ///< peers the host refused (handshake failed)
    std::uint64_t hub_refused = 0;  ///< connects the hub refused (all its places taken)
    bool digests_equal = false;     ///< both models equal at the end, and the joiner's check of the host's final digest
    bool carved = false;            ///< the haptic loop's samples changed the host's model
};

/// Runs every delay: both sites carve a groove at once, then the joiner alone, then the host alone, each at 1 kHz on
/// the wall clock; prints the table and writes shared_bench.json. Throws tridex::Error on an option out of range.
std::vector<SharedBenchRow> run_shared_bench(const SharedBenchOptions& o);

/// Times late joins after each of o.join_minutes of scripted sculpting (a ball circling over the box's top face at
/// 1 kHz, a stroke every 10 s), printing a table; the rows also go into shared_late_join.json. Throws tridex::Error for
/// minutes outside 1..60.
std::vector<LateJoinRow> run_late_join_bench(const SharedBenchOptions& o);

/// The haptic period while the link floods: runs a quiet phase and a flooded one of o.flood_s each (nothing when
/// o.flood_s is 0), each a host (EnetHub on 127.0.0.1, SharedHost) and one joiner (EnetLink, SharedJoin) sealed with
/// one key, as `tridex run --host` and `--join` build them, with cyclictest beside when it is on PATH; prints a table
/// and writes shared_flood.json. Throws tridex::Error for o.flood_s out of range, and what the session throws (a
/// socket that cannot open, a join that fails).
std::vector<SharedFloodRow> run_shared_flood_bench(const SharedBenchOptions& o);

}  // namespace tridex::bench
