// bench/bench_cluster.cpp - `tridex bench --cluster`: a cluster session under mpirun on this machine (rank 0 the
// session, K render ranks each a strip of the wall, offscreen): bytes broadcast per frame, sample-to-present latency,
// swap spread, and the time a late-joining rank needs to catch up from the stream.
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "app/session/cluster/cluster_replica.hpp"
#include "app/session/cluster/cluster_transport.hpp"
#include "app/support/assets.hpp"
#include "app/support/json_file.hpp"
#include "app/support/output_dir.hpp"
#include "compute/journal/journal_reader.hpp"
#include "core/error.hpp"

namespace tridex::bench {

namespace {

namespace fs = std::filesystem;
using app::write_json_file;

struct ClusterCli {
    int ranks = 2;            // render ranks
    int resolution = 128;     // workpiece cells along the longest side
    double stroke_s = 4.0;    // the scene's stroke, s
    std::string startup = "coarse";  // the render ranks' start-up (the cluster config's "startup")
    std::string stroke_contour = "coarse";  // how they draw a stroke (the cluster config's "stroke_contour")
    double stock_m = 0.3;                   // the workpiece's size on the wall, m
};

// The wall scene with a stroke of `seconds`, side by side, 640 x 480 per eye.
std::string write_scene(const fs::path& dir, const ClusterCli& o) {
    const nlohmann::json scene = {
        {"workpiece",
         {{"mesh", fs::absolute(app::default_mesh_path()).lexically_normal().string()},
          {"resolution", o.resolution},
          {"stock_m", o.stock_m},
          {"centre_m", {0.0, 1.3, 0.7}}}},
        {"tool", {{"radius_m", 0.01}, {"stiffness_n_per_m", 700}, {"damping_n_s_per_m", 0.5}}},
        {"workspace", {{"mode", "peng_moving"}, {"scale", 1.0}}},
        {"stroke",
         {{"duration_s", o.stroke_s},
          {"length_m", 0.12},
          {"depth_m", 0.008},
          {"clearance_m", 0.03},
          {"press_axis", "z"}}},
        {"display",
         {{"preset", "powerwall"},
          {"screen",
           {{"lower_left", {-1.524, 0.6, 0.0}},
            {"lower_right", {1.524, 0.6, 0.0}},
            {"upper_left", {-1.524, 2.886, 0.0}}}},
          {"stereo", "side-by-side"},
          {"refresh_hz", 60},
          {"resolution", {640, 480}},
          {"default_head_m", {0.0, 1.7, 2.0}}}},
        {"head", {{"provider", "fixed"}, {"position_m", {0.0, 1.7, 2.0}}}}};
    const std::string path = (dir / "cluster_scene.json").string();
    write_json_file(path, scene);
    return path;
}

// K vertical strips of the wall, one per render rank.
std::string write_config(const fs::path& dir, const ClusterCli& o) {
    nlohmann::json rs = nlohmann::json::array();
    const int ranks = o.ranks;
    for (int r = 1; r <= ranks; ++r)
        rs.push_back({{"rank", r},
                      {"viewports", {{{"name", "strip-" + std::to_string(r)},
                                      {"region", {static_cast<double>(r - 1) / ranks, 0.0, static_cast<double>(r) / ranks, 1.0}}}}}});
    const std::string path = (dir / "cluster_config.json").string();
    write_json_file(path, {{"check_every_frames", 30},
                           {"timeout_s", 30},
                           {"startup", o.startup},
                           {"stroke_contour", o.stroke_contour},
                           {"ranks", rs}});
    return path;
}

double value(const nlohmann::json& j, const char* key, const char* stat) {
    return j.contains(key) && j[key].is_object() ? j[key].value(stat, 0.0) : 0.0;
}

void run_cluster(const ClusterCli& o, const BenchCommon& c) {
    if (o.ranks < 1 || o.ranks > 16) throw Error("--cluster-ranks: 1..16 render ranks, got " + std::to_string(o.ranks));
    if (o.startup != "coarse" && o.startup != "full")
        throw Error("--cluster-startup: coarse or full, got '" + o.startup + "'");
    if (o.stroke_contour != "coarse" && o.stroke_contour != "full")
        throw Error("--cluster-stroke-contour: coarse or full, got '" + o.stroke_contour + "'");
    if (!(o.stock_m >= 0.05 && o.stock_m <= 3.0))
        throw Error("--cluster-stock-m: 0.05..3 m, got " + std::to_string(o.stock_m));
    if (!app::cluster_supported()) throw Error("--cluster: this build has no MPI (install openmpi-bin and libopenmpi-dev, rebuild)");
    if (std::system("command -v mpirun > /dev/null 2>&1") != 0) throw Error("--cluster: mpirun is not installed (Debian's openmpi-bin)");
    app::prepare_output_dir(c.out, "--out");
    const fs::path dir = fs::absolute(fs::path(c.out) / "cluster");
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene = write_scene(dir, o), config = write_config(dir, o);
    const fs::path run = dir / "run";
    const std::string exe = fs::read_symlink("/proc/self/exe").string();
    const std::string cmd = "timeout 600 mpirun" + std::string(geteuid() == 0 ? " --allow-run-as-root" : "") +
                            " --oversubscribe --mca orte_abort_on_non_zero_status 0 -np " + std::to_string(o.ranks + 1) + " " +
                            exe + " run " + scene + " --display offscreen --no-items --cluster " + config + " --out " +
                            run.string() + " > " + (dir / "mpirun.log").string() + " 2>&1";
    std::printf(
        "cluster: mpirun -np %d on this machine (2 cores shared by every rank), rank 0 the session, %d render "
        "rank%s each a strip of a 3.05 m wall, 640x480 per eye side by side, the workpiece %.2f m, N = %d, a %.1f s "
        "stroke, render ranks' start-up %s, strokes contoured %s\n",
        o.ranks + 1, o.ranks, o.ranks == 1 ? "" : "s", o.stock_m, o.resolution, o.stroke_s, o.startup.c_str(),
        o.stroke_contour.c_str());
    std::fflush(stdout);
    const int status = std::system(cmd.c_str());
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw Error("--cluster: the cluster session failed (exit " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                    "); its log: " + (dir / "mpirun.log").string());
    // mpirun exits 0 when a rank fails before the session starts (orte_abort_on_non_zero_status 0): no report then.
    std::ifstream in(run / "report.json");
    const nlohmann::json report = nlohmann::json::parse(in, nullptr, false);
    if (!in || report.is_discarded() || !report.contains("cluster"))
        throw Error("--cluster: the cluster session wrote no report (" + (run / "report.json").string() +
                    "); its log: " + (dir / "mpirun.log").string());
    const nlohmann::json& cl = report.at("cluster");

    // A late-joining rank: the workpiece built from the spec, then the whole stream applied (no checkpoint this short).
    const compute::Journal journal = compute::read_journal((run / "session.tdj").string());
    const auto t0 = std::chrono::steady_clock::now();
    app::ClusterReplica late(journal.session);
    const auto t1 = std::chrono::steady_clock::now();
    app::FrameMessage all;
    all.records = journal.records;
    (void)late.apply(all);
    late.contour();
    const auto t2 = std::chrono::steady_clock::now();
    const double load_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    const double apply_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
    const double session_s = report.value("session_s", 0.0);

    const double bytes_mean = cl.value("frame_bytes_mean", 0.0);
    std::printf("%-34s %12s %12s\n", "", "median", "p99");
    std::printf("%-34s %12.0f %12.0f   (mean %.0f; %llu frames, %llu records, %llu samples)\n", "bytes per frame message",
                value(cl, "frame_bytes", "median"), value(cl, "frame_bytes", "p99"), bytes_mean,
                static_cast<unsigned long long>(cl.value("frames", 0ull)), static_cast<unsigned long long>(cl.value("records", 0ull)),
                static_cast<unsigned long long>(cl.value("samples", 0ull)));
    std::printf("%-34s %12.2f %12.2f\n", "sample -> every rank presented, ms", value(cl, "sample_to_present_ms", "median"),
                value(cl, "sample_to_present_ms", "p99"));
    std::printf("%-34s %12.2f %12.2f\n", "frame sent -> all ranks ready, ms", value(cl, "ready_wait_ms", "median"),
                value(cl, "ready_wait_ms", "p99"));
    std::printf("%-34s %12.2f %12.2f\n", "swap spread across ranks, ms", value(cl, "swap_spread_ms", "median"),
                value(cl, "swap_spread_ms", "p99"));
    for (const nlohmann::json& rank : cl["render_ranks"]) {
        std::printf(
            "render rank %d: apply %.1f ms, contour %.1f ms, contour + draw %.1f ms (medians; contour p99 %.1f, "
            "max %.1f ms), workpiece %.0f ms\n",
            rank.value("rank", 0), value(rank, "apply_ms", "median"), value(rank, "contour_ms", "median"),
            value(rank, "draw_ms", "median"), value(rank, "contour_ms", "p99"), value(rank, "contour_ms", "max"),
            rank.value("workpiece_load_ms", 0.0));
        std::printf(
            "  start-up %s: first frame %.0f ms after the hello (workpiece, first contour and draw); %llu tiles "
            "contoured by start-up, %llu left at the end; %llu triangles in the last frame\n",
            rank.value("startup", "?").c_str(), rank.value("first_frame_ms", 0.0),
            static_cast<unsigned long long>(rank.value("startup_tiles_refined", 0ull)),
            static_cast<unsigned long long>(rank.value("startup_pending_at_end", 0ull)),
            static_cast<unsigned long long>(rank.value("tile_triangles_last_frame", 0ull)));
        std::printf(
            "  strokes contoured %s: %llu tiles contoured in all, %llu tile deferrals, %llu deferred tiles "
            "contoured, %llu deferred at the end\n",
            rank.value("stroke_contour", "?").c_str(),
            static_cast<unsigned long long>(rank.value("tiles_contoured", 0ull)),
            static_cast<unsigned long long>(rank.value("stroke_tiles_deferred", 0ull)),
            static_cast<unsigned long long>(rank.value("stroke_tiles_contoured", 0ull)),
            static_cast<unsigned long long>(rank.value("stroke_tiles_waiting_at_end", 0ull)));
    }
    std::printf("digest checks agreed: %llu; frames in step at %.1f Hz\n", static_cast<unsigned long long>(cl.value("checks", 0ull)),
                report["frames"].is_object() ? report["frames"].value("rate_hz", 0.0) : 0.0);
    std::printf("late join: workpiece %.0f ms + the %.1f s session's stream (%zu records) applied and contoured in %.0f ms "
                "(%.2f s per minute of sculpting)\n",
                load_ms, session_s, journal.records.size(), apply_ms, session_s > 0.0 ? apply_ms / 1e3 * 60.0 / session_s : 0.0);
    // On paper: rank 0 sends each render rank its own copy (point to point).
    const double per_rank_bps = bytes_mean * 8.0 * 60.0;
    std::printf("on paper, 24 render ranks at 60 Hz: %.2f Mb/s per rank, %.1f Mb/s out of rank 0 = %.3f%% of 10 Gb/s\n",
                per_rank_bps / 1e6, 24.0 * per_rank_bps / 1e6, 100.0 * 24.0 * per_rank_bps / 10e9);
    write_json_file((fs::path(c.out) / "cluster_bench.json").string(),
                    {{"ranks", o.ranks + 1},
                     {"resolution", o.resolution},
                     {"stroke_s", o.stroke_s},
                     {"startup", o.startup},
                     {"stroke_contour", o.stroke_contour},
                     {"stock_m", o.stock_m},
                     {"cluster", cl},
                     {"late_join",
                      {{"workpiece_ms", load_ms},
                       {"stream_apply_ms", apply_ms},
                       {"records", journal.records.size()},
                       {"session_s", session_s}}},
                     {"cave_24_ranks_mbps", 24.0 * per_rank_bps / 1e6}});
}

BenchRun setup_cluster(CLI::App& bench) {
    auto o = std::make_shared<ClusterCli>();
    bench.add_option("--cluster-ranks", o->ranks, "With --cluster: render ranks (default 2)");
    bench.add_option("--cluster-resolution", o->resolution, "With --cluster: workpiece cells along its longest side (default 128)");
    bench.add_option("--cluster-stroke-s", o->stroke_s, "With --cluster: the stroke's length, s (default 4)");
    bench.add_option(
        "--cluster-startup", o->startup,
        "With --cluster: the render ranks' start-up where their groups take coarse levels (from 512 cells): "
        "coarse (the coarsest levels first, tiles where frames need them) or full (default coarse)");
    bench.add_option("--cluster-stock-m", o->stock_m,
                     "With --cluster: the workpiece's size on the wall, m (0.05..3; default 0.3: the bunny about 100 "
                     "pixels tall; 1 fills most of the wall's height)");
    bench.add_option(
        "--cluster-stroke-contour", o->stroke_contour,
        "With --cluster: how the render ranks draw a stroke where their groups take coarse levels: coarse "
        "(its tiles wait while it is open, the coarse levels stand in) or full (contoured in the frame that "
        "brings them) (default coarse)");
    return [o](const BenchCommon& c) { run_cluster(*o, c); };
}

const BenchmarkRegistration kRegistration{
    {"cluster",
     "A cluster session under mpirun on this machine: bytes per frame, sample-to-present latency, swap spread across "
     "ranks, late-join catch-up time",
     48, setup_cluster}};

}  // namespace

}  // namespace tridex::bench
