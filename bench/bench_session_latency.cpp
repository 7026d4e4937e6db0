// bench/bench_session_latency.cpp - `bench --session`'s latency rows: how long after a tool sample the surface it
// changed is drawn, for a subtract and a clay push at the same hand speed.
#include "bench/bench_session.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/session/run_session.hpp"
#include "app/support/assets.hpp"
#include "app/support/json_file.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "core/error.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions and JSON files

namespace {

namespace fs = std::filesystem;

// The demo's placement (the bunny scaled to a 0.3 m stock) and its 8 mm ball; a 0.12 m carving pass over 55 % of
// the stroke's duration, so 2.2 s give 0.1 m/s along the surface.
constexpr double kStrokeS = 2.2;
constexpr double kPassM = 0.12;

std::string write_scene(const fs::path& dir, int n, const std::string& op, std::size_t group, const std::string& mesh) {
    nlohmann::json scene = {
        {"workpiece", {{"mesh", mesh}, {"resolution", n}, {"stock_m", 0.3}, {"centre_m", {0.0, 0.0, -0.1}}}},
        {"tool", {{"radius_m", 0.008}}},
        {"op", op},
        {"stroke", {{"duration_s", kStrokeS}, {"length_m", kPassM}, {"depth_m", 0.006}, {"press_axis", "z"}}},
        {"display", {{"preset", "desktop"}, {"stereo", "mono"}, {"resolution", {960, 540}}, {"refresh_hz", 60}}},
        {"head", {{"provider", "fixed"}, {"position_m", {0.0, 0.05, 0.6}}}}};
    if (group > 0) scene["clay_group_sweeps"] = group;
    const std::string path =
        (dir / ("latency_" + std::to_string(n) + "_" + op + std::to_string(group) + ".json")).string();
    write_json_file(path, scene);
    return path;
}

// One session of the bench: an op, and for a push the most sweeps per group (0: not a clay op).
struct Variant {
    std::string op;
    std::size_t group = 0;
};

}  // namespace

std::vector<LatencyBenchRow> run_latency_bench(const SessionBenchOptions& o) {
    const fs::path dir = fs::path(o.out) / "latency";
    fs::create_directories(dir);
    const std::string mesh = fs::absolute(default_mesh_path()).lexically_normal().string();
    std::printf("\nsurface latency: from a tool sample to the changed surface drawn (offscreen, paced at 60 Hz), an 8 mm "
                "ball at %.2f m/s; target: push p99 <= %.0f ms\n",
                kPassM / (0.55 * kStrokeS), kLatencyTargetMs);
    std::printf("%6s %9s %6s %5s %7s %9s %9s %9s %9s %9s %9s %9s %8s %s\n", "N", "op", "group", "path", "frames", "lat50", "lat99",
                "latmax", "pub50", "pub99", "step50", "step99", "frame50", "verdict");
    std::printf("%6s %9s %6s %5s %7s %9s %9s %9s %9s %9s %9s %9s %8s\n", "", "", "sweeps", "", "", "ms", "ms", "ms",
                "ms", "ms", "ms", "ms", "ms");
    std::vector<LatencyBenchRow> rows;
    for (const int n : o.latency_resolutions)
        for (const Variant& v : {Variant{"subtract", 0}, Variant{"push", compute::kClayGroupSweeps}, Variant{"push", 16}}) {
            const std::string& op = v.op;
            RunOptions r;
            r.scene = write_scene(dir, n, op, v.group, mesh);
            r.display = "offscreen";
            r.seconds = kStrokeS + 2.0;  // the frames go on while the sculpt thread catches up after the stroke
            r.out = (dir / ("run_" + std::to_string(n) + "_" + op + (v.group ? std::to_string(v.group) : ""))).string();
            const RunResult res = run_stereo_session(r);  // paced at 60 Hz until the stroke ends
            const nlohmann::json j = nlohmann::json::parse(std::ifstream(fs::path(r.out) / "report.json"));
            const nlohmann::json& lat = j.at("meshes").at("sample_to_drawn_ms");
            const nlohmann::json& step = j.at("sculpt").at("boolean_ms");
            LatencyBenchRow row;
            row.n = n;
            row.op = op;
            row.group_sweeps = v.group;
            row.path = j.at("sculpt_path").get<std::string>();
            row.frames = res.sample_to_drawn_ms.size();
            row.p50_ms = lat.at("median").get<double>();
            row.p99_ms = lat.at("p99").get<double>();
            row.max_ms = lat.at("max").get<double>();
            const nlohmann::json& pub = j.at("meshes").at("sample_to_published_ms");
            row.pub_p50_ms = pub.at("median").get<double>();
            row.pub_p99_ms = pub.at("p99").get<double>();
            row.frame_p50_ms = res.frame_ms.percentile_ms(0.5);
            row.step_p50_ms = step.at("median").get<double>();
            row.step_p99_ms = step.at("p99").get<double>();
            const bool judged = op == "push";
            const std::string group = v.group ? std::to_string(v.group) : "-";
            std::printf("%6d %9s %6s %5s %7zu %9.1f %9.1f %9.1f %9.1f %9.1f %9.2f %9.2f %8.1f %s\n", n, op.c_str(),
                        group.c_str(), row.path.c_str(), row.frames, row.p50_ms, row.p99_ms, row.max_ms, row.pub_p50_ms,
                        row.pub_p99_ms, row.step_p50_ms, row.step_p99_ms, row.frame_p50_ms,
                        !judged ? "(reference)" : row.p99_ms <= kLatencyTargetMs ? "target met" : "over target");
            std::fflush(stdout);
            rows.push_back(row);
        }
    nlohmann::json out = nlohmann::json::array();
    for (const LatencyBenchRow& r : rows)
        out.push_back({{"n", r.n}, {"op", r.op}, {"group_sweeps", r.group_sweeps}, {"path", r.path}, {"frames", r.frames}, {"p50_ms", r.p50_ms},
                       {"p99_ms", r.p99_ms}, {"max_ms", r.max_ms}, {"published_p50_ms", r.pub_p50_ms},
                       {"published_p99_ms", r.pub_p99_ms}, {"frame_p50_ms", r.frame_p50_ms}, {"step_p50_ms", r.step_p50_ms},
                       {"step_p99_ms", r.step_p99_ms}, {"target_p99_ms", kLatencyTargetMs}});
    write_json_file((fs::path(o.out) / "latency_bench.json").string(), out);
    return rows;
}

}  // namespace tridex::bench
