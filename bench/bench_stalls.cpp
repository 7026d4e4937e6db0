// bench/bench_stalls.cpp - the haptic loop's worst periods in a live mouse session: rendering, sculpting and the
// journal running, the mouse played by a scripted cursor so that every run moves the same way.
#include "bench/bench_registry.hpp"
#include "bench/bench_verdict.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "app/session/run/run_session.hpp"
#include "app/support/assets.hpp"
#include "app/support/json_file.hpp"
#include "app/support/output_dir.hpp"
#include "core/error.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions and JSON files

namespace {

namespace fs = std::filesystem;

// The targets the rows are printed beside: the worst period, and no period over 5 ms.
constexpr double kTargetWorstMs = 2.0;

struct StallsCli {
    double seconds = 60.0;
    std::string display;  // "" = window when an X display is set, else offscreen (paced)
    bool journal_off = false;
    bool shared_cpu = false;  // also a run with the loop's CPU shared with the drawing thread (the baseline)
    bool gpu = false;
};

// The default scene (the bunny at N = 128 in a 960x540 mono window) with the mouse as the stylus and a cursor that
// presses in and drags a 160 px groove across the bunny, lets go and comes back, every 1.6 s for `seconds`.
std::string write_scene(const fs::path& dir, double seconds, const std::string& mesh) {
    nlohmann::json cursor = nlohmann::json::array();
    for (double t = 0.5; t + 1.6 < seconds; t += 1.6) {
        cursor.push_back({{"t_s", t}, {"x_px", 400}, {"y_px", 260}, {"buttons", 0}});
        cursor.push_back({{"t_s", t + 0.1}, {"x_px", 400}, {"y_px", 260}, {"buttons", 1}});
        cursor.push_back({{"t_s", t + 0.9}, {"x_px", 560}, {"y_px", 280}, {"buttons", 1}});
        cursor.push_back({{"t_s", t + 1.0}, {"x_px", 560}, {"y_px", 280}, {"buttons", 0}});
    }
    const nlohmann::json scene = {
        {"workpiece", {{"mesh", mesh}, {"resolution", 128}, {"stock_m", 0.12},
                       {"centre_m", {0.0, 0.0, 0.05}}}},
        {"tool", {{"radius_m", 0.006}, {"stiffness_n_per_m", 700}, {"damping_n_s_per_m", 0.5}}},
        {"device", {{"driver", "mouse"}}},
        {"stroke", "none"},
        {"display", {{"preset", "desktop"}, {"stereo", "mono"}, {"resolution", {960, 540}}}},
        {"head", {{"provider", "fixed"}, {"position_m", {0.0, 0.05, 0.6}}}},
        {"cursor", cursor}};
    const std::string path = (dir / "stalls_scene.json").string();
    write_json_file(path, scene);
    return path;
}

struct StallRow {
    std::string display, journal, cpu;  // cpu: "own" (a CPU set aside for the loop) or "shared"
    std::size_t ticks = 0, over_2ms = 0, over_5ms = 0, overruns = 0;
    double worst_ms = 0.0, p99_ms = 0.0, frame_p50_ms = 0.0;
    std::uint64_t steps = 0;
    bool fifo = false, locked = false;
    int reserved_cpu = -1;  // the CPU the loop had to itself (report.json haptics.reserved_cpu), -1 = none
    std::string refused;
};

StallRow run_one(const StallsCli& o, const std::string& scene, const std::string& display, bool journal,
                 bool shared_cpu, const fs::path& out) {
    RunOptions r;
    r.scene = scene;
    r.display = display;
    r.seconds = o.seconds;
    r.out = out.string();
    r.no_journal = !journal;
    r.shared_haptic_cpu = shared_cpu;
    r.gpu = o.gpu;
    r.checkpoint_s = 0.0;
    const RunResult res = run_stereo_session(r);
    const nlohmann::json j = nlohmann::json::parse(std::ifstream(out / "report.json"));
    const nlohmann::json& h = j.at("haptics");
    StallRow row;
    row.display = display;
    row.journal = journal ? "on" : "off";
    row.cpu = shared_cpu ? "shared" : "own";
    row.ticks = h.at("ticks").get<std::size_t>();
    row.worst_ms = 1e-3 * h.at("period_us").at("max").get<double>();
    row.p99_ms = 1e-3 * h.at("period_us").at("p99").get<double>();
    row.over_2ms = h.at("periods_over_2ms").get<std::size_t>();
    row.over_5ms = h.at("periods_over_5ms").get<std::size_t>();
    row.overruns = h.at("overruns").get<std::size_t>();
    row.fifo = h.at("realtime_scheduling").get<bool>();
    row.locked = h.at("memory_locked").get<bool>();
    if (!h.at("reserved_cpu").is_null()) row.reserved_cpu = h.at("reserved_cpu").get<int>();
    if (!h.at("realtime_refused").is_null()) row.refused = h.at("realtime_refused").get<std::string>();
    row.steps = res.sculpt.steps;
    row.frame_p50_ms = res.frame_ms.percentile_ms(0.5);
    return row;
}

void run_stalls(const StallsCli& o, const BenchCommon& c) {
    if (!(o.seconds >= 5.0 && o.seconds <= 3600.0))
        throw Error("--stalls-seconds: must be between 5 and 3600, got " + std::to_string(o.seconds));
    const char* x = std::getenv("DISPLAY");
    const std::string display = !o.display.empty() ? o.display : (x && *x) ? "window" : "offscreen";
    if (display != "window" && display != "offscreen")
        throw Error("--stalls-display: window or offscreen, got '" + o.display + "'");
    prepare_output_dir(c.out, "--out");
    const fs::path dir = fs::path(c.out) / "stalls";
    fs::create_directories(dir);
    const std::string scene =
        write_scene(dir, o.seconds, fs::absolute(c.mesh.empty() ? default_mesh_path() : c.mesh).lexically_normal().string());
    std::printf("haptic stalls: a %.0f s mouse session (scripted cursor, press-drag-release every 1.6 s), %s, "
                "rendering, sculpting%s\n",
                o.seconds, display == "window" ? "in a window" : "offscreen (paced; no X display)",
                o.journal_off ? ", with and without the journal" : " and the journal");
    std::printf(
        "cpu: own = a CPU set aside for the loop, the drawing thread kept off it (the default); shared = "
        "--shared-haptic-cpu (the baseline)\n");
    std::printf("target: worst period <= %.1f ms, no period over 5 ms\n", kTargetWorstMs);
    std::printf("%9s %4s %6s %7s %9s %9s %8s %8s %8s %6s %7s %6s %s\n", "display", "jnl", "cpu", "ticks", "worst_ms",
                "p99_ms", ">2ms", ">5ms", "overrun", "steps", "frame50", "fifo", "verdict");
    nlohmann::json rows = nlohmann::json::array();
    struct Variant {
        bool journal, shared_cpu;
        const char* dir;
    };
    std::vector<Variant> variants{{true, false, "journal"}};
    if (o.journal_off) variants.push_back({false, false, "no_journal"});
    if (o.shared_cpu) variants.push_back({true, true, "shared_cpu"});
    for (const Variant& v : variants) {
        const StallRow r = run_one(o, scene, display, v.journal, v.shared_cpu, dir / v.dir);
        const Verdict verdict = verdict_of(r.ticks, r.worst_ms <= kTargetWorstMs && r.over_5ms == 0);
        std::printf("%9s %4s %6s %7zu %9.2f %9.3f %8zu %8zu %8zu %6llu %7.1f %6s %s\n", r.display.c_str(),
                    r.journal.c_str(), r.cpu.c_str(), r.ticks, r.worst_ms, r.p99_ms, r.over_2ms, r.over_5ms, r.overruns,
                    static_cast<unsigned long long>(r.steps), r.frame_p50_ms, r.fifo ? "yes" : "no",
                    verdict_text(verdict));
        if (!v.shared_cpu && r.fifo && r.reserved_cpu < 0)
            std::printf("  no CPU was set aside for the loop (fewer than 2 CPUs allowed)\n");
        if (!r.refused.empty()) std::printf("  SCHED_FIFO refused: %s\n", r.refused.c_str());
        std::fflush(stdout);
        rows.push_back(
            {{"display", r.display},
             {"journal", v.journal},
             {"haptic_cpu", r.cpu},
             {"reserved_cpu", r.reserved_cpu >= 0 ? nlohmann::json(r.reserved_cpu) : nlohmann::json(nullptr)},
             {"seconds", o.seconds},
             {"ticks", r.ticks},
             {"worst_period_ms", r.worst_ms},
             {"period_p99_ms", r.p99_ms},
             {"periods_over_2ms", r.over_2ms},
             {"periods_over_5ms", r.over_5ms},
             {"overruns", r.overruns},
             {"sculpt_steps", r.steps},
             {"frame_p50_ms", r.frame_p50_ms},
             {"realtime_scheduling", r.fifo},
             {"memory_locked", r.locked},
             {"realtime_refused", r.refused},
             {"target_worst_ms", kTargetWorstMs},
             {"verdict", verdict_text(verdict)},
             {"target_met", target_met(verdict)}});
    }
    write_json_file((fs::path(c.out) / "stalls_bench.json").string(), rows);
}

BenchRun setup_stalls(CLI::App& bench) {
    auto o = std::make_shared<StallsCli>();
    bench.add_option("--stalls-seconds", o->seconds, "With --stalls: session length, s (default 60)");
    bench.add_option("--stalls-display", o->display,
                     "With --stalls: window or offscreen (default: window when DISPLAY is set, e.g. under Xvfb)");
    bench.add_flag("--stalls-journal-off", o->journal_off,
                   "With --stalls: also run the session without its journal, for comparison");
    bench.add_flag("--stalls-shared-cpu", o->shared_cpu,
                   "With --stalls: also run with the loop's CPU shared with the drawing thread (--shared-haptic-cpu), "
                   "the baseline");
    bench.add_flag("--stalls-gpu", o->gpu, "With --stalls: sculpt on the GPU compute path (--gpu)");
    return [o](const BenchCommon& c) { run_stalls(*o, c); };
}

const BenchmarkRegistration kRegistration{
    {"stalls",
     "Haptic loop stalls in a live mouse session (scripted cursor, window under X or offscreen, rendering, sculpting "
     "and the journal running): worst tick period and periods over 2 and 5 ms, beside the target",
     45, setup_stalls}};

}  // namespace

}  // namespace tridex::bench
