// bench/soak/bench_soak.cpp - `tridex bench --soak MINUTES`: a long session of a scripted sculptor, read every minute.
#include "bench/soak/bench_soak.hpp"

#include "bench/bench_registry.hpp"
#include "bench/soak/bench_soak_minute.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/commands/recover/recover.hpp"
#include "app/session/run/run_session.hpp"
#include "app/support/json_file.hpp"
#include "app/support/output_dir.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::bench {

namespace {

namespace fs = std::filesystem;

nlohmann::json row_json(const SoakMinute& m) {
    return {{"minute", m.minute},
            {"t_s", m.t_s},
            {"rss_mb", m.rss_mb},
            {"heap_mb", m.heap_mb},
            {"triangles", m.triangles},
            {"journal_mb", m.journal_mb},
            {"history_mb", m.history_mb},
            {"history_budget_mb", m.history_budget_mb},
            {"frames", m.frames},
            {"frame_p50_ms", m.frame_p50_ms},
            {"frame_p99_ms", m.frame_p99_ms},
            {"ticks", m.ticks},
            {"period_p99_us", m.period_p99_us},
            {"period_worst_us", m.period_worst_us},
            {"periods_over_2ms", m.periods_over_2ms},
            {"steps", m.steps},
            {"step_p99_ms", m.step_p99_ms},
            {"fds", m.fds},
            {"threads", m.threads}};
}

void print_header() {
    std::printf("%4s %8s %8s %8s %8s %8s %6s %8s %8s %7s %8s %8s %5s %6s %8s %4s %4s\n", "min", "rss", "heap", "tri", "journal", "undo",
                "frames", "frame50", "frame99", "ticks", "period99", "worst", ">2ms", "steps", "step99", "fds", "thr");
    std::printf("%4s %8s %8s %8s %8s %8s %6s %8s %8s %7s %8s %8s %5s %6s %8s %4s %4s\n", "", "MB", "MB", "k", "MB", "MB", "", "ms", "ms",
                "", "us", "us", "", "", "ms", "", "");
}

void print_row(const SoakMinute& m) {
    std::printf("%4d %8.1f %8.1f %8.1f %8.2f %8.2f %6llu %8.2f %8.2f %7llu %8.0f %8.0f %5llu %6llu %8.2f %4d %4d\n", m.minute,
                m.rss_mb, m.heap_mb, 1e-3 * static_cast<double>(m.triangles), m.journal_mb, m.history_mb, static_cast<unsigned long long>(m.frames), m.frame_p50_ms,
                m.frame_p99_ms, static_cast<unsigned long long>(m.ticks), m.period_p99_us, m.period_worst_us,
                static_cast<unsigned long long>(m.periods_over_2ms), static_cast<unsigned long long>(m.steps),
                m.step_p99_ms, m.fds, m.threads);
    std::fflush(stdout);
}

// Times `tridex recover` on the journal, s; notes what it started from.
void time_recovery(SoakResult& r, const fs::path& out) {
    const auto t0 = std::chrono::steady_clock::now();
    app::run_recover(r.journal, out.string());
    r.recover_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ifstream in(out / "report.json");
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_object()) r.recovered_from = j.value("replayed_from", std::string());
}

nlohmann::json summary_json(const SoakResult& r, const SoakOptions& o) {
    nlohmann::json rows = nlohmann::json::array();
    for (const SoakMinute& m : r.minutes) rows.push_back(row_json(m));
    return {{"minutes_asked", o.minutes},
            {"strokes_kept", o.keep},
            {"resolution", o.resolution},
            {"growth_mb_per_min", r.growth_minutes >= 2 ? nlohmann::json(r.growth_mb_per_min) : nlohmann::json()},
            {"growth_less_history_mb_per_min",
             r.growth_minutes >= 2 ? nlohmann::json(r.growth_less_history_mb_per_min) : nlohmann::json()},
            {"growth_minutes", r.growth_minutes},
            {"growth_bound_mb_per_min", kSoakGrowthBoundMbPerMin},
            {"verdict", verdict_text(r.verdict)},
            {"target_met", target_met(r.verdict)},
            {"fds_first", r.fds_first},
            {"fds_last", r.fds_last},
            {"threads_first", r.threads_first},
            {"threads_last", r.threads_last},
            {"journal", r.journal},
            {"journal_mb", r.journal_mb},
            {"journal_mb_per_hour", r.journal_mb_per_hour},
            {"recover_s", r.recover_s >= 0.0 ? nlohmann::json(r.recover_s) : nlohmann::json()},
            {"recovered_from", r.recovered_from},
            {"ended", r.ended},
            {"rows", rows}};
}

}  // namespace

namespace {

// The least-squares slope of y(row) over the rows' minutes, per minute; 0 with fewer than two rows.
template <class Y>
double slope(const std::vector<SoakMinute>& rows, Y y) {
    if (rows.size() < 2) return 0.0;
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (const SoakMinute& m : rows) {
        sx += m.minute;
        sy += y(m);
        sxx += static_cast<double>(m.minute) * m.minute;
        sxy += m.minute * y(m);
    }
    const double n = static_cast<double>(rows.size());
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

void judge_soak(SoakResult& r) {
    r.growth_minutes = r.minutes.size();
    r.growth_mb_per_min = slope(r.minutes, [](const SoakMinute& m) { return m.rss_mb; });
    r.growth_less_history_mb_per_min = slope(r.minutes, [](const SoakMinute& m) { return m.rss_mb - m.history_mb; });
    const std::size_t timed = r.growth_minutes >= 2 ? r.growth_minutes : 0;
    r.verdict = verdict_of(timed, std::isfinite(r.growth_mb_per_min) && r.growth_mb_per_min <= kSoakGrowthBoundMbPerMin);
    if (r.minutes.empty()) return;
    const SoakMinute &first = r.minutes.front(), &last = r.minutes.back();
    r.fds_first = first.fds;
    r.fds_last = last.fds;
    r.threads_first = first.threads;
    r.threads_last = last.threads;
    r.journal_mb = last.journal_mb;
    const double span_min = last.minute - first.minute;
    r.journal_mb_per_hour = span_min > 0 ? 60.0 * (last.journal_mb - first.journal_mb) / span_min : 0.0;
}

SoakResult run_soak_bench(const SoakOptions& o) {
    if (!(std::isfinite(o.minutes) && o.minutes > 0.0 && o.minutes <= 1440.0))
        throw Error("bench --soak: MINUTES must be between 0 and 1440, got " + format_number(o.minutes));
    app::prepare_output_dir(o.out, "--out");
    const fs::path out(o.out), session = out / "soak";
    app::prepare_output_dir(session.string(), "--out");
    SoakResult r;
    r.journal = (session / "session.tdj").string();
    const std::string jsonl = (out / "soak.jsonl").string();
    std::ofstream rows(jsonl, std::ios::trunc);
    if (!rows) throw Error(jsonl + ": cannot open for writing");
    const double seconds = 60.0 * o.minutes;
    app::RunOptions ro;
    ro.scene = write_soak_scene(o.out, seconds, o.resolution, o.keep);
    ro.display = "offscreen";
    ro.out = session.string();
    ro.seconds = seconds + 2.0;  // the last minute's reading comes from a frame after it
    auto monitor = std::make_shared<SoakMonitor>(r.journal, [&](const SoakMinute& m) {
        if (m.minute > std::ceil(o.minutes)) return;
        r.minutes.push_back(m);
        rows << row_json(m).dump() << "\n" << std::flush;
        if (o.print) print_row(m);
    });
    ro.frame_probe = [monitor](const app::RunFrameProbe& p) { monitor->frame(p); };
    if (o.print) {
        std::printf("soak: a scripted sculptor for %s min (N = %d, offscreen, journal on, %s); a row per minute\n",
                    format_number(o.minutes).c_str(), o.resolution,
                    o.keep ? "half the strokes kept" : "every stroke undone");
        print_header();
    }
    const app::RunResult run = app::run_stereo_session(ro);
    r.ended = run.notes.empty() ? "" : run.notes.front();
    if (run.validation_messages + run.sculpt_validation_messages > 0)
        throw Error("bench --soak: the session logged Vulkan validation messages");
    judge_soak(r);
    if (o.recover) time_recovery(r, out / "soak_recover");
    if (o.print) {
        std::printf("memory growth after minute 1: %s (bound %.1f MB/min): %s; less the undo history: %s\n",
                    r.growth_minutes >= 2 ? (format_number(r.growth_mb_per_min) + " MB/min").c_str() : "-",
                    kSoakGrowthBoundMbPerMin, verdict_text(r.verdict),
                    r.growth_minutes >= 2 ? (format_number(r.growth_less_history_mb_per_min) + " MB/min").c_str() : "-");
        if (o.keep) std::printf("(strokes kept: the model, its meshes and undo images grow with the work; the bound is "
                                "for a model that stays the same, the default)\n");
        std::printf("fds %d -> %d, threads %d -> %d; journal %.2f MB (%.1f MB/h)", r.fds_first, r.fds_last,
                    r.threads_first, r.threads_last, r.journal_mb, r.journal_mb_per_hour);
        if (r.recover_s >= 0.0) std::printf("; recovery %.2f s (from %s)", r.recover_s, r.recovered_from.c_str());
        std::printf("\n");
    }
    app::write_json_file((out / "soak.json").string(), summary_json(r, o));
    write_soak_plot(r.minutes, (out / "soak.svg").string());
    return r;
}

namespace {

struct SoakCli {
    int resolution = 128;
    bool no_recover = false;
    bool keep = false;
};

BenchRun setup_soak_bench(CLI::App& bench) {
    auto o = std::make_shared<SoakCli>();
    bench.add_option("--soak-n", o->resolution, "With --soak: the workpiece's lattice cells along its longest side")
        ->capture_default_str()
        ->check(CLI::Range(16, 1024));
    bench.add_flag("--soak-keep", o->keep,
                   "With --soak: keep half the strokes (the model grows as a sculptor's does); default: every stroke "
                   "is undone, so the model stays the same and any growth is the process's");
    bench.add_flag("--soak-no-recover", o->no_recover, "With --soak: do not time `tridex recover` on the journal");
    return [o](const BenchCommon& c) {
        SoakOptions so;
        so.out = c.out;
        so.resolution = o->resolution;
        so.recover = !o->no_recover;
        so.keep = o->keep;
        try {
            so.minutes = std::stod(c.value);
        } catch (const std::exception&) {
            throw Error("--soak: MINUTES must be a number, got '" + c.value + "'");
        }
        run_soak_bench(so);
    };
}

const BenchmarkRegistration kRegistration{
    {"soak",
     "A scripted sculptor for MINUTES minutes through the full run session (every operation, undo and redo, saves, "
     "tool changes, head moves; offscreen, journal on): resident memory, journal and undo bytes, frame, haptic and "
     "sculpt times, descriptors and threads per minute; memory growth after minute 1 against its bound; recovery time",
     95, setup_soak_bench, "MINUTES"}};

}  // namespace

}  // namespace tridex::bench
