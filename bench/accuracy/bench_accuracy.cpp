// bench/accuracy/bench_accuracy.cpp - run time against error: tridex paths and the OpenVDB peer on exact programs.
#include "bench/accuracy/bench_accuracy.hpp"
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>

#include "app/support/json_file.hpp"
#include "bench/accuracy/bench_accuracy_coarse.hpp"
#include "bench/accuracy/bench_accuracy_dump.hpp"
#include "bench/accuracy/bench_accuracy_exact.hpp"
#include "bench/accuracy/bench_accuracy_match.hpp"
#include "bench/accuracy/bench_accuracy_metrics.hpp"
#include "bench/accuracy/bench_accuracy_openvdb.hpp"
#include "bench/accuracy/bench_accuracy_plot.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/tools/sweep_parallel.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions, stats and JSON files
namespace {

using Clock = std::chrono::steady_clock;
using namespace accuracy;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr int kGpuBatch = 64;  // segments per GpuSculptor::apply and per apply_sweeps_parallel call
constexpr double kHalfWidthVoxels = 3.0;

/// Bytes of the CPU model: the per-ray vectors and their interval storage.
std::size_t model_bytes(const compute::TriDexel& m) {
    std::size_t b = 0;
    for (const auto& set : m.sets) {
        b += set.rays.capacity() * sizeof(std::vector<compute::Interval>);
        for (const auto& ray : set.rays) b += ray.capacity() * sizeof(compute::Interval);
    }
    return b;
}

/// The box workpiece on the N-cell lattice (origin shifted by -offset_cells cells), scan-converted.
compute::TriDexel workpiece(int n, double offset_cells) {
    compute::Lattice L;
    L.origin_m = Vec3(-offset_cells * kLatticeSideM / n);
    L.cell_m = kLatticeSideM / n;
    L.cells = {n, n, n};
    compute::TriDexel m = compute::TriDexel::empty(L, std::size_t{1} << 36);
    compute::scan_convert(box_mesh(Aabb{Vec3(kBoxLoM), Vec3(kBoxHiM)}), m);
    return m;
}

/// Per-program reference data, shared by every N and path.
struct Reference {
    Program program;
    std::unique_ptr<ExactSolid> exact;
    std::vector<Vec3> samples;
    double volume_m3 = 0.0, sigma_m3 = 0.0;
};

void fill_errors(AccuracyRow& row, const TriMesh& mesh, const Reference& ref, const Vec3& origin, int threads) {
    const SurfaceErrors e = surface_errors(mesh, *ref.exact, ref.samples, 2.0 * row.cell_m, threads);
    row.mean_error_m = e.mean_vertex_m;
    row.max_error_m = e.max_vertex_m;
    row.surface_mean_m = e.mean_surface_m;
    row.surface_max_m = e.max_surface_m;
    row.hausdorff_m = e.hausdorff_m;
    for (int a = 0; a < 3; ++a) {
        row.worst_vertex_cells[a] = (e.worst_vertex[a] - origin[a]) / row.cell_m;
        row.worst_sample_cells[a] = (e.worst_sample[a] - origin[a]) / row.cell_m;
    }
    row.vertices = e.vertices;
    row.surface_samples = e.samples;
    row.exact_volume_m3 = ref.volume_m3;
    row.volume_sigma_m3 = ref.sigma_m3;
    row.volume_error_rel = (row.volume_m3 - ref.volume_m3) / ref.volume_m3;
}

void print_row(const AccuracyRow& r) {
    const double c = r.cell_m;
    std::printf("%-7s %-6s %4d %-11s %5zu %9.2f %8.3f %7.1f %8.3f %7.3f %7.3f %7.3f %8.4f\n", r.method.c_str(), r.path.c_str(),
                r.n, r.program.c_str(), r.segments, 1e6 * r.time_per_segment_s, r.contour_s, r.memory_bytes / 1048576.0,
                100.0 * r.volume_error_rel, r.mean_error_m / c, r.max_error_m / c, r.hausdorff_m / c, 1e3 * r.max_error_m);
    std::fflush(stdout);
}

nlohmann::json row_json(const AccuracyRow& r) {
    return {{"method", r.method}, {"path", r.path}, {"n", r.n}, {"cell_m", r.cell_m}, {"program", r.program},
            {"segments", r.segments}, {"time_per_segment_s", r.time_per_segment_s}, {"contour_s", r.contour_s},
            {"memory_bytes", r.memory_bytes}, {"volume_m3", r.volume_m3}, {"exact_volume_m3", r.exact_volume_m3},
            {"exact_volume_sigma_m3", r.volume_sigma_m3}, {"volume_error_rel", r.volume_error_rel},
            {"mean_error_m", r.mean_error_m}, {"max_error_m", r.max_error_m}, {"surface_mean_m", r.surface_mean_m},
            {"surface_max_m", r.surface_max_m}, {"hausdorff_m", r.hausdorff_m},
            {"mean_error_cells", r.mean_error_m / r.cell_m}, {"max_error_cells", r.max_error_m / r.cell_m},
            {"hausdorff_cells", r.hausdorff_m / r.cell_m}, {"vertices", r.vertices},
            {"surface_samples", r.surface_samples}, {"worst_vertex_cells", r.worst_vertex_cells},
            {"worst_sample_cells", r.worst_sample_cells}, {"volume_change_m3", r.volume_change_m3}};
}

/// The accuracy targets of every tridex row: max vertex error <= kMaxErrorCells; |volume error| <
/// kVolumeErrorMax at N = 256.
constexpr double kMaxErrorCells = 0.45;
constexpr double kVolumeErrorMax = 0.001;

void print_targets(const std::vector<AccuracyRow>& rows) {
    std::printf("targets: max vertex error <= %.2f cells; |volume error| < %.1f%% at N=256\n", kMaxErrorCells, 100.0 * kVolumeErrorMax);
    for (const AccuracyRow& t : rows) {
        if (t.method != "tridex") continue;
        std::printf("  %-6s %4d %-11s max %.3f c %s", t.path.c_str(), t.n, t.program.c_str(), t.max_error_m / t.cell_m,
                    t.max_error_m <= kMaxErrorCells * t.cell_m ? "ok  " : "MISS");
        if (t.n == 256) std::printf(" vol %.4f%% %s", 100.0 * t.volume_error_rel, std::abs(t.volume_error_rel) < kVolumeErrorMax ? "ok" : "MISS");
        std::printf("\n");
    }
}

/// Prints one program's coarse levels at one N (errors in mm, fine cells and coarse cells) and returns them as
/// bench.json "coarse" entries.
nlohmann::json report_coarse(const std::string& program, int n, double cell_m, const Vec3& origin,
                             const std::vector<CoarseLevelErrors>& rows) {
    nlohmann::json out = nlohmann::json::array();
    for (const CoarseLevelErrors& r : rows) {
        const double c = r.coarse_cell_m;
        const auto cells_of = [&](const Vec3& p) {
            return std::array<double, 3>{(p.x - origin.x) / c, (p.y - origin.y) / c, (p.z - origin.z) / c};
        };
        std::printf("coarse  %-11s %4d d%d/%-2d %6zu %9zu %8.3f %8.2f %6.3f %6.3f %6.3f %6zu %6zu %6zu %7.2f %7zu\n",
                    program.c_str(), n, r.depth, r.stride, r.groups, r.triangles, 1e3 * r.group_max_m,
                    r.group_max_m / cell_m, r.group_p50_m / c, r.group_p90_m / c, r.group_max_m / c,
                    r.over_startup_estimate, r.over_level_estimate, r.over_dexel_estimate,
                    r.dexel_excess_max_m / cell_m, r.samples_without_level);
        out.push_back({{"program", program},
                       {"n", n},
                       {"cell_m", cell_m},
                       {"depth", r.depth},
                       {"stride", r.stride},
                       {"coarse_cell_m", c},
                       {"groups", r.groups},
                       {"triangles", r.triangles},
                       {"max_vertex_m", r.max_vertex_m},
                       {"max_surface_m", r.max_surface_m},
                       {"group_p50_m", r.group_p50_m},
                       {"group_p90_m", r.group_p90_m},
                       {"group_max_m", r.group_max_m},
                       {"group_max_fine_cells", r.group_max_m / cell_m},
                       {"group_max_coarse_cells", r.group_max_m / c},
                       {"over_startup_estimate", r.over_startup_estimate},
                       {"over_level_estimate", r.over_level_estimate},
                       {"over_dexel_estimate", r.over_dexel_estimate},
                       {"dexel_excess_max_m", r.dexel_excess_max_m},
                       {"samples_without_level", r.samples_without_level},
                       {"worst_vertex_coarse_cells", cells_of(r.worst_vertex)},
                       {"worst_sample_coarse_cells", cells_of(r.worst_sample)}});
    }
    std::fflush(stdout);
    return out;
}

/// bench.json's "setup": what was run and how it was measured.
nlohmann::json setup_json(const AccuracyBenchOptions& o, const std::vector<Reference>& refs, int threads) {
    nlohmann::json programs = nlohmann::json::array();
    for (const Reference& r : refs)
        programs.push_back({{"name", r.program.name},
                            {"moves", r.program.moves.size()},
                            {"segment_m", r.program.segment_m},
                            {"tool_radius_m", r.program.tool.radius_m},
                            {"exact_volume_m3", r.volume_m3},
                            {"exact_volume_sigma_m3", r.sigma_m3},
                            {"surface_samples", r.samples.size()}});
    return {
        {"workpiece",
         "0.1 m cube [0.014, 0.114]^3 m, lattice [0, 0.128]^3 m with N cells (cell_m = 0.128 / N), shifted by "
         "-offset_cells cells (0: the cube's faces lie on lattice nodes at N = 64, 128, 256)"},
        {"offset_cells", o.offset_cells},
        {"tridex_threads", threads},
        {"tridex",
         "cpu-1t: apply_sweep per segment, one thread; cpu: apply_sweeps_parallel per 64 segments on "
         "tridex_threads threads (std::thread::hardware_concurrency); gpu: GpuSculptor::apply per 64 segments "
         "(incl. copy to the CPU mirror); contour_s: Contourer::update of the dirty tiles after the program"},
        {"openvdb",
         {{"version", openvdb_version()},
          {"threads", 1},
          {"voxel", "voxel size = tridex cell_m"},
          {"narrow_band_voxels", kHalfWidthVoxels},
          {"usage",
           "workpiece createLevelSetBox; ball segment = createLevelSetSphere stamps at <= 0.5 voxel "
           "spacing, each csgDifference/csgUnion into the workpiece (10.0.1 has no createLevelSetCapsule); "
           "flat-end segment = meshToLevelSet of its exact swept solid; volumeToMesh(isovalue 0) at the "
           "end; volume by levelSetVolume; paint = no geometry change (0 s)"},
          {"fairness",
           "same voxel size as the tridex lattice, narrow band 3 voxels (OpenVDB's default), "
           "one thread for both (tbb::global_control; compare openvdb with tridex cpu-1t, the tridex cpu row uses all "
           "cores), same segments, same error metrics"}}},
        {"errors",
         "mean/max_error_m: |sdf| of the exact solid at mesh vertices (CSG max/min of exact primitive SDFs: "
         "exact near faces, a lower bound near edges); surface_*: quasi-random points on the exact surface -> "
         "nearest mesh triangle; hausdorff_m = max of both"},
        {"volume",
         "tridex: dexel_volume_m3; openvdb: levelSetVolume; exact: box volume -/+ tool part by quasi-random "
         "sampling (exact_volume_sigma_m3 = binomial standard error, conservative)"},
        {"coarse",
         "coarse_level_errors: CoarseGroupLevels of the first tridex path's model at each depth (every depth "
         "contoured whole); per group, |sdf| at its level's own vertices and exact-surface samples in its box -> "
         "its level (own triangles, ring and skirt); estimates: start-up kStartupErrorCoarseCells, level "
         "error_coarse_cells, in coarse cells"},
        {"programs", programs}};
}

}  // namespace

std::vector<AccuracyRow> run_accuracy_bench(const AccuracyBenchOptions& o) {
    if (o.resolutions.empty()) throw Error("bench --accuracy: no resolutions");
    if (!(o.offset_cells >= 0.0 && o.offset_cells < 1.0)) throw Error("bench --accuracy: lattice offset must be in [0, 1) cells");
    for (const int n : o.resolutions)
        if (n < 16 || n > 1024) throw Error("bench --accuracy: resolution must be in 16..1024, got " + std::to_string(n));
    const std::vector<std::string> known = program_names();
    for (const std::string& name : o.programs)
        if (std::find(known.begin(), known.end(), name) == known.end()) throw Error("bench --accuracy: unknown program '" + name + "'");
    for (const int d : o.coarse_depths)
        if (d < 1 || d > 6) throw Error("bench --accuracy: coarse depth must be in 1..6, got " + std::to_string(d));
    const int threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    std::unique_ptr<gpu::Context> ctx;
    if (o.gpu) {
        try {
            ctx = std::make_unique<gpu::Context>(gpu::Context::create({}));
        } catch (const Error& e) {
            std::printf("gpu rows skipped: no usable Vulkan device (%s)\n", e.what());
        }
    }
    const bool vdb = o.openvdb && openvdb_available();
    if (o.openvdb && !vdb) std::printf("openvdb rows skipped: this build has no OpenVDB\n");

    const int n_max = *std::max_element(o.resolutions.begin(), o.resolutions.end());
    const double fine = kLatticeSideM / n_max;
    std::vector<Reference> refs;
    for (const std::string& name : o.programs.empty() ? program_names() : o.programs) {
        Reference r;
        r.program = make_program(name, o.short_programs);
        r.exact = std::make_unique<ExactSolid>(r.program);
        r.samples = r.exact->surface_samples(std::min(o.samples_per_cell2 / (fine * fine), 3e7));
        r.volume_m3 = r.exact->volume_m3(o.volume_samples, r.sigma_m3);
        refs.push_back(std::move(r));
    }
    std::printf("workpiece: 0.1 m cube [%.3f, %.3f]^3 m on a %.3f m lattice of N cells; errors in cells; t/seg in us\n",
                kBoxLoM, kBoxHiM, kLatticeSideM);
    std::printf("%-7s %-6s %4s %-11s %5s %9s %8s %7s %8s %7s %7s %7s %8s\n", "method", "path", "N", "program", "segs",
                "t/seg_us", "mesh_s", "mem_MB", "vol_err%", "mean_c", "max_c", "haus_c", "max_mm");
    std::vector<AccuracyRow> rows;
    nlohmann::json coarse = nlohmann::json::array();
    if (!o.coarse_depths.empty())
        std::printf(
            "coarse levels after each program's first tridex path, per depth d (stride): groups measured, own "
            "triangles, "
            "worst group error in mm and fine cells; groups' p50 / p90 / max error in coarse cells; groups over "
            "the start-up estimate (%.2f coarse cells), over the level's (1) and by more than half a fine cell over "
            "the distance from the model's own surface points in the box (its rays' ends) to the level, with the "
            "largest excess in fine cells; "
            "exact samples in a box with no level\n",
            compute::TileSurfaceCache::kStartupErrorCoarseCells);
    if (!o.coarse_depths.empty())
        std::printf("coarse  %-11s %4s %5s %6s %9s %8s %8s %6s %6s %6s %6s %6s %6s %7s %7s\n", "program", "N", "d/s",
                    "groups", "triangles", "max_mm", "max_c", "p50_cc", "p90_cc", "max_cc", ">start", ">level",
                    ">dexel", "dexel+c", "missed");
    for (const int n : o.resolutions) {
        compute::TriDexel pristine = workpiece(n, o.offset_cells);
        compute::Contourer pristine_contour(pristine);
        pristine_contour.update(pristine);  // the whole box once (clears the dirty flags); each path starts from copies
        const double v0 = compute::dexel_volume_m3(pristine);
        for (const Reference& ref : refs) {
            const std::vector<compute::Sweep> sweeps = ref.program.sweeps();
            std::unique_ptr<compute::TriDexel> coarse_from;  // the first tridex path's model, for its coarse levels
            for (const char* path : {"cpu-1t", "cpu", "gpu"}) {
                const std::string p = path;
                if (p == "gpu" && !ctx) continue;
                if (p == "cpu" && !o.cpu_all_cores) continue;
                if (p == "cpu-1t" && !o.cpu_one_thread) continue;
                AccuracyRow row{"tridex", p, n, kLatticeSideM / n, ref.program.name, sweeps.size()};
                compute::TriDexel m = pristine;
                compute::Contourer contourer = pristine_contour;
                const auto t0 = Clock::now();
                if (p == "cpu-1t") {
                    for (const compute::Sweep& s : sweeps) compute::apply_sweep(m, s);
                    row.time_per_segment_s = since(t0) / static_cast<double>(sweeps.size());
                    row.memory_bytes = model_bytes(m);
                } else if (p == "cpu") {
                    for (std::size_t i = 0; i < sweeps.size(); i += kGpuBatch)
                        compute::apply_sweeps_parallel(
                            m, std::span<const compute::Sweep>(sweeps).subspan(i, std::min<std::size_t>(kGpuBatch, sweeps.size() - i)),
                            threads);
                    row.time_per_segment_s = since(t0) / static_cast<double>(sweeps.size());
                    row.memory_bytes = model_bytes(m);
                } else {
                    compute::GpuSculptor sculptor(*ctx, m);
                    const auto t1 = Clock::now();
                    for (std::size_t i = 0; i < sweeps.size(); i += kGpuBatch)
                        sculptor.apply(std::span<const compute::Sweep>(sweeps).subspan(i, std::min<std::size_t>(kGpuBatch, sweeps.size() - i)));
                    row.time_per_segment_s = since(t1) / static_cast<double>(sweeps.size());
                    for (const auto& b : sculptor.slabs().bytes()) row.memory_bytes += b.total();
                }
                const auto t2 = Clock::now();
                contourer.update(m);
                row.contour_s = since(t2);
                row.volume_m3 = compute::dexel_volume_m3(m);
                row.volume_change_m3 = row.volume_m3 - v0;
                const TriMesh mesh = contourer.mesh();
                fill_errors(row, mesh, ref, m.lattice.origin_m, threads);
                print_row(row);
                if (o.dump_worst > 0 && p == "cpu-1t") dump_worst_vertices(m, mesh, *ref.exact, o.dump_worst);
                if (!o.coarse_depths.empty() && coarse_from == nullptr)
                    coarse_from = std::make_unique<compute::TriDexel>(std::move(m));
                rows.push_back(row);
            }
            if (coarse_from) {
                const auto levels =
                    coarse_level_errors(*coarse_from, *ref.exact, ref.samples, o.coarse_depths, threads);
                for (nlohmann::json& j :
                     report_coarse(ref.program.name, n, kLatticeSideM / n, coarse_from->lattice.origin_m, levels))
                    coarse.push_back(std::move(j));
                coarse_from.reset();
            }
            if (vdb) {
                AccuracyRow row{"openvdb", "cpu-1t", n, kLatticeSideM / n, ref.program.name};
                PeerRun peer = run_openvdb(ref.program, row.cell_m, kHalfWidthVoxels, pristine.lattice.origin_m);
                row.segments = peer.segments;
                row.time_per_segment_s = peer.segments ? peer.sculpt_s / static_cast<double>(peer.segments) : 0.0;
                row.contour_s = peer.mesh_s;
                row.memory_bytes = peer.memory_bytes;
                row.volume_m3 = peer.volume_m3;
                fill_errors(row, peer.mesh, ref, pristine.lattice.origin_m, threads);
                print_row(row);
                rows.push_back(row);
            }
        }
    }
    print_targets(rows);
    const std::vector<MatchedRun> matched = match_openvdb(rows);
    print_matched(matched);

    nlohmann::json runs = nlohmann::json::array();
    for (const AccuracyRow& r : rows) runs.push_back(row_json(r));
    nlohmann::json jmatched = nlohmann::json::array();
    for (const MatchedRun& m : matched)
        jmatched.push_back({{"program", m.program}, {"path", m.path}, {"openvdb_n", m.openvdb_n},
                            {"openvdb_max_error_m", m.openvdb_max_error_m}, {"openvdb_time_per_segment_s", m.openvdb_time_s},
                            {"tridex_n", m.tridex_n}, {"tridex_max_error_m", m.tridex_max_error_m},
                            {"tridex_time_per_segment_s", m.tridex_time_s}, {"ratio", m.ratio}});
    const nlohmann::json setup = setup_json(o, refs, threads);
    const std::string file = (std::filesystem::path(o.out) / "bench.json").string();
    write_json_file(file, {{"runs", runs}, {"matched", jmatched}, {"coarse", coarse}, {"setup", setup}});
    std::printf("wrote %s\n", file.c_str());
    if (o.plots)
        for (const std::string& png : write_accuracy_plots(rows, o.out)) std::printf("wrote %s\n", png.c_str());
    return rows;
}

namespace {

struct AccuracyBenchCli {
    AccuracyBenchOptions options;
    std::vector<int> n;
    std::vector<std::string> paths;
};

BenchRun setup_accuracy_bench(CLI::App& bench) {
    auto o = std::make_shared<AccuracyBenchCli>();
    bench.add_option("--accuracy-n", o->n, "With --accuracy: run only these N (16..1024), e.g. --accuracy-n 64,256")
        ->delimiter(',');
    bench.add_option("--accuracy-programs", o->options.programs,
                     "With --accuracy: run only these programs (pocket, random_ball, flat_random, plunge, union, paint)")
        ->delimiter(',');
    bench.add_option("--accuracy-paths", o->paths, "With --accuracy: run only these paths (cpu-1t, cpu, gpu, openvdb)")
        ->delimiter(',')
        ->check(CLI::IsMember({"cpu-1t", "cpu", "gpu", "openvdb"}));
    bench.add_option("--accuracy-offset", o->options.offset_cells,
                     "With --accuracy: lattice origin shift in cells, [0, 1) (0 = cube faces on lattice nodes)")
        ->capture_default_str();
    bench.add_option("--accuracy-dump", o->options.dump_worst,
                     "With --accuracy: print the K worst vertices of each tridex cpu-1t run with their cells' crossings "
                     "and normals against the exact solid")
        ->check(CLI::Range(0, 1000));
    bench
        .add_option(
            "--accuracy-coarse-depths", o->options.coarse_depths,
            "With --accuracy: group depths (1..6, stride 2^d) whose coarse levels are measured against the exact "
            "solid after each program (default 1,2,3,4; 0 for none)")
        ->delimiter(',')
        ->check(CLI::Range(0, 6));
    return [o](const BenchCommon& c) {
        AccuracyBenchOptions a = o->options;
        std::erase(a.coarse_depths, 0);
        a.out = c.out;
        if (!o->n.empty()) a.resolutions = o->n;
        if (!o->paths.empty()) {
            const auto has = [&](const char* p) { return std::find(o->paths.begin(), o->paths.end(), p) != o->paths.end(); };
            a.cpu_one_thread = has("cpu-1t");
            a.cpu_all_cores = has("cpu");
            a.gpu = has("gpu");
            a.openvdb = has("openvdb");
        }
        run_accuracy_bench(a);
    };
}

const BenchmarkRegistration kRegistration{
    {"accuracy",
     "Run time against error on stroke programs with an exact answer (box workpiece, N = 64, 128, 256, 512): "
     "tridex CPU 1 thread, CPU all cores and GPU, and an OpenVDB level-set peer at the same N when built in",
     100, setup_accuracy_bench}};

}  // namespace

}  // namespace tridex::bench
