// bench/bench_contour.cpp - the re-contour per carving step, by the way the changed region is marked.
#include "bench/bench_contour.hpp"
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/scene/workpiece_source.hpp"
#include "app/support/assets.hpp"
#include "app/support/json_file.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/model/probe.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "core/summary.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: workpieces, JSON files

namespace {

namespace fs = std::filesystem;

constexpr double kStockM = 0.12;  // the default scene's workpiece, tool and stroke depth
const Vec3 kCentreM(0.0, 0.0, 0.05);
constexpr double kToolRadiusM = 0.006;
constexpr double kDepthM = 0.004;
constexpr double kHalfLengthM = 0.045;
constexpr double kStepM = 0.0005;

enum class Marks { kSweptWhole, kSweptPartial, kChangedPartial };
const char* marks_name(Marks m) {
    return m == Marks::kSweptWhole     ? "swept box, whole tiles"
           : m == Marks::kSweptPartial ? "swept box, partial tiles"
                                       : "changed ends, partial tiles";
}

// The stroke's sweeps: the ball kDepthM below the front surface (+z: the height probe_top finds on the Z ray nearest
// each sample of the uncut model), every kStepM along x at y = 0.
std::vector<compute::Sweep> plan_stroke(const compute::TriDexel& model) {
    std::vector<Vec3> path;
    for (double x = -kHalfLengthM; x <= kHalfLengthM + 1e-12; x += kStepM) {
        Vec3 top;
        if (compute::probe_top(model, 2, Vec3(x, 0.0, kCentreM.z), top))
            path.push_back(Vec3(x, 0.0, top.z + kToolRadiusM - kDepthM));
    }
    if (path.size() < 2) throw Error("bench --contour: the workpiece has no front surface at y = 0");
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

ContourBenchRow run_marks(compute::TriDexel model, const std::vector<compute::Sweep>& stroke, Marks marks,
                          TriMesh& mesh) {
    compute::Contourer contourer(model);
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), compute::TileGrid::kWhole);
    contourer.update(model);  // the start: every tile, not timed
    ContourBenchRow r;
    r.marks = marks_name(marks);
    std::vector<double> ms;
    double tiles = 0.0, partial = 0.0, cells = 0.0;
    for (const compute::Sweep& s : stroke) {
        if (compute::apply_sweep(model, s).rays_changed > 0 && marks != Marks::kChangedPartial)
            model.mark_dirty(
                compute::sweep_dirty_bounds(s, model.lattice));  // grows each tile's box to the swept box's
        if (marks == Marks::kSweptWhole)
            for (std::uint8_t& d : model.tiles.dirty)
                if (d != 0) d = compute::TileGrid::kWhole;
        const auto t0 = std::chrono::steady_clock::now();
        contourer.update(model);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        const compute::ContourStats st = contourer.stats();
        tiles += static_cast<double>(st.tiles_recontoured);
        if (st.tiles_recontoured == 0) ++r.idle_steps;
        partial += static_cast<double>(st.tiles_partial);
        cells += static_cast<double>(st.cells_visited);
    }
    const double steps = static_cast<double>(stroke.size());
    r.steps = stroke.size();
    r.tiles_per_step = tiles / steps;
    r.partial_per_step = partial / steps;
    r.cells_per_step = cells / steps;
    const Summary sum = summarize(ms);
    r.ms_median = sum.median;
    r.ms_p99 = sum.p99;
    r.ms_mean = sum.mean;
    mesh = contourer.mesh();
    return r;
}

}  // namespace

std::vector<ContourBenchRow> run_contour_bench(const ContourBenchOptions& o) {
    for (const int n : o.resolutions)
        if (n < 16) throw Error("bench --contour: resolution " + std::to_string(n) + " is below 16 cells");
    const std::string mesh = o.mesh.empty() ? default_mesh_path() : o.mesh;
    fs::create_directories(o.out);
    std::printf(
        "contour: %s in %.2f m stock, a %.0f mm ball %.0f mm deep along x, %.1f mm per step; Contourer::update "
        "after each step on the CPU\n",
        mesh.c_str(), kStockM, kToolRadiusM * 1e3, kDepthM * 1e3, kStepM * 1e3);
    std::printf("%5s  %-28s %6s %5s %8s %8s %8s %9s %9s %9s %8s %5s\n", "N", "marks", "steps", "idle", "tiles",
                "partial", "cells", "ms med", "ms p99", "ms mean", "ratio", "same");
    std::vector<ContourBenchRow> rows;
    nlohmann::json jrows = nlohmann::json::array();
    for (const int n : o.resolutions) {
        const Workpiece wp = prepare_workpiece(mesh, n, kStockM, kCentreM);
        const std::vector<compute::Sweep> stroke = plan_stroke(wp.model);
        TriMesh first;
        double whole_ms = 0.0;
        for (const Marks m : {Marks::kSweptWhole, Marks::kSweptPartial, Marks::kChangedPartial}) {
            TriMesh got;
            ContourBenchRow r = run_marks(wp.model, stroke, m, got);
            r.n = n;
            if (m == Marks::kSweptWhole) {
                first = got;
                whole_ms = r.ms_mean;
            }
            r.same_mesh = got.positions == first.positions && got.triangles == first.triangles;
            r.ratio_to_whole = r.ms_mean > 0.0 ? whole_ms / r.ms_mean : 0.0;
            std::printf("%5d  %-28s %6zu %5zu %8.1f %8.1f %8.0f %9.3f %9.3f %9.3f %7.2fx %5s\n", n, r.marks.c_str(),
                        r.steps, r.idle_steps, r.tiles_per_step, r.partial_per_step, r.cells_per_step, r.ms_median,
                        r.ms_p99, r.ms_mean, r.ratio_to_whole, r.same_mesh ? "yes" : "NO");
            jrows.push_back({{"n", n},
                             {"marks", r.marks},
                             {"steps", r.steps},
                             {"idle_steps", r.idle_steps},
                             {"tiles_per_step", r.tiles_per_step},
                             {"partial_tiles_per_step", r.partial_per_step},
                             {"cells_per_step", r.cells_per_step},
                             {"ms_median", r.ms_median},
                             {"ms_p99", r.ms_p99},
                             {"ms_mean", r.ms_mean},
                             {"speedup_over_swept_whole", r.ratio_to_whole},
                             {"same_mesh", r.same_mesh}});
            rows.push_back(r);
        }
    }
    std::printf(
        "ratio: the swept box with whole tiles' mean over the row's (higher is faster); same: the final mesh "
        "equals that row's, bit for bit\n");
    const nlohmann::json setup{
        {"mesh", mesh},
        {"stock_m", kStockM},
        {"tool_radius_m", kToolRadiusM},
        {"depth_m", kDepthM},
        {"stroke", "along world x from -45 to +45 mm at y = 0, 0.5 mm steps, below the front surface"},
        {"measured", "compute::Contourer::update after each apply_sweep (CPU), whole run of the stroke"}};
    write_json_file((fs::path(o.out) / "contour_bench.json").string(), {{"rows", jrows}, {"setup", setup}});
    return rows;
}

namespace {

struct ContourBenchCli {
    std::vector<int> n;
};

BenchRun setup_contour_bench(CLI::App& bench) {
    auto o = std::make_shared<ContourBenchCli>();
    bench.add_option("--contour-n", o->n, "With --contour: run only these N, e.g. --contour-n 128")->delimiter(',');
    return [o](const BenchCommon& c) {
        ContourBenchOptions b;
        b.out = c.out;
        b.mesh = c.mesh;
        if (!o->n.empty()) b.resolutions = o->n;
        run_contour_bench(b);
    };
}

const BenchmarkRegistration kRegistration{
    {"contour",
     "The re-contour after each step of the default scene's stroke, marking the swept box with whole or partial tiles "
     "or the changed interval ends with partial tiles (ms per step, cells, tiles): N = 128, 256",
     96, setup_contour_bench}};

}  // namespace

}  // namespace tridex::bench
