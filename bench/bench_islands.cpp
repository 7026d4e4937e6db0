// bench/bench_islands.cpp - the speck search at a stroke's end after the newcomer's deep cut, per resolution.
#include "bench/bench_islands.hpp"
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/scene/workpiece_source.hpp"
#include "app/support/assets.hpp"
#include "app/support/json_file.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/model/islands.hpp"
#include "compute/model/probe.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "core/error.hpp"
#include "core/summary.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: workpieces, the sculpt history, JSON files

namespace {

namespace fs = std::filesystem;

constexpr double kStockM = 0.12;            // the default scene's workpiece
const Vec3 kCentreM(0.0, 0.0, 0.05);
constexpr double kToolRadiusM = 0.006;      // the default scene's ball
constexpr double kDepthM = 2.0 * kToolRadiusM;  // the mouse stylus's deepest press (MouseStylus::kMaxDepthSteps)
constexpr double kHalfLengthM = 0.045;      // the drag, along world x
constexpr double kStepM = 0.0005;           // between samples

// The cut's sweeps: the ball kDepthM below the front surface (+z; probe_top on the Z rays of the uncut model, as the
// stylus follows the surface of the press), from x = -kHalfLengthM to +kHalfLengthM at y = 0, after a plunge.
std::vector<compute::Sweep> plan_cut(const compute::TriDexel& model) {
    std::vector<Vec3> path;
    for (double x = -kHalfLengthM; x <= kHalfLengthM + 1e-12; x += kStepM) {
        Vec3 top;
        if (!compute::probe_top(model, 2, Vec3(x, 0.0, kCentreM.z), top)) continue;
        if (path.empty()) path.push_back(top + Vec3(0.0, 0.0, kToolRadiusM));  // resting on the surface
        path.push_back(top + Vec3(0.0, 0.0, kToolRadiusM - kDepthM));
    }
    if (path.size() < 2) throw Error("bench --islands: the workpiece has no front surface at y = 0");
    std::vector<compute::Sweep> out;
    for (std::size_t i = 1; i < path.size(); ++i) {
        compute::Sweep s;
        s.op = ToolOp::kSubtract;
        s.tool = compute::SweepTool{ToolKind::kBall, kToolRadiusM, 0.0};
        s.path_m = Segment{path[i - 1], path[i]};
        out.push_back(s);
    }
    return out;
}

std::size_t mesh_parts(compute::TriDexel model) {
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});
    compute::Contourer c(model);
    c.update(model);
    return mesh_components(c.mesh());
}

// The box SculptHistory searches: the sweeps' box grown by the tool's radius and two cells.
Aabb search_box(const std::vector<compute::Sweep>& sweeps, double cell_m) {
    Aabb box;
    for (const compute::Sweep& s : sweeps) {
        const Aabb b = compute::sweep_bounds(s);
        box.add(b.lo);
        box.add(b.hi);
    }
    return box.inflated(kToolRadiusM + 2.0 * cell_m);
}

IslandBenchRow run_one(const std::string& mesh, int n, int repeats) {
    Workpiece wp = prepare_workpiece(mesh, n, kStockM, kCentreM);
    const std::vector<compute::Sweep> cut = plan_cut(wp.model);
    IslandBenchRow r;
    r.n = n;
    r.sweeps = cut.size();
    const std::unique_ptr<BooleanBackend> cpu = make_cpu_backend(wp.model);
    compute::TriDexel kept;  // the carved model before the removal
    {
        SculptHistory h(wp.model, *cpu);
        h.apply(cut);
        kept = wp.model;
        h.remove_islands(true);
        IslandRemoval removed;
        h.end_stroke(nullptr, &removed);
        r.specks = removed.specks;
        r.speck_volume_m3 = removed.volume_m3;
        r.end_stroke_ms = removed.search_ms;
    }
    const Aabb box = search_box(cut, wp.model.lattice.cell_m);
    compute::IslandOptions opt;
    opt.max_volume_m3 = compute::speck_volume_m3(kToolRadiusM);
    std::vector<double> ms;
    compute::IslandSearch found;
    for (int k = 0; k < repeats; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        found = compute::find_islands(kept, box, opt);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    const Summary s = summarize(ms);
    r.search_median_ms = s.median;
    r.search_max_ms = s.max;
    ms.clear();
    for (int k = 0; k < repeats; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        (void)compute::find_islands(kept, kept.lattice.bounds(), opt);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    r.whole_median_ms = summarize(ms).median;
    r.nodes = found.nodes;
    r.pieces = found.pieces;
    const Vec3 size = box.size() / wp.model.lattice.cell_m;
    r.box_nodes = static_cast<std::size_t>((size.x + 1.0) * (size.y + 1.0) * (size.z + 1.0));
    r.parts_before = mesh_parts(kept);
    r.parts_after = mesh_parts(wp.model);
    return r;
}

}  // namespace

std::vector<IslandBenchRow> run_islands_bench(const IslandBenchOptions& o) {
    if (o.resolutions.empty() || o.repeats < 1) throw Error("bench --islands: nothing to run");
    for (const int n : o.resolutions)
        if (n < 32 || n > 1024) throw Error("bench --islands: N must be 32..1024, got " + std::to_string(n));
    const std::string mesh = o.mesh.empty() ? default_mesh_path() : o.mesh;
    fs::create_directories(o.out);
    std::printf("islands: %s, %.2f m stock; a %.0f mm ball %.0f mm below the front surface dragged %.0f mm along x (one "
                "stroke, CPU backend), specks removed at its end; find_islands then repeated %d times on its box\n",
                mesh.c_str(), kStockM, kToolRadiusM * 1e3, kDepthM * 1e3, 2e3 * kHalfLengthM, o.repeats);
    std::printf("%5s %7s %11s %10s %7s %7s %10s %9s %9s %11s %10s %10s %9s\n", "N", "sweeps", "box_nodes", "inside",
                "pieces", "specks", "speck_mm3", "parts_in", "parts_out", "end_strk_ms", "search50", "search_max",
                "whole50");
    std::vector<IslandBenchRow> rows;
    nlohmann::json jrows = nlohmann::json::array();
    for (const int n : o.resolutions) {
        const IslandBenchRow r = run_one(mesh, n, o.repeats);
        std::printf("%5d %7zu %11zu %10zu %7zu %7zu %10.3g %9zu %9zu %11.2f %10.2f %10.2f %9.2f\n", r.n, r.sweeps,
                    r.box_nodes, r.nodes, r.pieces, r.specks, r.speck_volume_m3 * 1e9, r.parts_before, r.parts_after,
                    r.end_stroke_ms, r.search_median_ms, r.search_max_ms, r.whole_median_ms);
        std::fflush(stdout);
        jrows.push_back({{"n", r.n},
                         {"sweeps", r.sweeps},
                         {"box_nodes", r.box_nodes},
                         {"inside_nodes", r.nodes},
                         {"pieces", r.pieces},
                         {"specks", r.specks},
                         {"speck_volume_m3", r.speck_volume_m3},
                         {"mesh_parts_before", r.parts_before},
                         {"mesh_parts_after", r.parts_after},
                         {"end_stroke_ms", r.end_stroke_ms},
                         {"search_ms_median", r.search_median_ms},
                         {"search_ms_max", r.search_max_ms},
                         {"whole_lattice_ms_median", r.whole_median_ms}});
        rows.push_back(r);
    }
    const nlohmann::json setup{{"mesh", mesh},
                               {"stock_m", kStockM},
                               {"tool_radius_m", kToolRadiusM},
                               {"depth_m", kDepthM},
                               {"drag", "along world x from -45 to +45 mm at y = 0, 0.5 mm steps, below the front surface"},
                               {"repeats", o.repeats},
                               {"threshold_m3", compute::speck_volume_m3(kToolRadiusM)},
                               {"measured", "IslandRemoval::search_ms of SculptHistory::end_stroke (search, undo capture, "
                                            "CPU write), and compute::find_islands alone on the same box"}};
    write_json_file((fs::path(o.out) / "islands_bench.json").string(), {{"rows", jrows}, {"setup", setup}});
    return rows;
}

namespace {

struct IslandBenchCli {
    std::vector<int> n;
};

BenchRun setup_islands_bench(CLI::App& bench) {
    auto o = std::make_shared<IslandBenchCli>();
    bench.add_option("--islands-n", o->n, "With --islands: run only these N, e.g. --islands-n 256")->delimiter(',');
    return [o](const BenchCommon& c) {
        IslandBenchOptions b;
        b.out = c.out;
        b.mesh = c.mesh;
        if (!o->n.empty()) b.resolutions = o->n;
        run_islands_bench(b);
    };
}

const BenchmarkRegistration kRegistration{
    {"islands",
     "The speck search at a stroke's end after a deep cut across the bunny (search time, specks, mesh parts before and "
     "after): N = 128, 256, 512",
     95, setup_islands_bench}};

}  // namespace

}  // namespace tridex::bench
