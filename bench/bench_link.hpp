// bench/bench_link.hpp - `tridex bench --link`: local against distributed haptic rendering through a link with
// injected latency and loss (Popescu, Burdea, Bouzit, section 2), a stiff wall pressed by the simulated hand.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tridex::bench {

/// One run: a rendering mode through a link of one latency and loss.
struct LinkBenchRow {
    std::string mode;                 ///< "distributed" or "local"
    double latency_ms = 0.0;          ///< injected one-way latency, ms
    double loss = 0.0;                ///< injected loss probability of unreliable datagrams
    double rate_hz = 0.0;             ///< new force values reaching the device per second of the run
    double max_penetration_m = 0.0;   ///< deepest the stylus went into the wall, m
    double force_rms_error_n = 0.0;   ///< RMS, over the device's steps, of the force against the same mode's 0 ms, 0-loss run, N
    double passivity_energy_j = 0.0;  ///< -sum F.v dt over the run, the stylus out of the wall at the end (< 0: energy created), J
    double hold_force_p2p_n = 0.0;    ///< peak-to-peak force over the last 0.4 s of the hold, N (oscillation)
    bool stable = false;              ///< passivity_energy_j > -1 mJ and hold_force_p2p_n < 0.2 N
    double rtt_median_us = 0.0;       ///< the session's measured round trip, median, us
    std::uint64_t lost = 0;           ///< datagrams lost, both ways
};

/// What to measure.
struct LinkBenchOptions {
    std::vector<double> latencies_ms{0.0, 1.0, 5.0, 10.0, 20.0};  ///< one-way latencies, ms (0..200)
    std::vector<double> losses{0.0, 0.01, 0.05};                   ///< loss probabilities, [0, 0.5]
    double stiffness_n_per_m = 700.0;  ///< the wall's stiffness, N/m (the Omni's stable 0.7 N/mm at 1 kHz)
    /// How far into the wall the hand's target goes, m: 1 mm, a light press (0.21 N at rest, 0.3 mm in).
    double press_depth_m = 0.001;
    std::string out = "out/bench";      ///< folder for link_bench.json
};

/// For each mode, latency and loss: a DeviceServer with a simulated PHANTOM Omni (its hand going from 10 mm above a
/// wall at z = 0 to press_depth_m into it in 0.3 s, holding until 1.5 s, out again by 1.8 s, 2 s in all:
/// bench_wall_press) and a
/// session's net driver and haptic loop (step mode) joined by the in-process link shim on one simulated clock
/// (1 ms ticks), so every run is deterministic. Distributed: the session's loop computes the force from the states
/// it receives; local: the server's loop does, from the snapshot the session sent. Writes link_bench.json (rows) into
/// options.out, prints the table and returns the rows. Throws tridex::Error on bad options or an unwritable folder.
std::vector<LinkBenchRow> run_link_bench(const LinkBenchOptions& options);

}  // namespace tridex::bench
