// bench/bench_session.cpp - whole sessions through the runtime, timed from their reports.
#include "bench/bench_session.hpp"
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/commands/demo/demo.hpp"
#include "app/support/json_file.hpp"
#include "app/support/output_dir.hpp"
#include "core/error.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions, stats and JSON files

std::vector<SessionBenchRow> run_session_bench(const SessionBenchOptions& o) {
    if (o.resolutions.empty() || o.paths.empty() || o.journal.empty()) throw Error("bench --session: nothing to run");
    for (const std::string& p : o.paths)
        if (p != "cpu" && p != "gpu") throw Error("bench --session: unknown path '" + p + "'; use cpu or gpu");
    prepare_output_dir(o.out, "--out");
    std::vector<SessionBenchRow> rows;
    std::printf("session benchmark: the demo's %.1f s stroke on the bunny, through the session runtime\n", o.seconds);
    std::printf("%6s %5s %4s %7s %10s %10s %10s %10s %9s %10s %10s %10s %10s %8s %8s %7s %8s\n", "N", "path", "jnl",
                "ticks", "period50", "period99", "tick50", "tick99", "booleans", "bool50", "bool99", "contour50",
                "contour99", "busy", "jnl", "jnl%", "wall");
    std::printf("%6s %5s %4s %7s %10s %10s %10s %10s %9s %10s %10s %10s %10s %8s %8s %7s %8s\n", "", "", "", "", "us",
                "us", "us", "us", "", "ms", "ms", "ms", "ms", "ms", "ms", "", "s");
    for (const int n : o.resolutions)
        for (const std::string& path : o.paths)
        for (const bool journal : o.journal) {
            DemoOptions d;
            d.resolution = n;
            d.seconds = o.seconds;
            d.width = 64;
            d.height = 48;
            d.cpu = path == "cpu";  // each path forced: the device's type decides neither row
            d.gpu = path == "gpu";
            d.no_journal = !journal;
            d.out = (std::filesystem::path(o.out) /
                     ("session_" + std::to_string(n) + "_" + path + (journal ? "" : "_nojournal"))).string();
            run_demo(d);
            std::ifstream in(std::filesystem::path(d.out) / "report.json");
            const nlohmann::json j = nlohmann::json::parse(in);
            SessionBenchRow r;
            r.n = n;
            r.path = j.at("sculpt_path").get<std::string>();
            r.ticks = j.at("ticks").get<std::size_t>();
            r.period_p50_us = j.at("period_us").at("median").get<double>();
            r.period_p99_us = j.at("period_us").at("p99").get<double>();
            r.compute_p50_us = j.at("tick_compute_us").at("median").get<double>();
            r.compute_p99_us = j.at("tick_compute_us").at("p99").get<double>();
            r.booleans = j.at("booleans").get<std::size_t>();
            r.boolean_p50_ms = j.at("sculpt").at("boolean_ms").at("median").get<double>();
            r.boolean_p99_ms = j.at("sculpt").at("boolean_ms").at("p99").get<double>();
            r.contour_p50_ms = j.at("sculpt").at("contour_ms").at("median").get<double>();
            r.contour_p99_ms = j.at("sculpt").at("contour_ms").at("p99").get<double>();
            r.volume_removed_m3 = j.at("volume_removed_m3").get<double>();
            r.wall_s = j.at("wall_s").get<double>();
            r.journal = journal;
            if (const nlohmann::json& jj = j.at("journal"); !jj.is_null()) {
                r.journal_ms = jj.at("append_ms_total").get<double>() + jj.at("flush_ms_total").get<double>();
                r.journal_sync_thread_ms = jj.value("sync_thread_ms_total", 0.0);
                r.sculpt_busy_ms = jj.at("sculpt_busy_ms_total").get<double>();
                r.journal_share = r.sculpt_busy_ms > 0.0 ? r.journal_ms / r.sculpt_busy_ms : 0.0;
            }
            std::printf("%6d %5s %4s %7zu %10.1f %10.1f %10.2f %10.2f %9zu %10.3f %10.3f %10.3f %10.3f %8.1f %8.2f %6.2f%% "
                        "%8.2f\n",
                        r.n, r.path.c_str(), journal ? "on" : "off", r.ticks, r.period_p50_us, r.period_p99_us,
                        r.compute_p50_us, r.compute_p99_us, r.booleans, r.boolean_p50_ms, r.boolean_p99_ms,
                        r.contour_p50_ms, r.contour_p99_ms, r.sculpt_busy_ms, r.journal_ms, 100.0 * r.journal_share,
                        r.wall_s);
            std::fflush(stdout);
            rows.push_back(r);
        }
    nlohmann::json out = nlohmann::json::array();
    for (const SessionBenchRow& r : rows)
        out.push_back({{"n", r.n},
                       {"path", r.path},
                       {"ticks", r.ticks},
                       {"period_p50_us", r.period_p50_us},
                       {"period_p99_us", r.period_p99_us},
                       {"tick_compute_p50_us", r.compute_p50_us},
                       {"tick_compute_p99_us", r.compute_p99_us},
                       {"booleans", r.booleans},
                       {"boolean_p50_ms", r.boolean_p50_ms},
                       {"boolean_p99_ms", r.boolean_p99_ms},
                       {"contour_p50_ms", r.contour_p50_ms},
                       {"contour_p99_ms", r.contour_p99_ms},
                       {"journal", r.journal},
                       {"journal_ms", r.journal_ms},
                       {"journal_sync_thread_ms", r.journal_sync_thread_ms},
                       {"sculpt_busy_ms", r.sculpt_busy_ms},
                       {"journal_share", r.journal_share},
                       {"volume_removed_m3", r.volume_removed_m3},
                       {"wall_s", r.wall_s}});
    write_json_file((std::filesystem::path(o.out) / "session_bench.json").string(), out);
    if (!o.latency_resolutions.empty()) run_latency_bench(o);
    return rows;
}

namespace {

struct SessionBenchCli {
    std::vector<int> n;
    bool journal_off = false;
};

BenchRun setup_session_bench(CLI::App& bench) {
    auto o = std::make_shared<SessionBenchCli>();
    bench.add_option("--session-n", o->n, "With --session: run only these N, e.g. --session-n 256 (the latency rows too)")->delimiter(',');
    bench.add_flag("--session-journal-off", o->journal_off,
                   "With --session: also run each session without its journal (--no-journal), for comparison");
    return [o](const BenchCommon& c) {
        SessionBenchOptions sb;
        sb.out = c.out;
        if (!o->n.empty()) sb.resolutions = sb.latency_resolutions = o->n;
        if (o->journal_off) sb.journal = {true, false};
        run_session_bench(sb);
    };
}

const BenchmarkRegistration kRegistration{
    {"session",
     "Whole sessions through the session runtime (the demo's stroke on the bunny, N = 256 and 512, CPU and GPU "
     "paths): haptic period and tick time, sculpt step times; and the time from a tool sample to the surface drawn "
     "for a subtract and a clay push at 0.1 m/s (N = 256), beside the push target",
     40, setup_session_bench}};

}  // namespace

}  // namespace tridex::bench
