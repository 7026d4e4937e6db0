// bench/bench_filter.hpp - `tridex bench --filter`: the EWMA force filter's constant against force chatter and lag,
// with encoder quantisation and sensor noise on the simulated device (Peng et al. section 5, Fig. 7).
#pragma once

#include <string>
#include <vector>

namespace tridex::bench {

/// One filter constant.
struct FilterBenchRow {
    double alpha = 0.0;          ///< EWMA weight a of F_i = (1 - a) E_i + a F_{i-1}
    double chatter_n = 0.0;      ///< standard deviation of the force sent over the hold, N
    double raw_chatter_n = 0.0;  ///< the same of the contact force before the filter, N
    double lag_ms = 0.0;         ///< measured delay of the sent force behind the contact force on the press, ms
    double lag_theory_ms = 0.0;  ///< a / (1 - a) periods: the EWMA's low-frequency group delay, ms
};

/// What to measure.
struct FilterBenchOptions {
    std::vector<double> alphas{0.0, 0.5, 0.8, 0.9, 0.95};  ///< filter constants, [0, 1)
    double quantum_m = 0.055e-3;   ///< encoder step of the simulated device, m (the Omni's 450 dpi)
    double noise_std_m = 0.02e-3;  ///< sensor noise, m
    std::string out = "out/bench";  ///< folder for filter_bench.json and filter_bench.png
};

/// For each constant: the 1 kHz haptic loop (step mode, simulated time) and a simulated PHANTOM Omni whose hand
/// presses 3 mm into a 700 N/m wall and holds (bench_wall_press, 3 mm: 0.63 N at rest), its position quantised and noisy (seeded, the same
/// for every row) and its velocity differentiated from the measured positions. Chatter: the force's standard
/// deviation over 0.9-1.35 s of the hold (the hand still); lag: the shift (0.1 ms steps) that best aligns the sent force with the
/// contact force over the press (0.15-0.8 s). Writes filter_bench.json, filter_bench.dat/.gp and filter_bench.png
/// (gnuplot: chatter against lag, one point per constant), prints the table and returns the rows. Throws
/// tridex::Error on a constant outside [0, 1), a negative quantum or noise, or an unwritable folder.
std::vector<FilterBenchRow> run_filter_bench(const FilterBenchOptions& options);

}  // namespace tridex::bench
