// bench/bench_filter.cpp - a noisy press into the wall per filter constant; chatter and lag from the tick records.
#include "bench/bench_filter.hpp"
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "app/support/json_file.hpp"
#include "bench/bench_wall.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "devices/simulated_device.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions, stats and JSON files

namespace {

constexpr double kDt = 1e-3;
constexpr std::size_t kTicks = 1600;

double stddev(const std::vector<double>& v) {
    if (v.size() < 2) return 0.0;
    double m = 0.0;
    for (double x : v) m += x;
    m /= static_cast<double>(v.size());
    double s = 0.0;
    for (double x : v) s += (x - m) * (x - m);
    return std::sqrt(s / static_cast<double>(v.size() - 1));
}

// Linear interpolation of v at fractional index i (clamped).
double at(const std::vector<double>& v, double i) {
    if (i <= 0.0) return v.front();
    const auto k = static_cast<std::size_t>(i);
    if (k + 1 >= v.size()) return v.back();
    const double f = i - static_cast<double>(k);
    return (1.0 - f) * v[k] + f * v[k + 1];
}

FilterBenchRow run_alpha(double alpha, const FilterBenchOptions& o) {
    devices::SimulatedHandParams hand;
    hand.substeps = 10;
    devices::SimulatedDevice device(devices::DeviceProfile::phantom_omni(), bench_wall_press(0.003), hand, kDt);
    devices::SensorModel sensor;
    sensor.quantum_m = o.quantum_m;
    sensor.noise_std_m = o.noise_std_m;
    sensor.seed = 7;
    device.set_sensor(sensor);
    TripleBuffer<ActiveSurface> surface;
    surface.back() = *bench_wall_surface();
    surface.publish();
    SpscRing<ToolSample> samples(kTicks + 16);
    haptics::HapticLoopConfig cfg;
    cfg.contact.stiffness_n_per_m = 700.0;
    cfg.contact.damping_n_s_per_m = 0.5;
    cfg.ewma_alpha = alpha;
    cfg.request_realtime = false;
    cfg.max_ticks = kTicks;
    haptics::HapticLoop loop(device, surface, samples, cfg);
    for (std::size_t k = 0; k < kTicks; ++k) loop.step(static_cast<double>(k + 1) * kDt);
    loop.stop();
    const std::vector<haptics::TickRecord>& recs = loop.records();
    std::vector<double> sent, raw, hold_sent, hold_raw;
    for (const haptics::TickRecord& r : recs) {
        sent.push_back(r.force_n.z);
        raw.push_back(r.points[0].force_n.z);
        if (r.device.t_s >= 0.9 && r.device.t_s <= 1.35) {
            hold_sent.push_back(r.force_n.z);
            hold_raw.push_back(r.points[0].force_n.z);
        }
    }
    FilterBenchRow row;
    row.alpha = alpha;
    row.chatter_n = stddev(hold_sent);
    row.raw_chatter_n = stddev(hold_raw);
    row.lag_theory_ms = alpha / (1.0 - alpha) * kDt * 1e3;
    // The shift (ticks, in 0.1 steps up to 100 ms) minimising the squared difference between the sent force and the
    // shifted contact force over the press.
    const auto k0 = static_cast<std::size_t>(0.15 / kDt), k1 = static_cast<std::size_t>(0.8 / kDt);
    double best = std::numeric_limits<double>::infinity();
    for (int s10 = 0; s10 <= 1000; ++s10) {
        const double shift = s10 * 0.1;
        double e = 0.0;
        for (std::size_t k = k0; k < k1 && k < sent.size(); ++k) {
            const double d = sent[k] - at(raw, static_cast<double>(k) - shift);
            e += d * d;
        }
        if (e < best) {
            best = e;
            row.lag_ms = shift * kDt * 1e3;
        }
    }
    return row;
}

void write_plot(const std::vector<FilterBenchRow>& rows, const std::string& out) {
    if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
        std::printf("plot skipped: gnuplot not found (Debian gnuplot-nox)\n");
        return;
    }
    const std::filesystem::path dir(out);
    const std::string dat = (dir / "filter_bench.dat").string(), gp = (dir / "filter_bench.gp").string(),
                      png = (dir / "filter_bench.png").string();
    std::ofstream d(dat), g(gp);
    if (!d || !g) throw Error(dat + ": cannot open for writing");
    d << "# lag_ms chatter_n alpha raw_chatter_n\n";
    for (const FilterBenchRow& r : rows) d << r.lag_ms << " " << r.chatter_n << " " << r.alpha << " " << r.raw_chatter_n << "\n";
    d.close();
    g << "set terminal pngcairo size 800,560\nset output '" << png << "'\n"
      << "set title 'bench --filter: EWMA force filter, chatter against lag (labels: a)'\n"
      << "set xlabel 'lag of the sent force, ms'\nset ylabel 'force chatter (std over the hold), N'\nset grid\n"
      << "set key top right\nset offsets 0.5, 0.5, 0, 0\n"
      << "plot '" << dat << "' using 1:2 with linespoints pt 7 title 'sent force', '' using 1:2:3 with labels offset 1.5,0.8 "
      << "notitle, '' using 1:4 with lines dt 2 title 'contact force before the filter'\n";
    g.close();
    if (std::system(("gnuplot '" + gp + "' > /dev/null 2>&1").c_str()) == 0) std::printf("wrote %s\n", png.c_str());
    else std::printf("plot: gnuplot failed (%s)\n", gp.c_str());
}

}  // namespace

std::vector<FilterBenchRow> run_filter_bench(const FilterBenchOptions& o) {
    if (o.alphas.empty()) throw Error("bench --filter: no filter constants to run");
    for (double a : o.alphas)
        if (!(a >= 0.0 && a < 1.0)) throw Error("bench --filter: filter constant " + format_number(a) + " is not in [0, 1)");
    if (!(o.quantum_m >= 0.0) || !(o.noise_std_m >= 0.0)) throw Error("bench --filter: quantum and noise must be >= 0");
    std::filesystem::create_directories(o.out);
    std::vector<FilterBenchRow> rows;
    std::printf("encoder step %.3f mm, sensor noise %.3f mm (std), 700 N/m wall, 1 kHz\n", o.quantum_m * 1e3,
                o.noise_std_m * 1e3);
    std::printf("%6s %11s %15s %8s %14s\n", "alpha", "chatter_N", "raw_chatter_N", "lag_ms", "lag_theory_ms");
    nlohmann::json j = nlohmann::json::array();
    for (double a : o.alphas) {
        const FilterBenchRow r = run_alpha(a, o);
        std::printf("%6.2f %11.4f %15.4f %8.1f %14.1f\n", r.alpha, r.chatter_n, r.raw_chatter_n, r.lag_ms, r.lag_theory_ms);
        rows.push_back(r);
        j.push_back({{"alpha", r.alpha},
                     {"chatter_n", r.chatter_n},
                     {"raw_chatter_n", r.raw_chatter_n},
                     {"lag_ms", r.lag_ms},
                     {"lag_theory_ms", r.lag_theory_ms}});
    }
    const std::string path = (std::filesystem::path(o.out) / "filter_bench.json").string();
    nlohmann::json doc = {{"quantum_m", o.quantum_m}, {"noise_std_m", o.noise_std_m}, {"rows", j}};
    write_json_file(path, doc);
    std::printf("wrote %s\n", path.c_str());
    write_plot(rows, o.out);
    return rows;
}

namespace {

BenchRun setup_filter_bench(CLI::App&) {
    return [](const BenchCommon& c) {
        FilterBenchOptions o;
        o.out = c.out;
        run_filter_bench(o);
    };
}

const BenchmarkRegistration kRegistration{
    {"filter",
     "EWMA force filter constant: chatter amplitude vs lag with encoder quantisation and noise (filter_bench.json, "
     "filter_bench.png)",
     30, setup_filter_bench}};

}  // namespace

}  // namespace tridex::bench
