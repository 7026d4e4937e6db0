// bench/bench_session_latency.cpp - `bench --session`'s latency rows: how long after a tool sample the surface it
// changed is drawn, for a subtract and a clay push at the same hand speed.
#include "bench/bench_session.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/session/run/run_session.hpp"
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
// The settled rows start the stroke this long after the session: after the start-up levels of detail are built.
constexpr double kSettledStartS = 3.0;
// The start-up levels of detail should all be built within this long of the first frame, ms.
constexpr double kLodStartupTargetMs = 1000.0;

std::string write_scene(const fs::path& dir, int n, const std::string& op, std::size_t group, double start_s,
                        const std::string& mesh) {
    nlohmann::json scene = {
        {"workpiece", {{"mesh", mesh}, {"resolution", n}, {"stock_m", 0.3}, {"centre_m", {0.0, 0.0, -0.1}}}},
        {"tool", {{"radius_m", 0.008}}},
        {"op", op},
        {"stroke",
         {{"duration_s", kStrokeS},
          {"start_s", start_s},
          {"length_m", kPassM},
          {"depth_m", 0.006},
          {"press_axis", "z"}}},
        {"display", {{"preset", "desktop"}, {"stereo", "mono"}, {"resolution", {960, 540}}, {"refresh_hz", 60}}},
        {"head", {{"provider", "fixed"}, {"position_m", {0.0, 0.05, 0.6}}}}};
    if (group > 0) scene["clay_group_sweeps"] = group;
    const std::string path = (dir / ("latency_" + std::to_string(n) + "_" + op + std::to_string(group) +
                                     (start_s > 0.0 ? "_settled" : "") + ".json"))
                                 .string();
    write_json_file(path, scene);
    return path;
}

// One session of the bench: an op, for a push the most sweeps per group (0: not a clay op), when the stroke
// starts (0: with the session, while the start-up levels of detail are built), --ao-while-sculpting, and whether a
// sculpted change starts a frame early (false: --fixed-pace).
struct Variant {
    std::string op;
    std::size_t group = 0;
    double start_s = 0.0;
    std::string ao_sculpting = "auto";
    bool early_frames = true;
};

}  // namespace

Verdict latency_verdict(const LatencyBenchRow& row) {
    return verdict_of(row.drawn_clock == "none" ? 0 : row.frames, row.p99_ms <= kLatencyTargetMs);
}

std::vector<LatencyBenchRow> run_latency_bench(const SessionBenchOptions& o) {
    const fs::path dir = fs::path(o.out) / "latency";
    fs::create_directories(dir);
    const std::string mesh = fs::absolute(default_mesh_path()).lexically_normal().string();
    std::printf("\nsurface latency: from a tool sample to the changed surface drawn (offscreen, paced at 60 Hz), an 8 mm "
                "ball at %.2f m/s; target: push p99 <= %.0f ms\n",
                kPassM / (0.55 * kStrokeS), kLatencyTargetMs);
    std::printf(
        "(stroke start 0: with the session, while the start-up levels of detail are built; %.0f s: after; "
        "lod: when the start-up levels were all built, ms after the first frame; target <= %.0f ms; first, refined: "
        "from the workpiece loaded to the first frame done and to every tile at full resolution)\n",
        kSettledStartS, kLodStartupTargetMs);
    std::printf(
        "(lat: to the frame that first drew the change done on the device and presented; sub: to that frame's "
        "submit; pub: to the mesh's publish)\n");
    std::printf(
        "(ao: the ambient occlusion on the sculpting frames, --ao-while-sculpting; pace: early = a published change "
        "starts a frame early, half a period after the last at the soonest, as on a variable-refresh display; fixed "
        "= the 60 Hz grid only; the last two rows are the settled push-32 row's baselines: the occlusion kept, the "
        "fixed pace)\n");
    std::printf("%6s %9s %6s %6s %5s %4s %5s %7s %9s %9s %9s %9s %9s %9s %9s %9s %9s %8s %7s %7s %8s %s\n", "N", "op",
                "group", "start", "path", "ao", "pace", "frames", "lat50", "lat99", "latmax", "sub50", "sub99", "pub50",
                "pub99", "step50", "step99", "frame50", "lod", "first", "refined", "verdict");
    std::printf("%6s %9s %6s %6s %5s %4s %5s %7s %9s %9s %9s %9s %9s %9s %9s %9s %9s %8s %7s %7s %8s\n", "", "", "sweeps",
                "s", "", "", "", "", "ms", "ms", "ms", "ms", "ms", "ms", "ms", "ms", "ms", "ms", "ms", "ms", "ms");
    std::vector<LatencyBenchRow> rows;
    for (const int n : o.latency_resolutions)
        for (const Variant& v :
             {Variant{"subtract", 0, 0.0}, Variant{"push", compute::kClayGroupSweeps, 0.0}, Variant{"push", 16, 0.0},
              Variant{"subtract", 0, kSettledStartS}, Variant{"push", compute::kClayGroupSweeps, kSettledStartS},
              Variant{"push", 16, kSettledStartS}, Variant{"push", compute::kClayGroupSweeps, kSettledStartS, "on"},
              Variant{"push", compute::kClayGroupSweeps, kSettledStartS, "auto", false}}) {
            const std::string& op = v.op;
            RunOptions r;
            r.scene = write_scene(dir, n, op, v.group, v.start_s, mesh);
            r.display = "offscreen";
            r.ao_sculpting = v.ao_sculpting;
            r.early_frames = v.early_frames;
            r.seconds =
                v.start_s + kStrokeS + 2.0;  // the frames go on while the sculpt thread catches up after the stroke
            r.out = (dir / ("run_" + std::to_string(n) + "_" + op + (v.group ? std::to_string(v.group) : "") +
                            (v.start_s > 0.0 ? "_settled" : "") + (v.ao_sculpting == "on" ? "_ao" : "") +
                            (v.early_frames ? "" : "_fixed")))
                        .string();
            const RunResult res = run_stereo_session(r);  // paced at 60 Hz until the stroke ends
            const nlohmann::json j = nlohmann::json::parse(std::ifstream(fs::path(r.out) / "report.json"));
            const nlohmann::json& lat = j.at("meshes").at("sample_to_drawn_ms");
            const nlohmann::json& step = j.at("sculpt").at("boolean_ms");
            LatencyBenchRow row;
            row.n = n;
            row.op = op;
            row.group_sweeps = v.group;
            row.start_s = v.start_s;
            const nlohmann::json& lod = j.at("render").at("lod");
            const bool built = lod.is_object() && lod.contains("all_built_after_first_frame_ms") &&
                               lod.at("all_built_after_first_frame_ms").is_number();
            row.lod_all_built_ms = built ? lod.at("all_built_after_first_frame_ms").get<double>() : -1.0;
            const nlohmann::json& startup = j.at("render").at("startup");
            const auto startup_ms = [&](const char* key) {
                return startup.is_object() && startup.at(key).is_number() ? startup.at(key).get<double>() : -1.0;
            };
            row.first_frame_ms = startup_ms("load_to_first_frame_ms");
            row.refined_ms = startup_ms("load_to_refined_ms");
            row.path = j.at("sculpt_path").get<std::string>();
            row.ao_sculpting = j.at("render").at("ambient_occlusion_while_sculpting").at("on").get<bool>();
            row.ao_chosen = v.ao_sculpting;
            row.pacing = j.at("frames").at("pacing").get<std::string>();
            row.frames = res.sample_to_drawn_ms.count();
            row.p50_ms = lat.at("median").get<double>();
            row.p99_ms = lat.at("p99").get<double>();
            row.max_ms = lat.at("max").get<double>();
            const nlohmann::json& pub = j.at("meshes").at("sample_to_published_ms");
            const nlohmann::json& sub = j.at("meshes").at("sample_to_submitted_ms");
            row.sub_p50_ms = sub.at("median").get<double>();
            row.sub_p99_ms = sub.at("p99").get<double>();
            const nlohmann::json& clock = j.at("meshes").at("drawn_clock");
            row.drawn_clock = clock.is_string() ? clock.get<std::string>() : "none";
            row.pub_p50_ms = pub.at("median").get<double>();
            row.pub_p99_ms = pub.at("p99").get<double>();
            row.frame_p50_ms = res.frame_ms.percentile_ms(0.5);
            row.step_p50_ms = step.at("median").get<double>();
            row.step_p99_ms = step.at("p99").get<double>();
            const bool baseline = v.ao_sculpting != "auto" || !v.early_frames;
            const bool judged = op == "push" && !baseline;
            if (judged) row.verdict = latency_verdict(row);
            const std::string group = v.group ? std::to_string(v.group) : "-";
            std::printf(
                "%6d %9s %6s %6.1f %5s %4s %5s %7zu %9.1f %9.1f %9.1f %9.1f %9.1f %9.1f %9.1f %9.2f %9.2f %8.1f %7.0f "
                "%7.0f %8.0f %s%s\n",
                n, op.c_str(), group.c_str(), v.start_s, row.path.c_str(), row.ao_sculpting ? "on" : "off",
                row.pacing.c_str(), row.frames, row.p50_ms, row.p99_ms, row.max_ms, row.sub_p50_ms, row.sub_p99_ms,
                row.pub_p50_ms, row.pub_p99_ms, row.step_p50_ms, row.step_p99_ms, row.frame_p50_ms,
                row.lod_all_built_ms, row.first_frame_ms, row.refined_ms,
                v.ao_sculpting != "auto"         ? "(baseline: occlusion kept)"
                : !v.early_frames                ? "(baseline: fixed pace)"
                : !judged                        ? "(reference)"
                                                 : verdict_text(*row.verdict),
                row.drawn_clock == "gpu" ? "" : (" (lat timed at: " + row.drawn_clock + ")").c_str());
            std::fflush(stdout);
            rows.push_back(row);
        }
    nlohmann::json out = nlohmann::json::array();
    for (const LatencyBenchRow& r : rows)
        out.push_back({{"n", r.n},
                       {"op", r.op},
                       {"group_sweeps", r.group_sweeps},
                       {"stroke_start_s", r.start_s},
                       {"ao_while_sculpting", r.ao_chosen},
                       {"ao_on_sculpting_frames", r.ao_sculpting},
                       {"pacing", r.pacing},
                       {"lod_all_built_after_first_frame_ms", r.lod_all_built_ms},
                       {"lod_target_ms", kLodStartupTargetMs},
                       {"load_to_first_frame_ms", r.first_frame_ms},
                       {"load_to_refined_ms", r.refined_ms},
                       {"path", r.path},
                       {"frames", r.frames},
                       {"p50_ms", r.p50_ms},
                       {"p99_ms", r.p99_ms},
                       {"max_ms", r.max_ms},
                       {"drawn_clock", r.drawn_clock},
                       {"submitted_p50_ms", r.sub_p50_ms},
                       {"submitted_p99_ms", r.sub_p99_ms},
                       {"published_p50_ms", r.pub_p50_ms},
                       {"published_p99_ms", r.pub_p99_ms},
                       {"frame_p50_ms", r.frame_p50_ms},
                       {"step_p50_ms", r.step_p50_ms},
                       {"step_p99_ms", r.step_p99_ms},
                       {"target_p99_ms", kLatencyTargetMs},
                       {"verdict", r.verdict ? nlohmann::json(verdict_text(*r.verdict)) : nlohmann::json()},
                       {"target_met", r.verdict ? nlohmann::json(target_met(*r.verdict)) : nlohmann::json()}});
    write_json_file((fs::path(o.out) / "latency_bench.json").string(), out);
    return rows;
}

}  // namespace tridex::bench
