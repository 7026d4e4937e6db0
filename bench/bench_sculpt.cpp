// bench/bench_sculpt.cpp - timing the sculpting paths (CPU one thread / all cores, GPU per segment / batched).
#include "bench/bench_sculpt.hpp"
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <numeric>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>

#include "app/support/json_file.hpp"
#include "core/summary.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/gpu/gpu_clay.hpp"
#include "compute/gpu/gpu_dexel_slabs.hpp"
#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/clay_push.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/parallel/task_pool.hpp"
#include "compute/tools/sweep_parallel.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions, stats and JSON files
namespace {

using Clock = std::chrono::steady_clock;
using compute::Sweep;
using compute::TriDexel;

constexpr double kStockM = 0.3;       // lattice side, m
constexpr double kMarginCells = 4.0;  // the box covers grid [4, N-4]^3
constexpr double kDepthCells = 3.37;  // groove depth below the top face (the ball's centre sits off the nodes)
const std::string kPaths[] = {"cpu-1t",    "cpu",         "gpu",           "gpu-batched",
                               "clay-push", "clay-smooth", "gpu-clay-push", "gpu-clay-smooth"};  // in row order

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The workpiece: a box over grid [4, N-4]^3 of an N^3-cell lattice of side 0.3 m, scan-converted.
TriDexel box_workpiece(int n) {
    compute::Lattice L;
    L.origin_m = Vec3(0.0);
    L.cell_m = kStockM / n;
    L.cells = {n, n, n};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 36);
    scan_convert(box_mesh(Aabb{L.to_world(Vec3(kMarginCells)), L.to_world(Vec3(n - kMarginCells))}), m);
    return m;
}

/// A ball (subtract) carving a random-walk groove kDepthCells deep into the top face: segments of
/// 0.5..1 cell, heading turning by a few degrees per segment, turning back near the box's edges. A 64-bit
/// LCG with a fixed seed: the same walk (relative to the centre of the top face) at every N.
std::vector<Sweep> groove_stroke(const compute::Lattice& L, double radius_cells, int segments) {
    std::uint64_t state = 0x2545F4914F6CDD1Dull;
    auto uniform = [&state] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
    };
    const double n = L.cells[0];
    const double lo = kMarginCells + radius_cells + 2.0, hi = n - lo;
    // Off the lattice nodes (+0.37 cell), so footprints do not hinge on rounding at a node.
    const double z = n - kMarginCells + radius_cells - kDepthCells;
    Vec3 p(0.5 * n + 0.37, 0.5 * n + 0.37, z);
    double heading = 0.0;
    std::vector<Sweep> out;
    out.reserve(static_cast<std::size_t>(segments));
    Sweep s;
    s.op = ToolOp::kSubtract;
    s.tool = compute::SweepTool{compute::ToolKind::kBall, radius_cells * L.cell_m, 0.0};
    s.material = 1;
    for (int i = 0; i < segments; ++i) {
        heading += (uniform() - 0.5) * 0.6;
        const double len = 0.5 + 0.5 * uniform();
        Vec3 q = p + len * Vec3(std::cos(heading), std::sin(heading), 0.0);
        if (q.x < lo || q.x > hi || q.y < lo || q.y > hi) {  // turn towards the centre
            heading = std::atan2(0.5 * n - p.y, 0.5 * n - p.x) + (uniform() - 0.5);
            q = p + len * Vec3(std::cos(heading), std::sin(heading), 0.0);
        }
        s.path_m = Segment{L.to_world(p), L.to_world(q)};
        out.push_back(s);
        p = q;
    }
    return out;
}

/// Footprint rays of each segment (all three sets), as the Boolean paths count them.
std::vector<double> footprints(const TriDexel& m, std::span<const Sweep> stroke) {
    std::vector<double> out;
    out.reserve(stroke.size());
    for (const Sweep& s : stroke) {
        const compute::GridSweep g = compute::to_grid_sweep(m.lattice, s);
        double rays = 0.0;
        for (const compute::RaySet& set : m.sets) {
            int u0, u1, v0, v1;
            if (compute::sweep_footprint(g, set, u0, u1, v0, v1)) rays += double(u1 - u0 + 1) * double(v1 - v0 + 1);
        }
        out.push_back(rays);
    }
    return out;
}

/// FNV-1a 64 over every ray (count, depth bits, materials) of all three sets, as 16 hex digits.
std::string model_hash(const TriDexel& m) {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&h](const void* p, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
    };
    for (const compute::RaySet& set : m.sets)
        for (const auto& ray : set.rays) {
            const std::uint32_t count = static_cast<std::uint32_t>(ray.size());
            mix(&count, 4);
            for (const compute::Interval& iv : ray) {
                mix(&iv.enter, 4);
                mix(&iv.exit, 4);
                mix(&iv.enter_material, 1);
                mix(&iv.exit_material, 1);
            }
        }
    char buf[17];
    std::snprintf(buf, sizeof(buf), "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

/// A step function: applies stroke[first, first + count) to the path's model; returns rays visited.
using StepFn = std::function<std::size_t(std::span<const Sweep>)>;

/// Carves `stroke` from its start in steps of `batch` segments until the options' limits, re-contouring
/// the dirty tiles after each step, and fills the row's timings.
void run_row(const SculptBenchOptions& o, TriDexel& m, compute::Contourer& contourer, std::span<const Sweep> stroke,
             const std::vector<double>& rays_of, const StepFn& step, SculptBenchRow& row) {
    std::vector<double> step_ms, latency_ms;
    std::size_t rays = 0;
    double cpu_s = 0.0;
    const auto process_cpu_s = [] {
        timespec t{};
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
        return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
    };
    const auto wall0 = Clock::now();
    while (row.segments < stroke.size() && row.boolean_s < o.min_boolean_s && seconds_since(wall0) < o.max_row_s) {
        const std::size_t count = std::min<std::size_t>(static_cast<std::size_t>(row.batch), stroke.size() - row.segments);
        const double c0 = process_cpu_s();
        const auto t0 = Clock::now();
        rays += step(stroke.subspan(row.segments, count));
        const auto t1 = Clock::now();
        cpu_s += process_cpu_s() - c0;
        row.tiles_contoured += contourer.update(m);
        const auto t2 = Clock::now();
        const double b = std::chrono::duration<double>(t1 - t0).count(), c = std::chrono::duration<double>(t2 - t1).count();
        row.boolean_s += b;
        row.contour_s += c;
        step_ms.push_back(1e3 * b);
        row.step_s.push_back(b);
        latency_ms.push_back(1e3 * (b + c));
        row.segments += count;
        ++row.steps;
    }
    row.segments_per_s = row.boolean_s > 0.0 ? static_cast<double>(row.segments) / row.boolean_s : 0.0;
    row.rays_per_s = row.boolean_s > 0.0 ? static_cast<double>(rays) / row.boolean_s : 0.0;
    row.tiles_contoured_per_s = row.contour_s > 0.0 ? static_cast<double>(row.tiles_contoured) / row.contour_s : 0.0;
    row.step_ms_median = summarize(step_ms).median;
    row.step_cpu_ms = row.steps > 0 ? 1e3 * cpu_s / static_cast<double>(row.steps) : 0.0;
    row.latency_ms = summarize(latency_ms).median;
    row.rays_per_segment = summarize(std::vector<double>(rays_of.begin(), rays_of.begin() + static_cast<std::ptrdiff_t>(row.segments))).median;
    row.model_hash = model_hash(m);
}

/// The model's own volume, m^3: the mean of the three sets' interval lengths (ray_set_volume_m3), the measure the
/// clay tools keep. dexel_volume_m3's face correction is left out: it changes wherever a clay tool bends a face that
/// lies on the lattice's nodes (the bench's workpiece), by up to half a cell times the area bent.
double raw_volume_m3(const TriDexel& m) {
    return (compute::ray_set_volume_m3(m, 0) + compute::ray_set_volume_m3(m, 1) + compute::ray_set_volume_m3(m, 2)) / 3.0;
}

/// The clay row's volume drift and three-set disagreement (SculptBenchRow): `before` is the workpiece the row
/// started from, `after` the model it left.
void clay_row_checks(const TriDexel& before, const TriDexel& after, std::span<const Sweep> stroke, SculptBenchRow& row) {
    const double cell3 = std::pow(after.lattice.cell_m, 3.0);
    row.volume_before_cells3 = raw_volume_m3(before) / cell3;
    row.volume_change_cells3 = raw_volume_m3(after) / cell3 - row.volume_before_cells3;
    row.volume_drift_per_1000_cells3 =
        row.segments > 0 ? row.volume_change_cells3 * 1000.0 / static_cast<double>(row.segments) : 0.0;
    std::vector<compute::GridSweep> grid;
    for (std::size_t k = 0; k < row.segments; ++k) {
        Sweep s = stroke[k];
        s.op = ToolOp::kPush;  // the larger reach of push and smooth
        grid.push_back(compute::to_clay_grid_sweep(after.lattice, s));
    }
    const compute::ClayBox box = compute::clay_sweeps_box(grid);
    row.disagreement_before = compute::clay_set_disagreement(before, box);
    row.disagreement_after = compute::clay_set_disagreement(after, box);
}

}  // namespace

double seconds_for_segments(const SculptBenchRow& row, std::size_t segments) {
    const std::size_t batch = static_cast<std::size_t>(std::max(row.batch, 1));
    const std::size_t steps = std::min(row.step_s.size(), (segments + batch - 1) / batch);
    double s = 0.0;
    for (std::size_t i = 0; i < steps; ++i) s += row.step_s[i];
    return s;
}

namespace {

void check_options(const SculptBenchOptions& o) {
    if (o.resolutions.empty() || o.radii_cells.empty()) throw Error("bench --sculpt: no resolutions or radii to measure");
    for (const int n : o.resolutions)
        if (n < 24 || n > 2048) throw Error("bench --sculpt: resolution must be in 24..2048, got " + std::to_string(n));
    for (const int n : o.resolutions)
        for (const double r : o.radii_cells)
            if (!(r > 0.0) || r > n / 8.0)
                throw Error("bench --sculpt: tool radius must be in (0, N/8] cells, got " + std::to_string(r) + " at N = " + std::to_string(n));
    if (o.batch < 1 || o.max_segments < 1) throw Error("bench --sculpt: batch and max_segments must be >= 1");
    if (o.paths.empty()) throw Error("bench --sculpt: no paths to run (--sculpt-paths)");
    for (std::size_t i = 0; i < o.paths.size(); ++i) {
        if (std::find(std::begin(kPaths), std::end(kPaths), o.paths[i]) == std::end(kPaths))
            throw Error("bench --sculpt: unknown path '" + o.paths[i] +
                        "' (--sculpt-paths: cpu-1t, cpu, gpu, gpu-batched, clay-push, clay-smooth, gpu-clay-push, gpu-clay-smooth)");
        if (std::find(o.paths.begin(), o.paths.begin() + static_cast<std::ptrdiff_t>(i), o.paths[i]) != o.paths.begin() + static_cast<std::ptrdiff_t>(i))
            throw Error("bench --sculpt: path '" + o.paths[i] + "' given twice (--sculpt-paths)");
    }
}

std::size_t total(const std::array<compute::SlabBytes, 3>& b) { return b[0].total() + b[1].total() + b[2].total(); }

nlohmann::json bytes_json(const std::array<compute::SlabBytes, 3>& b) {
    nlohmann::json sets = nlohmann::json::array();
    for (const auto& s : b)
        sets.push_back({{"meta", s.meta}, {"inline_depth", s.inline_depth}, {"inline_mat", s.inline_mat}, {"pool", s.pool}, {"total", s.total()}});
    return {{"per_set", sets}, {"total", total(b)}};
}

const SculptBenchRow* find(const std::vector<SculptBenchRow>& rows, int n, double r, const std::string& path) {
    for (const auto& row : rows)
        if (row.n == n && row.radius_cells == r && row.path == path) return &row;
    return nullptr;
}

}  // namespace

namespace {

/// The Vulkan device for the gpu rows: none when the caller disabled them (o.gpu false) or no device is usable; says
/// which on stdout.
std::unique_ptr<gpu::Context> open_gpu(const SculptBenchOptions& o) {
    std::unique_ptr<gpu::Context> ctx;
    if (!o.gpu) {
        std::printf("gpu rows skipped: disabled by the caller\n");
        return ctx;
    }
    try {
        ctx = std::make_unique<gpu::Context>(gpu::Context::create({}));
        std::printf("gpu: %s (validation %s; %d driver worker threads pinned one per core)\n", ctx->device_name().c_str(),
                    ctx->validation_enabled() ? "on" : "off", ctx->spread_driver_threads());
    } catch (const Error& e) {
        std::printf("gpu rows skipped: no usable Vulkan device (%s)\n", e.what());
    }
    return ctx;
}

/// The apply step of path `p` (kPaths) on model m: CPU subtract one sweep at a time or on `threads` threads, CPU clay,
/// or on the GPU of `ctx` through the sculptor (and clay tools) it makes in `sculptor` (and `clay`), which must
/// outlive the step. Returns the rays each call visited.
StepFn path_step(const std::string& p, TriDexel& m, int threads, gpu::Context* ctx,
                 std::unique_ptr<compute::GpuSculptor>& sculptor, std::unique_ptr<compute::GpuClay>& clay) {
    if (p == "cpu-1t") {
        return [&m](std::span<const Sweep> b) {
            std::size_t rays = 0;
            for (const Sweep& s : b) rays += compute::apply_sweep(m, s).rays_visited;
            return rays;
        };
    }
    if (p == "clay-push" || p == "clay-smooth") {
        const ToolOp op = p == "clay-push" ? ToolOp::kPush : ToolOp::kSmooth;
        return [&m, op](std::span<const Sweep> b) {
            std::vector<Sweep> clay(b.begin(), b.end());
            for (Sweep& s : clay) s.op = op;
            return compute::apply_clay_batch(m, clay).rays_visited;
        };
    }
    if (p == "gpu-clay-push" || p == "gpu-clay-smooth") {
        const ToolOp op = p == "gpu-clay-push" ? ToolOp::kPush : ToolOp::kSmooth;
        sculptor = std::make_unique<compute::GpuSculptor>(*ctx, m);
        clay = std::make_unique<compute::GpuClay>(*ctx, *sculptor);
        return [&m, &clay, op](std::span<const Sweep> b) {
            std::vector<Sweep> ops(b.begin(), b.end());
            for (Sweep& s : ops) s.op = op;
            return compute::apply_clay_batch(m, ops, nullptr, *clay).rays_visited;
        };
    }
    if (p == "cpu")
        return [&m, threads](std::span<const Sweep> b) { return compute::apply_sweeps_parallel(m, b, threads).rays_visited; };
    sculptor = std::make_unique<compute::GpuSculptor>(*ctx, m);
    return [&sculptor](std::span<const Sweep> b) { return sculptor->apply(b).rays_visited; };
}

/// The row of path `p` at N = n with a ball of `r` cells: `stroke` (footprint rays `rays_of`) applied to a copy of the
/// workpiece `pristine_model` and its contour, timed (run_row) and printed; a GPU row's slab bytes after the run go to
/// `after`.
SculptBenchRow sculpt_row(const SculptBenchOptions& o, const std::string& p, int n, double r, const TriDexel& pristine_model,
                          const compute::Contourer& pristine_contour, std::span<const Sweep> stroke,
                          const std::vector<double>& rays_of, int threads, gpu::Context* ctx,
                          std::optional<std::array<compute::SlabBytes, 3>>& after) {
    SculptBenchRow row;
    row.n = n;
    row.radius_cells = r;
    row.path = p;
    row.batch = (p == "cpu" || p == "gpu-batched" || p.find("clay") != std::string::npos) ? o.batch : 1;
    TriDexel m = pristine_model;
    compute::Contourer contourer = pristine_contour;
    std::unique_ptr<compute::GpuSculptor> sculptor;
    std::unique_ptr<compute::GpuClay> clay;
    const StepFn step = path_step(p, m, threads, ctx, sculptor, clay);
    const bool clay_row = p.find("clay") != std::string::npos;
    run_row(o, m, contourer, stroke, rays_of, step, row);
    if (clay_row) clay_row_checks(pristine_model, m, stroke, row);
    if (sculptor) {
        after = sculptor->slabs().bytes();
        const compute::GpuSculptStats& st = sculptor->stats();
        row.gpu_ray_tiles = st.ray_tiles;
        row.gpu_retried_rays = st.retried_rays;
        const double per = st.batches > 0 ? 1e3 / static_cast<double>(st.batches) : 0.0;
        row.gpu_prepare_ms = st.prepare_s * per;
        row.gpu_submit_ms = st.submit_s * per;
        row.gpu_finish_ms = st.finish_s * per;
    }
    std::printf("%5d %4.0f %-11s %7zu %10.0f %11.3g %9.0f %9.3f %9.3f %8.0f\n", n, r, p.c_str(), row.segments,
                row.segments_per_s, row.rays_per_s, row.tiles_contoured_per_s, row.step_ms_median, row.latency_ms,
                row.rays_per_segment);
    std::printf("%5s %4s   process CPU time per apply call %.3f ms (all threads)", "", "", row.step_cpu_ms);
    if (sculptor && sculptor->stats().batches > 0) {
        const double batches = static_cast<double>(sculptor->stats().batches);
        std::printf("; mean per submission: host before %.3f ms, submit to fence %.3f ms, host after %.3f ms, "
                    "%.0f ray tiles, %.0f workgroups", row.gpu_prepare_ms, row.gpu_submit_ms, row.gpu_finish_ms,
                    static_cast<double>(row.gpu_ray_tiles) / batches,
                    static_cast<double>(sculptor->stats().workgroups) / batches);
    }
    std::printf("\n");
    std::fflush(stdout);
    return row;
}

bool is_clay(const std::string& path) { return path.find("clay") != std::string::npos; }

/// Prints every parallel path against the best single-thread path of its N and radius over the same first segments.
/// Single-thread paths: "cpu-1t", and "cpu" when the pool has one thread (`threads`); every other path (the GPU ones,
/// "cpu" on several threads) is parallel. Clay rows are compared by print_clay_ratios.
void print_parallel_ratios(const std::vector<SculptBenchRow>& rows, int threads) {
    const auto single_thread = [&](const std::string& path) { return path == "cpu-1t" || (path == "cpu" && threads == 1); };
    std::printf("parallel path / best single-thread path segments_per_s over the same first segments of the stroke "
                "(target cpu >= 1.7 on 2 cores):\n");
    for (const auto& row : rows) {
        if (single_thread(row.path) || is_clay(row.path)) continue;
        const SculptBenchRow* best = nullptr;
        for (const auto& one : rows)
            if (one.n == row.n && one.radius_cells == row.radius_cells && single_thread(one.path) &&
                (!best || one.segments_per_s > best->segments_per_s))
                best = &one;
        if (!best || best->segments_per_s <= 0.0) {
            std::printf("  N=%4d r=%2.0f %-11s: no single-thread row (add cpu-1t to --sculpt-paths)\n", row.n, row.radius_cells,
                        row.path.c_str());
            continue;
        }
        // Both over the same segments: the rows run different lengths of the stroke, whose cost per segment varies
        // along it (fresh material, crossings of its own groove).
        const std::size_t lcm = std::lcm(static_cast<std::size_t>(std::max(row.batch, 1)),
                                         static_cast<std::size_t>(std::max(best->batch, 1)));
        const std::size_t common = std::min(row.segments, best->segments) / lcm * lcm;
        const double t_row = seconds_for_segments(row, common), t_best = seconds_for_segments(*best, common);
        if (common == 0 || !(t_row > 0.0) || !(t_best > 0.0)) {
            std::printf("  N=%4d r=%2.0f %-11s: too few common segments to compare\n", row.n, row.radius_cells,
                        row.path.c_str());
            continue;
        }
        std::printf("  N=%4d r=%2.0f %-11s: %.2f  (vs %s, first %zu segments; whole rows %.2f)\n", row.n,
                    row.radius_cells, row.path.c_str(), t_best / t_row, best->path.c_str(), common,
                    row.segments_per_s / best->segments_per_s);
    }
}

/// Prints each clay row's time per segment against one-thread subtract (cpu-1t) over the same first segments (batch
/// `batch`), a Vulkan clay row also against the Vulkan subtract; then each clay row's volume change and three-set
/// disagreement.
void print_clay_ratios(const std::vector<SculptBenchRow>& rows, int batch) {
    std::printf("clay / cpu-1t ms per segment over the same first segments of the stroke (clay-*: CPU reference, "
                "one thread, %d segments per apply_clay_batch; gpu-clay-*: Vulkan) against one-thread subtract "
                "(target <= 2):\n", batch);
    for (const auto& row : rows) {
        if (!is_clay(row.path)) continue;
        const SculptBenchRow* one = find(rows, row.n, row.radius_cells, "cpu-1t");
        if (!one) continue;
        const std::size_t b = static_cast<std::size_t>(std::max(row.batch, 1));
        const std::size_t common = std::min(row.segments, one->segments) / b * b;
        const double t_row = seconds_for_segments(row, common), t_one = seconds_for_segments(*one, common);
        if (common == 0 || !(t_row > 0.0) || !(t_one > 0.0)) continue;
        std::printf("  N=%4d r=%2.0f %-15s: %.1f  (%.4f ms against %.4f ms, first %zu segments)", row.n,
                    row.radius_cells, row.path.c_str(), t_row / t_one, 1e3 * t_row / static_cast<double>(common),
                    1e3 * t_one / static_cast<double>(common), common);
        // A Vulkan clay row beside the Vulkan subtract on the same device too: batched as the clay rows are when
        // that row ran, else per segment.
        if (row.path.rfind("gpu-", 0) == 0) {
            for (const char* g : {"gpu-batched", "gpu"}) {
                const SculptBenchRow* sub = find(rows, row.n, row.radius_cells, g);
                if (!sub) continue;
                const std::size_t l = std::lcm(b, static_cast<std::size_t>(std::max(sub->batch, 1)));
                const std::size_t c = std::min(row.segments, sub->segments) / l * l;
                const double tr = seconds_for_segments(row, c), ts = seconds_for_segments(*sub, c);
                if (c == 0 || !(tr > 0.0) || !(ts > 0.0)) continue;
                std::printf("; %.1f against Vulkan subtract (%s, %.4f ms, first %zu segments)", tr / ts, g,
                            1e3 * ts / static_cast<double>(c), c);
                break;
            }
        }
        std::printf("\n");
    }
    std::printf("clay rows: the model's volume change (the three sets' mean interval length) over the row and per 1,000 segments, and the "
                "three-set disagreement (nodes) in the sweeps' box before -> after:\n");
    for (const auto& row : rows) {
        if (!is_clay(row.path)) continue;
        std::printf("  N=%4d r=%2.0f %-15s: %+.3g cells^3 over %zu segments (%+.3g%% of %.4g); %+.3g cells^3 per 1,000; "
                    "disagreement %zu -> %zu\n", row.n, row.radius_cells, row.path.c_str(), row.volume_change_cells3,
                    row.segments, 100.0 * row.volume_change_cells3 / std::max(row.volume_before_cells3, 1e-30),
                    row.volume_before_cells3, row.volume_drift_per_1000_cells3, row.disagreement_before,
                    row.disagreement_after);
    }
}

/// Prints batched GPU against all-cores CPU throughput, and the step cost of the largest N against the smallest
/// (`resolutions`) per radius and path.
void print_gpu_and_scaling(const std::vector<SculptBenchRow>& rows, const std::vector<int>& resolutions) {
    std::printf("gpu-batched / cpu segments_per_s (target >= 0.5 when a batch's footprint > 10,000 rays):\n");
    for (const auto& row : rows) {
        if (row.path != "cpu") continue;
        const SculptBenchRow* g = find(rows, row.n, row.radius_cells, "gpu-batched");
        if (!g || row.segments_per_s <= 0.0) continue;
        const double batch_rays = row.rays_per_segment * row.batch;
        std::printf("  N=%4d r=%2.0f: %.2f  (footprint %.0f rays/segment, %.0f rays/batch%s)\n", row.n, row.radius_cells,
                    g->segments_per_s / row.segments_per_s, row.rays_per_segment, batch_rays, batch_rays > 1e4 ? " > 10,000" : "");
    }
    const int n_lo = *std::min_element(resolutions.begin(), resolutions.end());
    const int n_hi = *std::max_element(resolutions.begin(), resolutions.end());
    std::printf("step_ms_median N=%d / N=%d (target <= 1.5); latency ratio in brackets:\n", n_hi, n_lo);
    for (const auto& row : rows) {
        if (row.n != n_lo) continue;
        const SculptBenchRow* hi = find(rows, n_hi, row.radius_cells, row.path);
        if (!hi || row.step_ms_median <= 0.0 || row.latency_ms <= 0.0) continue;
        std::printf("  r=%2.0f %-11s: %.2f  (%.2f)\n", row.radius_cells, row.path.c_str(), hi->step_ms_median / row.step_ms_median,
                    hi->latency_ms / row.latency_ms);
    }
}

/// Interval storage of a one-interval-per-ray model at N = 1024 (the inline slots: depths + materials; and the per-ray
/// meta), printed against the 64 MiB target and returned as the setup JSON's entry.
nlohmann::json interval_storage_n1024() {
    compute::Lattice l1024;
    l1024.cell_m = kStockM / 1024;
    l1024.cells = {1024, 1024, 1024};
    const auto b1024 = compute::GpuDexelSlabs::bytes_for(l1024, 0);
    std::size_t inline_bytes = 0, meta_bytes = 0;
    for (const auto& s : b1024) {
        inline_bytes += s.inline_depth + s.inline_mat;
        meta_bytes += s.meta;
    }
    const double mib = static_cast<double>(inline_bytes) / (1024.0 * 1024.0);
    std::printf("interval storage at N=1024, one interval per ray (inline depths + materials, 3 x 1025^2 rays): %.1f MiB "
                "(target 64 MiB: %s); + per-ray meta %.1f MiB\n", mib, mib <= 64.0 ? "fits" : "does not fit",
                static_cast<double>(meta_bytes) / (1024.0 * 1024.0));
    return {{"bytes", inline_bytes}, {"mib", mib}, {"target_mib", 64}, {"fits", mib <= 64.0}, {"meta_bytes", meta_bytes},
            {"layout", "per ray 2 inline (enter, exit) float pairs + 4 material bytes"}};
}

/// Writes sculpt_bench.json (the list of rows, one object per path and size) and, beside it, sculpt_bench_setup.json
/// (the set-up, the device and the memory: `memory` per N and `storage`) into `out`; prints their paths.
void write_sculpt_json(const std::vector<SculptBenchRow>& rows, int threads, const gpu::Context* ctx,
                       const nlohmann::json& memory, const nlohmann::json& storage, const std::string& out) {
    nlohmann::json jrows = nlohmann::json::array();
    for (const auto& r : rows)
        jrows.push_back({{"n", r.n}, {"radius_cells", r.radius_cells}, {"path", r.path}, {"batch", r.batch},
                         {"segments", r.segments}, {"steps", r.steps}, {"segments_per_s", r.segments_per_s},
                         {"rays_per_s", r.rays_per_s}, {"tiles_contoured_per_s", r.tiles_contoured_per_s},
                         {"latency_ms", r.latency_ms}, {"step_ms_median", r.step_ms_median}, {"step_cpu_ms", r.step_cpu_ms},
                         {"rays_per_segment", r.rays_per_segment}, {"boolean_s", r.boolean_s}, {"contour_s", r.contour_s},
                         {"tiles_contoured", r.tiles_contoured}, {"contour", "cpu"},
                         {"threads", r.path == "cpu" ? threads : 1}, {"model_hash", r.model_hash},
                         {"gpu_ray_tiles", r.gpu_ray_tiles}, {"gpu_retried_rays", r.gpu_retried_rays},
                         {"volume_change_cells3", r.volume_change_cells3},
                         {"volume_drift_per_1000_cells3", r.volume_drift_per_1000_cells3},
                         {"disagreement_before", r.disagreement_before}, {"disagreement_after", r.disagreement_after},
                         {"gpu_prepare_ms", r.gpu_prepare_ms}, {"gpu_submit_ms", r.gpu_submit_ms}, {"gpu_finish_ms", r.gpu_finish_ms}});
    nlohmann::json j = {
        {"workpiece", "box over grid [4, N-4]^3 of an N^3-cell lattice, 0.3 m side (scan_convert of box_mesh)"},
        {"stroke", "ball subtract, random-walk groove 3.37 cells deep into the top face, segments 0.5..1 cell"},
        {"gpu_device", ctx ? ctx->device_name() : std::string()},
        {"gpu_driver_threads_pinned", ctx ? ctx->spread_driver_threads() : 0},
        {"memory", {{"gpu_slabs", memory}, {"interval_storage_n1024", storage}}}};
    const std::string path = (std::filesystem::path(out) / "sculpt_bench.json").string();
    const std::string info = (std::filesystem::path(out) / "sculpt_bench_setup.json").string();
    write_json_file(path, jrows);
    write_json_file(info, j);
    std::printf("wrote %s and %s\n", path.c_str(), info.c_str());
}

}  // namespace

std::vector<SculptBenchRow> run_sculpt_bench(const SculptBenchOptions& o) {
    check_options(o);
    const int threads = static_cast<int>(compute::pool_slots(o.threads));  // the task pool's threads
    const std::unique_ptr<gpu::Context> ctx = open_gpu(o);
    std::printf("workpiece: box over grid [4, N-4]^3 of an N^3 lattice (0.3 m side); ball subtract, random-walk groove "
                "%.2f cells deep in the top face, segments 0.5..1 cell; cpu = %d threads, batch %d; contour on the CPU\n",
                kDepthCells, threads, o.batch);
    std::vector<SculptBenchRow> rows;
    nlohmann::json memory = nlohmann::json::array();
    std::printf("%5s %4s %-11s %7s %10s %11s %9s %9s %9s %8s\n", "N", "r", "path", "segs", "segs/s", "rays/s",
                "tiles/s", "step_ms", "lat_ms", "rays/seg");
    for (const int n : o.resolutions) {
        auto t0 = Clock::now();
        TriDexel pristine_model = box_workpiece(n);
        compute::Contourer pristine_contour(pristine_model);
        pristine_contour.update(pristine_model);  // the whole box, once; each path starts from a copy
        std::printf("N=%d: workpiece and first contour %.1f s, %zu intervals\n", n, seconds_since(t0), pristine_model.interval_count());
        std::optional<std::array<compute::SlabBytes, 3>> after;
        for (const double r : o.radii_cells) {
            const std::vector<Sweep> stroke = groove_stroke(pristine_model.lattice, r, o.max_segments);
            const std::vector<double> rays_of = footprints(pristine_model, stroke);
            for (const std::string& p : kPaths) {
                if (std::find(o.paths.begin(), o.paths.end(), p) == o.paths.end()) continue;
                if (p.rfind("gpu", 0) == 0 && !ctx) continue;
                rows.push_back(sculpt_row(o, p, n, r, pristine_model, pristine_contour, stroke, rays_of, threads, ctx.get(), after));
            }
        }
        nlohmann::json mem = {{"n", n}, {"bytes_for_pool0", bytes_json(compute::GpuDexelSlabs::bytes_for(pristine_model.lattice, 0))}};
        mem["bytes_after_run"] = after ? bytes_json(*after) : nlohmann::json(nullptr);
        memory.push_back(mem);
    }
    // Targets: every parallel path against the best single-thread path; batched GPU vs all-cores CPU throughput;
    // step cost flat in N.
    print_parallel_ratios(rows, threads);
    print_clay_ratios(rows, o.batch);
    print_gpu_and_scaling(rows, o.resolutions);
    const nlohmann::json storage = interval_storage_n1024();
    write_sculpt_json(rows, threads, ctx.get(), memory, storage, o.out);
    return rows;
}

namespace {

BenchRun setup_sculpt_bench(CLI::App& bench) {
    auto o = std::make_shared<SculptBenchOptions>();
    auto n = std::make_shared<std::vector<int>>();
    auto radii = std::make_shared<std::vector<double>>();
    auto paths = std::make_shared<std::vector<std::string>>();
    bench.add_option("--sculpt-n", *n, "With --sculpt: run only these N (24..2048), e.g. --sculpt-n 256,512")->delimiter(',');
    bench.add_option("--sculpt-radius", *radii,
                     "With --sculpt: run only these tool radii, cells ((0, N/8]), e.g. --sculpt-radius 8")
        ->delimiter(',');
    bench.add_option("--sculpt-paths", *paths,
                     "With --sculpt: run only these paths (cpu-1t, cpu, gpu, gpu-batched; clay-push, clay-smooth, "
                     "gpu-clay-push, gpu-clay-smooth only when named), e.g. --sculpt-paths cpu,gpu-batched")
        ->delimiter(',');
    return [o, n, radii, paths](const BenchCommon& c) {
        SculptBenchOptions s = *o;
        s.out = c.out;
        if (!n->empty()) s.resolutions = *n;
        if (!radii->empty()) s.radii_cells = *radii;
        if (!paths->empty()) s.paths = *paths;
        run_sculpt_bench(s);
    };
}

const BenchmarkRegistration kRegistration{
    {"sculpt",
     "Swept-Boolean throughput and latency: CPU 1 thread / all cores, GPU per segment / batched, N = 256, 512, "
     "1024, tool radius 2 and 8 cells",
     70, setup_sculpt_bench}};

}  // namespace

}  // namespace tridex::bench
