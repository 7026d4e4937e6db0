// bench/bench_persistence.cpp - save / load times and sizes of the .tdx model file.
#include "bench/bench_persistence.hpp"
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numeric>

#include "app/commands/demo/demo.hpp"
#include "app/support/json_file.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "app/scene/stroke.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/volume.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/tools/sweep.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions, stats and JSON files

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr double kToolRadiusM = 0.008;  // the demo's ball

bool identical(const compute::TriDexel& a, const compute::TriDexel& b) {
    for (int s = 0; s < 3; ++s) {
        if (a.sets[s].rays.size() != b.sets[s].rays.size()) return false;
        for (std::size_t r = 0; r < a.sets[s].rays.size(); ++r) {
            const auto& x = a.sets[s].rays[r];
            const auto& y = b.sets[s].rays[r];
            if (x.size() != y.size()) return false;
            for (std::size_t k = 0; k < x.size(); ++k)
                if (std::memcmp(&x[k].enter, &y[k].enter, 4) != 0 || std::memcmp(&x[k].exit, &y[k].exit, 4) != 0 ||
                    x[k].enter_material != y[k].enter_material || x[k].exit_material != y[k].exit_material)
                    return false;
        }
    }
    // Files keep whether a tile is dirty, not which of its cells (a partial flag loads as whole).
    return std::equal(a.tiles.dirty.begin(), a.tiles.dirty.end(), b.tiles.dirty.begin(), b.tiles.dirty.end(),
                      [](std::uint8_t x, std::uint8_t y) { return (x != 0) == (y != 0); });
}

}  // namespace

std::vector<PersistenceBenchRow> run_persistence_bench(const PersistenceBenchOptions& o) {
    const std::string mesh = o.mesh.empty() ? default_mesh_path() : o.mesh;
    fs::create_directories(o.out);
    std::printf("persistence: %s, 0.3 m stock, carved by the demo's stroke (%.0f mm ball, CPU); zstd level 3\n",
                mesh.c_str(), kToolRadiusM * 1e3);
    std::printf("%5s %10s %6s %9s %8s %8s %11s %11s %7s %9s\n", "N", "intervals", "segs", "cut_cm3", "save_s", "load_s",
                "file_B", "memory_B", "ratio", "identical");
    std::vector<PersistenceBenchRow> rows;
    nlohmann::json jrows = nlohmann::json::array();
    for (int n : o.resolutions) {
        Workpiece wp = prepare_workpiece(mesh, n, 0.3, Vec3(0.0, 0.0, 0.3));
        StrokeParams sp;
        sp.tool_radius_m = kToolRadiusM;
        const StrokePlan plan = plan_stroke(wp.model, sp);
        const double volume_before = compute::dexel_volume_m3(wp.model);
        std::size_t segments = 0;
        compute::Sweep sweep;
        sweep.tool = compute::SweepTool{ToolKind::kBall, kToolRadiusM, 0.0};
        for (std::size_t i = 1; i < plan.world_m.size(); ++i) {
            sweep.path_m = Segment{plan.world_m[i - 1], plan.world_m[i]};
            compute::apply_sweep(wp.model, sweep);
            ++segments;
        }
        const std::string path = (fs::path(o.out) / ("bench_" + std::to_string(n) + ".tdx")).string();
        compute::save_tdx(path, wp.model, wp.to_world, "{}");  // warm-up (page cache, allocator)
        PersistenceBenchRow row;
        row.n = n;
        row.intervals = wp.model.interval_count();
        row.segments = segments;
        row.removed_m3 = volume_before - compute::dexel_volume_m3(wp.model);
        auto t0 = Clock::now();
        compute::save_tdx(path, wp.model, wp.to_world, "{}");
        row.save_s = seconds_since(t0);
        t0 = Clock::now();
        const compute::TdxModel back = compute::load_tdx(path, std::size_t{8} << 30);
        row.load_s = seconds_since(t0);
        row.file_bytes = static_cast<std::size_t>(fs::file_size(path));
        const auto bytes = cpu_model_bytes(wp.model);
        row.memory_bytes = std::accumulate(bytes.begin(), bytes.end(), std::size_t{0});
        row.ratio = static_cast<double>(row.file_bytes) / static_cast<double>(row.memory_bytes);
        row.identical = identical(wp.model, back.model);
        std::printf("%5d %10zu %6zu %9.3f %8.3f %8.3f %11zu %11zu %7.3f %9s\n", n, row.intervals, row.segments,
                    row.removed_m3 * 1e6, row.save_s, row.load_s, row.file_bytes, row.memory_bytes, row.ratio,
                    row.identical ? "yes" : "NO");
        jrows.push_back({{"n", n}, {"intervals", row.intervals}, {"segments", row.segments}, {"removed_m3", row.removed_m3},
                         {"save_s", row.save_s}, {"load_s", row.load_s},
                         {"file_bytes", row.file_bytes}, {"memory_bytes", row.memory_bytes}, {"ratio", row.ratio},
                         {"identical", row.identical}});
        rows.push_back(row);
    }
    const nlohmann::json setup{{"mesh", mesh}, {"stock_m", 0.3}, {"tool_radius_m", kToolRadiusM},
                               {"stroke", "plan_stroke defaults (the demo's), ball subtract between consecutive waypoints"},
                               {"zstd_level", 3},
                               {"memory_bytes", "vector headers plus interval capacity of the CPU model (cpu_model_bytes)"}};
    write_json_file((fs::path(o.out) / "persistence_bench.json").string(), {{"rows", jrows}, {"setup", setup}});
    return rows;
}

namespace {

BenchRun setup_persistence_bench(CLI::App&) {
    return [](const BenchCommon& c) {
        PersistenceBenchOptions p;
        p.out = c.out;
        p.mesh = c.mesh;
        run_persistence_bench(p);
    };
}

const BenchmarkRegistration kRegistration{
    {"persistence",
     "Model file (.tdx) save and load time, file size against memory: bunny at N = 256 and 512, carved",
     80, setup_persistence_bench}};

}  // namespace

}  // namespace tridex::bench
