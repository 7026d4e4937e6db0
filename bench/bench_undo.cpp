// bench/bench_undo.cpp - undo and redo latency of a real sculpt thread, per stroke.
#include "bench/bench_undo.hpp"
#include "bench/bench_registry.hpp"
#include "bench/bench_verdict.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/commands/demo/demo.hpp"
#include "app/support/json_file.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "core/summary.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/model/probe.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/active_surface.hpp"
#include "core/error.hpp"
#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions, stats and JSON files

namespace {

namespace fs = std::filesystem;

constexpr double kToolRadiusM = 0.008;   // the demo's ball
constexpr double kDepthM = 0.006;        // the demo's depth below the surface
constexpr double kGrooveLengthM = 0.12;  // the demo's pass length, along world x
constexpr double kGrooveSpacingM = 0.014;
constexpr double kClearanceM = 0.03;     // tool lifted between grooves
constexpr double kTargetMs = 16.0;       // one 60 Hz frame, at N = 256

// Nearest-rank percentile q in (0, 1].
double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::min(v.size(), std::max<std::size_t>(k, 1)) - 1];
}

// The grooves' samples: per groove a lifted sample above its start, segments + 1 cutting samples along x following
// the top surface (probe_top on the Y rays) at kDepthM below it (the first sweep is the plunge), a lifted sample
// above its end (which closes the stroke). 1 ms apart, as the haptic loop's.
std::vector<ToolSample> plan_grooves(const compute::TriDexel& model, int strokes, int segments) {
    const Aabb box = model.lattice.bounds();
    const Vec3 c = 0.5 * (box.lo + box.hi);
    std::vector<ToolSample> out;
    double t = 0.0;
    ToolSample s;
    s.tool = ToolShape{ToolKind::kBall, kToolRadiusM, 0.0, 0};
    for (int k = 0; k < strokes; ++k) {
        const double z = c.z + (k - 0.5 * (strokes - 1)) * kGrooveSpacingM;
        std::vector<Vec3> path;
        double last_y = box.hi.y;
        for (int i = 0; i <= segments; ++i) {
            const double x = c.x + (static_cast<double>(i) / segments - 0.5) * kGrooveLengthM;
            Vec3 top;
            if (compute::probe_top(model, 1, Vec3(x, c.y, z), top)) last_y = top.y + kToolRadiusM - kDepthM;
            path.emplace_back(x, last_y, z);
        }
        auto push = [&](const Vec3& p, ToolOp op) {
            s.t_s = t;
            t += 0.001;
            s.position = p;
            s.surface_m = p;
            s.op = op;
            out.push_back(s);
        };
        push(path.front() + Vec3(0.0, kClearanceM, 0.0), ToolOp::kNone);
        for (const Vec3& p : path) push(p, ToolOp::kSubtract);
        push(path.back() + Vec3(0.0, kClearanceM, 0.0), ToolOp::kNone);
    }
    return out;
}

}  // namespace

std::vector<UndoBenchRow> run_undo_bench(const UndoBenchOptions& o) {
    if (o.resolutions.empty() || o.paths.empty()) throw Error("bench --undo: nothing to run");
    for (const std::string& p : o.paths)
        if (p != "cpu" && p != "gpu") throw Error("bench --undo: unknown path '" + p + "'; use cpu or gpu");
    if (o.strokes < 1 || o.strokes > 30 || o.segments < 1)
        throw Error("bench --undo: strokes must be 1..30 and segments >= 1");
    const std::string mesh = o.mesh.empty() ? default_mesh_path() : o.mesh;
    fs::create_directories(o.out);
    std::printf("undo: %s, 0.3 m stock; %d grooves across the top (%.0f mm ball, %.0f mm deep, %d segments + a plunge each), "
                "then each undone and redone through a SculptThread (CPU contour, validation off)\n",
                mesh.c_str(), o.strokes, kToolRadiusM * 1e3, kDepthM * 1e3, o.segments);
    std::printf("%5s %5s %7s %9s %9s %9s %9s %9s %9s %9s %9s %12s %12s\n", "N", "path", "strokes", "rays50", "undo50",
                "undo95", "undo_max", "redo50", "redo_max", "restore50", "contour50", "hist_B/strk", "16ms");
    std::printf("%5s %5s %7s %9s %9s %9s %9s %9s %9s %9s %9s %12s %12s\n", "", "", "", "", "ms", "ms", "ms", "ms", "ms",
                "ms", "ms", "", "");
    std::vector<UndoBenchRow> rows;
    nlohmann::json jrows = nlohmann::json::array();
    for (const int n : o.resolutions)
        for (const std::string& want : o.paths) {
            Workpiece wp = prepare_workpiece(mesh, n, 0.3, Vec3(0.0, 0.0, 0.3));
            const std::vector<ToolSample> samples = plan_grooves(wp.model, o.strokes, o.segments);
            BackendChoice choice;
            try {  // each path forced: the device's type decides neither row
                choice = make_boolean_backend(wp.model, {want == "cpu" ? BackendMode::kCpu : BackendMode::kGpu}, false);
            } catch (const Error& e) {
                std::printf("%5d %5s  skipped: %s\n", n, want.c_str(), e.what());
                continue;
            }
            compute::Contourer contourer(wp.model);
            contourer.update(wp.model);
            SpscRing<ToolSample> ring(samples.size() + 16);
            TripleBuffer<ActiveSurface> surface;
            SculptThread thread(wp.model, contourer, ring, surface, samples.front().position, kToolRadiusM, 0.0);
            thread.use_backend(*choice.backend);
            thread.start();
            for (const ToolSample& s : samples)
                while (!ring.try_push(s)) std::this_thread::sleep_for(std::chrono::microseconds(100));
            // A sample leaves the ring in the step that applies it; a request pushed after that is taken at the start
            // of a later step, so every groove is applied (and closed by its lifted sample) before the first undo.
            while (ring.size() > 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
            for (int k = 0; k < o.strokes; ++k) thread.request(SculptRequest::kUndo);
            for (int k = 0; k < o.strokes; ++k) thread.request(SculptRequest::kRedo);
            thread.stop();  // takes the queued requests first
            const SculptStats& st = thread.stats();
            std::vector<double> undo_ms, redo_ms, rays;
            for (std::size_t i = 0; i < st.undo_ms.size(); ++i) {
                (st.undo_redo[i] ? redo_ms : undo_ms).push_back(st.undo_ms[i]);
                if (!st.undo_redo[i]) rays.push_back(static_cast<double>(st.undo_rays[i]));
            }
            // Each undo and redo was also a sculpt step: its write-back + surface publish, and its re-contour.
            const std::vector<double>& restore_ms = st.undo_restore_ms;
            const std::vector<double>& recontour_ms = st.undo_contour_ms;
            UndoBenchRow r;
            r.n = n;
            r.restore_median_ms = summarize(restore_ms).median;
            r.contour_median_ms = summarize(recontour_ms).median;
            r.path = choice.backend->path();
            r.strokes = st.history.undo_steps;
            r.segments = static_cast<std::size_t>(o.segments) + 1;
            const Summary u = summarize(undo_ms), d = summarize(redo_ms);
            r.rays_median = summarize(rays).median;
            r.undo_median_ms = u.median;
            r.undo_p95_ms = percentile(undo_ms, 0.95);
            r.undo_max_ms = u.max;
            r.redo_median_ms = d.median;
            r.redo_max_ms = d.max;
            r.history_bytes_per_stroke =
                st.history.undo_steps ? static_cast<double>(st.history.bytes) / static_cast<double>(st.history.undo_steps) : 0.0;
            r.target_ms = n == 256 ? kTargetMs : 0.0;
            // Both the undos and the redos must have been timed: the max of none reads 0.
            const Verdict verdict =
                verdict_of(std::min(undo_ms.size(), redo_ms.size()), std::max(u.max, d.max) <= r.target_ms);
            r.target_met = r.target_ms > 0.0 && target_met(verdict);
            if (undo_ms.size() != static_cast<std::size_t>(o.strokes) || redo_ms.size() != static_cast<std::size_t>(o.strokes))
                std::printf("      (warning: %zu undos and %zu redos changed the model, %d expected)\n", undo_ms.size(),
                            redo_ms.size(), o.strokes);
            std::printf("%5d %5s %7zu %9.0f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %12.0f %12s\n", n, r.path.c_str(),
                        r.strokes, r.rays_median, r.undo_median_ms, r.undo_p95_ms, r.undo_max_ms, r.redo_median_ms,
                        r.redo_max_ms, r.restore_median_ms, r.contour_median_ms, r.history_bytes_per_stroke,
                        r.target_ms > 0.0 ? verdict_text(verdict) : "-");
            std::fflush(stdout);
            jrows.push_back({{"n", r.n},
                             {"path", r.path},
                             {"device", choice.backend->device()},
                             {"validation_messages", choice.backend->validation_messages()},
                             {"strokes", r.strokes},
                             {"segments_per_stroke", r.segments},
                             {"rays_restored_median", r.rays_median},
                             {"undo_ms_median", r.undo_median_ms},
                             {"undo_ms_p95", r.undo_p95_ms},
                             {"undo_ms_max", r.undo_max_ms},
                             {"redo_ms_median", r.redo_median_ms},
                             {"redo_ms_max", r.redo_max_ms},
                             {"undo_ms", undo_ms},
                             {"redo_ms", redo_ms},
                             {"restore_ms_median", r.restore_median_ms},
                             {"contour_ms_median", r.contour_median_ms},
                             {"tiles_recontoured", st.tiles_recontoured},
                             {"history_bytes_per_stroke", r.history_bytes_per_stroke},
                             {"history_bytes", st.history.bytes},
                             {"target_ms", r.target_ms > 0.0 ? nlohmann::json(r.target_ms) : nlohmann::json()},
                             {"target_met", r.target_ms > 0.0 ? nlohmann::json(r.target_met) : nlohmann::json()}});
            rows.push_back(r);
        }
    const nlohmann::json setup{
        {"mesh", mesh},
        {"stock_m", 0.3},
        {"tool_radius_m", kToolRadiusM},
        {"depth_m", kDepthM},
        {"strokes", o.strokes},
        {"segments", o.segments},
        {"groove", "along world x, 0.12 m, following the top surface (probe_top, Y rays), 14 mm apart in z; lifted between"},
        {"measured", "SculptStats::undo_ms of a real SculptThread: close stroke, history undo/redo (write rays back through "
                     "the BooleanBackend), active-surface extraction and publish, dirty-tile re-contour (CPU Contourer)"},
        {"order", "all strokes undone newest first, then all redone, requests queued at once"},
        {"target", "every undo and redo (max) within 16 ms at N = 256"},
        {"validation", false}};
    write_json_file((fs::path(o.out) / "undo_bench.json").string(), {{"rows", jrows}, {"setup", setup}});
    return rows;
}

namespace {

struct UndoBenchCli {
    std::vector<int> n;
    std::vector<std::string> paths;
};

BenchRun setup_undo_bench(CLI::App& bench) {
    auto o = std::make_shared<UndoBenchCli>();
    bench.add_option("--undo-n", o->n, "With --undo: run only these N, e.g. --undo-n 256")->delimiter(',');
    bench.add_option("--undo-paths", o->paths, "With --undo: run only these paths (cpu, gpu)")->delimiter(',');
    return [o](const BenchCommon& c) {
        UndoBenchOptions u;
        u.out = c.out;
        u.mesh = c.mesh;
        if (!o->n.empty()) u.resolutions = o->n;
        if (!o->paths.empty()) u.paths = o->paths;
        run_undo_bench(u);
    };
}

const BenchmarkRegistration kRegistration{
    {"undo",
     "Per-stroke undo and redo latency of the sculpt thread (write back, active surface, re-contour): bunny at N = "
     "256 and 512, CPU and GPU paths",
     90, setup_undo_bench}};

}  // namespace

}  // namespace tridex::bench
