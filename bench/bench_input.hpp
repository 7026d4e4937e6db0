// bench/bench_input.hpp - `tridex bench --input`: what tracked input costs on its way to a frame: the DTrack ASCII
// parse per datagram, and a datagram's trip from a loopback sender through the receiver thread to a reader.
#pragma once

#include <string>
#include <vector>

namespace tridex::bench {

/// One parse row: a kind of datagram parsed many times.
struct InputParseRow {
    std::string datagram;     ///< "head" (fr, ts, 6dcal, one 6d body), "head+flystick", "wall" (10 bodies, 2 Flysticks)
    int bytes = 0;            ///< its length, bytes
    double ns_per_datagram = 0.0;  ///< median over rounds of the mean parse time, ns
    double mb_per_s = 0.0;    ///< bytes / ns_per_datagram, MB/s
};

/// The receiver's hand-off: sender -> UDP loopback -> receiver thread (poll, parse, publish) -> a polling reader.
struct InputHandoffRow {
    int datagrams = 0;         ///< datagrams timed
    double median_us = 0.0;    ///< send to first latest() that shows it, us
    double p99_us = 0.0;
    double max_us = 0.0;
};

/// What `bench --input` measured.
struct InputBenchResult {
    std::vector<InputParseRow> parse;
    InputHandoffRow handoff;
};

/// Parses each kind of datagram 20,000 times per round for 7 rounds (devices/tracking/dtrack_parser.hpp) and
/// times 1,000 datagrams through a DTrackReceiver on 127.0.0.1 (one every 2 ms; the reader polls latest()
/// without sleeping). Writes <out>/input_bench.json ({"parse": [...], "handoff": {...}}), prints the table and
/// returns it. Throws tridex::Error when a datagram is rejected, no datagram arrives within 5 s, or the folder
/// cannot be written.
InputBenchResult run_input_bench(const std::string& out);

}  // namespace tridex::bench
