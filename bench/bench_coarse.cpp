// bench/bench_coarse.cpp - `tridex bench --coarse`: the workpiece contoured straight from every 2nd, 4th, 8th and
// 16th ray of its tri-dexel model (compute/model/coarse_lattice.hpp) beside its full contour: time, triangles, memory
// and the two-sided distance between the two surfaces, in metres and in cells.
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/scene/workpiece_source.hpp"
#include "app/support/assets.hpp"
#include "app/support/json_file.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/surface_distance.hpp"
#include "compute/model/coarse_lattice.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "core/error.hpp"

namespace tridex::bench {
using namespace tridex::app;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kStockM = 0.12;  // the default scene's workpiece
const Vec3 kCentreM(0.0, 0.0, 0.05);

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Bytes of a model's rays (vector headers and interval storage), all three sets.
std::size_t ray_bytes(const compute::TriDexel& m) {
    std::size_t b = 0;
    for (const std::size_t set : cpu_model_bytes(m)) b += set;
    return b;
}

// Largest distance from every `step`-th of `points` to `surface`, m.
double largest_distance(const std::vector<Vec3>& points, std::size_t step, compute::TriangleGrid& surface) {
    double worst = 0.0;
    for (std::size_t i = 0; i < points.size(); i += step) worst = std::max(worst, surface.distance(points[i]));
    return worst;
}

struct CoarseRow {
    int n = 0, stride = 1;
    double read_ms = 0.0, contour_ms = 0.0;
    std::size_t triangles = 0, model_bytes = 0;
    double to_full_m = 0.0, from_full_m = 0.0;  // coarse surface -> full surface, full vertices -> coarse surface
};

nlohmann::json row_json(const CoarseRow& r, double full_ms, std::size_t full_triangles, double h) {
    return {{"n", r.n},
            {"stride", r.stride},
            {"read_ms", r.read_ms},
            {"contour_ms", r.contour_ms},
            {"time_vs_full", (r.read_ms + r.contour_ms) / full_ms},
            {"triangles", r.triangles},
            {"triangles_vs_full", double(r.triangles) / double(full_triangles)},
            {"model_bytes", r.model_bytes},
            {"coarse_to_full_m", r.to_full_m},
            {"full_to_coarse_m", r.from_full_m},
            {"distance_fine_cells", std::max(r.to_full_m, r.from_full_m) / h},
            {"distance_coarse_cells", std::max(r.to_full_m, r.from_full_m) / (h * r.stride)}};
}

void run_coarse_bench(const std::vector<int>& resolutions, const BenchCommon& c) {
    for (const int n : resolutions)
        if (n < 32) throw Error("bench --coarse: resolution " + std::to_string(n) + " is below 32 cells");
    const std::string mesh = c.mesh.empty() ? default_mesh_path() : c.mesh;
    fs::create_directories(c.out);
    std::printf("coarse: %s in %.2f m stock; each stride's model read from the full one (every stride-th ray) and "
                "contoured whole on the CPU pool, beside the full contour\n",
                mesh.c_str(), kStockM);
    std::printf("%5s %6s %9s %10s %8s %11s %8s %9s %12s %10s %10s\n", "N", "stride", "read ms", "contour ms", "time x",
                "triangles", "tri x", "MiB", "distance mm", "fine cells", "coarse c.");
    nlohmann::json jrows = nlohmann::json::array(), startup = nlohmann::json::array();
    for (const int n : resolutions) {
        const Workpiece wp = prepare_workpiece(mesh, n, kStockM, kCentreM);
        const double h = wp.model.lattice.cell_m;
        compute::TriDexel full_model = wp.model;
        auto t0 = Clock::now();
        compute::Contourer full(full_model);
        full.update(full_model);
        const double full_ms = ms_since(t0);
        const TriMesh full_mesh = full.mesh();
        const std::size_t full_triangles = full_mesh.triangles.size();
        CoarseRow f{n, 1, 0.0, full_ms, full_triangles, ray_bytes(wp.model), 0.0, 0.0};
        std::printf("%5d %6d %9s %10.0f %8s %11zu %8s %9.1f %12s %10s %10s\n", n, 1, "-", full_ms, "1.00",
                    full_triangles, "1.000", f.model_bytes / 1048576.0, "-", "-", "-");
        jrows.push_back(row_json(f, full_ms, full_triangles, h));
        double plain_refresh_ms = 0.0;
        {  // the baseline: a first refresh without coarse groups (the tiles' meshes; levels deferred to a worker)
            compute::TileSurfaceCache cache;
            compute::TileLodOptions lo;
            lo.cell_m = h;
            cache.enable_lod(lo);
            cache.defer_lods(true);
            t0 = Clock::now();
            cache.refresh(full);
            plain_refresh_ms = ms_since(t0);
        }
        {  // what a session's start-up adds: the coarse models and contours, then every group's level
            compute::TileSurfaceCache cache;
            compute::TileLodOptions lo;
            lo.cell_m = h;
            cache.enable_lod(lo);
            cache.defer_lods(true);  // the tiles' own levels wait for a worker in a session
            t0 = Clock::now();
            cache.use_coarse_groups(full_model);
            const double models_ms = ms_since(t0);
            t0 = Clock::now();
            cache.refresh(full);
            const double levels_ms = ms_since(t0);
            std::size_t level_triangles = 0;
            for (const compute::TileGroupSurface& g : cache.groups())
                for (const compute::TileLodLevel& l : g.lods) level_triangles += l.mesh.triangles.size();
            std::printf("%5d start-up: coarse models and contours %.0f ms, first refresh with %zu group levels (%zu "
                        "triangles, rings and skirts included) %.0f ms, against %.0f ms without\n",
                        n, models_ms, cache.groups().size(), level_triangles, levels_ms, plain_refresh_ms);
            startup.push_back({{"n", n}, {"coarse_models_ms", models_ms}, {"first_refresh_ms", levels_ms}, {"first_refresh_without_ms", plain_refresh_ms},
                               {"groups", cache.groups().size()}, {"group_level_triangles", level_triangles}});
        }
        compute::TriangleGrid full_grid(full_mesh, 8.0 * h);
        // Every full vertex is checked up to N = 256; above, every (N / 256)^2-th (the distance search dominates).
        const std::size_t step = n > 256 ? static_cast<std::size_t>((n / 256) * (n / 256)) : 1;
        for (const int stride : {2, 4, 8, 16}) {  // 16: a session's coarsest depth
            CoarseRow r;
            r.n = n;
            r.stride = stride;
            t0 = Clock::now();
            compute::TriDexel cm = compute::coarse_model(wp.model, stride);
            r.read_ms = ms_since(t0);
            t0 = Clock::now();
            compute::Contourer cc(cm);
            cc.update(cm);
            r.contour_ms = ms_since(t0);
            const TriMesh coarse_mesh = cc.mesh();
            r.triangles = coarse_mesh.triangles.size();
            r.model_bytes = ray_bytes(cm);
            r.to_full_m = largest_distance(compute::surface_samples(coarse_mesh, h * stride), 1, full_grid);
            compute::TriangleGrid coarse_grid(coarse_mesh, 4.0 * h * stride);
            r.from_full_m = largest_distance(full_mesh.positions, step, coarse_grid);
            const double d = std::max(r.to_full_m, r.from_full_m);
            std::printf("%5d %6d %9.1f %10.1f %8.3f %11zu %8.4f %9.1f %12.3f %10.2f %10.2f\n", n, stride, r.read_ms,
                        r.contour_ms, (r.read_ms + r.contour_ms) / full_ms, r.triangles,
                        double(r.triangles) / double(full_triangles), r.model_bytes / 1048576.0, d * 1e3, d / h,
                        d / (h * stride));
            jrows.push_back(row_json(r, full_ms, full_triangles, h));
        }
    }
    std::printf("time x / tri x: the stride's read plus contour time and triangles over the full contour's; distance: "
                "two-sided, the coarse surface's samples to the full surface and the full vertices (every "
                "(N / 256)^2-th above N = 256) to the coarse one\n");
    const nlohmann::json setup{{"mesh", mesh},
                               {"stock_m", kStockM},
                               {"measured", "compute::coarse_model then compute::Contourer::update of every tile, "
                                            "beside Contourer::update of the full model; wall time on the CPU pool"}};
    write_json_file((fs::path(c.out) / "coarse_bench.json").string(), {{"rows", jrows}, {"startup", startup}, {"setup", setup}});
}

BenchRun setup_coarse_bench(CLI::App& bench) {
    auto n = std::make_shared<std::vector<int>>();
    bench.add_option("--coarse-n", *n, "With --coarse: run only these N, e.g. --coarse-n 256")->delimiter(',');
    return [n](const BenchCommon& c) { run_coarse_bench(n->empty() ? std::vector<int>{256, 512, 1024} : *n, c); };
}

const BenchmarkRegistration kRegistration{
    {"coarse",
     "The workpiece contoured from every 2nd, 4th, 8th and 16th ray of its model beside its full contour (time, triangles, "
     "memory, two-sided distance in mm and cells): N = 256, 512, 1024",
     97, setup_coarse_bench}};

}  // namespace

}  // namespace tridex::bench
