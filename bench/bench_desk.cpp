// bench/bench_desk.cpp - frames at the desk: a live mouse session in a window (the default scene at the desk's
// window size), mono and anaglyph, with the frame time, the time per pass and the mouse-to-photon lag.
#include "bench/bench_desk.hpp"

#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/session/run/run_session.hpp"
#include "app/scene/run_scene.hpp"
#include "app/support/json_file.hpp"
#include "app/support/output_dir.hpp"
#include "core/duration_histogram.hpp"
#include "core/error.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions and JSON files

namespace {

namespace fs = std::filesystem;

// The desk targets the rows are printed beside: frame median and p99, and a lag of at most two frames.
constexpr double kTargetMedianMs = 25.0;
constexpr double kTargetP99Ms = 40.0;
constexpr double kTargetLagFrames = 2.0;

struct DeskCli {
    DeskBenchOptions o;
    std::string stereo = "mono,anaglyph";
    std::string scales = "1,0.75";
    std::string resolutions;
};

// The default scene's workpiece and head in a desk window of the given size, the mouse as the stylus, and a
// cursor that presses in, drags a groove across the bunny and lets go, every 1.6 s; between the grooves it
// sweeps over the surface without the button, as a person looking for the next cut does.
std::string write_scene(const fs::path& dir, const DeskBenchOptions& o, const std::string& stereo, int resolution) {
    const std::string default_scene = default_scene_path();
    const nlohmann::json base = nlohmann::json::parse(std::ifstream(default_scene));
    nlohmann::json cursor = nlohmann::json::array();
    const double cx = 0.5 * o.width, cy = 0.5 * o.height, dx = o.width / 6.0, dy = o.height / 27.0;
    if (o.lead_in_s > 0.0) cursor.push_back({{"t_s", 0.4}, {"x_px", cx - dx}, {"y_px", cy + 2 * dy}, {"buttons", 0}});
    for (double t = 0.4 + o.lead_in_s; t + 1.6 < o.lead_in_s + o.seconds; t += 1.6) {
        cursor.push_back({{"t_s", t}, {"x_px", cx - dx}, {"y_px", cy - dy}, {"buttons", 0}});
        cursor.push_back({{"t_s", t + 0.1}, {"x_px", cx - dx}, {"y_px", cy - dy}, {"buttons", 1}});
        cursor.push_back({{"t_s", t + 0.9}, {"x_px", cx + dx}, {"y_px", cy + dy}, {"buttons", 1}});
        cursor.push_back({{"t_s", t + 1.0}, {"x_px", cx + dx}, {"y_px", cy + dy}, {"buttons", 0}});
        cursor.push_back({{"t_s", t + 1.5}, {"x_px", cx - dx}, {"y_px", cy + 2 * dy}, {"buttons", 0}});
    }
    nlohmann::json scene = base;
    // The scene is written elsewhere: its mesh, named relative to the default scene's folder, by its full path.
    const fs::path mesh = fs::path(default_scene).parent_path() / base.at("workpiece").at("mesh").get<std::string>();
    scene["workpiece"]["mesh"] = fs::absolute(mesh).lexically_normal().string();
    if (resolution > 0) scene["workpiece"]["resolution"] = resolution;
    scene["device"] = {{"driver", "mouse"}};
    scene["stroke"] = "none";
    scene["display"] = {{"preset", "desktop"}, {"stereo", stereo}, {"resolution", {o.width, o.height}}};
    scene["cursor"] = cursor;
    const std::string path = (dir / ("desk_scene_" + stereo + "_n" + std::to_string(resolution) + ".json")).string();
    write_json_file(path, scene);
    return path;
}

double at_or_nan(const nlohmann::json& j, const char* key) {
    return j.is_object() && j.contains(key) && j.at(key).is_number() ? j.at(key).get<double>() : std::nan("");
}

DeskBenchRow run_one(const DeskBenchOptions& o, const std::string& scene, const std::string& stereo, double min_scale,
                     const std::string& display, const fs::path& out) {
    RunOptions r;
    r.min_render_scale = min_scale;
    r.max_lod_px = min_scale < 1.0 ? o.lod_px : 1.0;  // the baseline row trades the occlusion only
    r.scene = scene;
    r.display = display;
    r.seconds = o.seconds + o.lead_in_s;
    r.out = out.string();
    // After a lead-in the row's frames are those drawn once it has passed since the first frame (which comes after
    // the loop's start, so before the first groove on the cursor script's clock).
    DurationHistogram after_lead_in;
    std::chrono::steady_clock::time_point first;
    if (o.lead_in_s > 0.0)
        r.frame_probe = [&after_lead_in, &first, lead = o.lead_in_s](const RunFrameProbe& p) {
            const auto now = std::chrono::steady_clock::now();
            if (p.frame == 0) first = now;
            if (std::chrono::duration<double>(now - first).count() >= lead) after_lead_in.add(p.frame_ms);
        };
    r.lod = o.lod;
    r.stroke_contour = o.stroke_contour;
    r.checkpoint_s = 0.0;
    run_stereo_session(r);
    const nlohmann::json j = nlohmann::json::parse(std::ifstream(out / "report.json"));
    const nlohmann::json& f = j.at("frames");
    DeskBenchRow row;
    row.stereo = stereo;
    row.display = display;
    row.min_scale = min_scale;
    row.max_lod_px = r.max_lod_px;
    row.frames = f.at("count").get<std::uint64_t>();
    row.frame_median_ms = at_or_nan(f.at("frame_ms"), "p50_ms");
    row.frame_p99_ms = at_or_nan(f.at("frame_ms"), "p99_ms");
    if (o.lead_in_s > 0.0) {
        row.frames = after_lead_in.count();
        row.frame_median_ms = row.frames > 0 ? after_lead_in.percentile_ms(0.5) : std::nan("");
        row.frame_p99_ms = row.frames > 0 ? after_lead_in.percentile_ms(0.99) : std::nan("");
    }
    row.interval_median_ms = at_or_nan(f.at("interval_ms"), "p50_ms");
    if (j.at("mouse").is_object()) {
        const nlohmann::json& lat = j.at("mouse").at("latency_ms");
        row.lag_median_ms = at_or_nan(lat, "median");
        row.lag_p99_ms = at_or_nan(lat, "p99");
        row.lag_timed = lat.value("count", std::uint64_t{0});
        const nlohmann::json& m = j.at("mouse");
        if (m.contains("hand_wait_ms")) {
            row.hand_wait_median_ms = at_or_nan(m.at("hand_wait_ms"), "median");
            row.hand_wait_p99_ms = at_or_nan(m.at("hand_wait_ms"), "p99");
        }
        row.targets = m.value("targets", std::uint64_t{0});
        row.same_frame = m.value("same_frame", std::uint64_t{0});
    }
    for (const auto& [name, p] : j.at("render").at("passes").items()) row.passes[name] = at_or_nan(p, "median_ms");
    row.present = f.contains("present") ? f.at("present") : nlohmann::json();
    row.frame_budget = j.at("render").value("frame_budget", nlohmann::json());
    row.resolution = j.at("workpiece").value("resolution", 0);
    const nlohmann::json lod = j.at("render").value("lod", nlohmann::json());
    if (lod.is_object() && lod.contains("tile_triangles_per_frame"))
        row.triangles_per_frame = lod.at("tile_triangles_per_frame").at(0).get<double>();
    return row;
}

// Splits "mono,anaglyph" into its names.
std::vector<std::string> split_list(const std::string& text) {
    std::vector<std::string> out;
    for (std::size_t b = 0; b <= text.size();) {
        const std::size_t e = std::min(text.find(',', b), text.size());
        out.push_back(text.substr(b, e - b));
        b = e + 1;
    }
    return out;
}

// Sets the row's verdict: median, p99 and lag within the targets; not measured when no frame or no cursor target (the
// lag's samples) was timed, or a figure is missing (NaN).
void judge(DeskBenchRow& r) {
    const bool figures = std::isfinite(r.frame_median_ms) && std::isfinite(r.frame_p99_ms) && std::isfinite(r.lag_frames);
    const std::uint64_t timed = figures ? std::min(r.frames, r.targets) : 0;
    r.verdict = verdict_of(timed, r.frame_median_ms <= kTargetMedianMs && r.frame_p99_ms <= kTargetP99Ms &&
                                      r.lag_frames <= kTargetLagFrames);
    r.target_met = target_met(r.verdict);
}

// The median of `v`, the mean of the middle two for an even count (core's summarize() takes the lower one: with
// two runs the verdict would judge the better of them); NaN when empty.
double median_of(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? std::nan("") : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The median over the runs of one output and scale (repeat 0): each figure's median, the verdict from those.
DeskBenchRow median_row(const std::vector<DeskBenchRow>& runs, int resolution, const std::string& stereo,
                        double min_scale) {
    std::vector<const DeskBenchRow*> mine;
    for (const DeskBenchRow& r : runs)
        if (r.repeat > 0 && r.resolution == resolution && r.stereo == stereo && r.min_scale == min_scale)
            mine.push_back(&r);
    DeskBenchRow out = *mine.front();
    out.repeat = 0;
    const auto med = [&]<typename T>(T DeskBenchRow::*f) {
        std::vector<double> v;
        for (const DeskBenchRow* r : mine) v.push_back(static_cast<double>(r->*f));
        return median_of(std::move(v));
    };
    out.frames = static_cast<std::uint64_t>(std::lround(med(&DeskBenchRow::frames)));
    out.frame_median_ms = med(&DeskBenchRow::frame_median_ms);
    out.frame_p99_ms = med(&DeskBenchRow::frame_p99_ms);
    out.interval_median_ms = med(&DeskBenchRow::interval_median_ms);
    out.lag_median_ms = med(&DeskBenchRow::lag_median_ms);
    out.lag_p99_ms = med(&DeskBenchRow::lag_p99_ms);
    out.lag_frames = med(&DeskBenchRow::lag_frames);
    out.hand_wait_median_ms = med(&DeskBenchRow::hand_wait_median_ms);
    out.hand_wait_p99_ms = med(&DeskBenchRow::hand_wait_p99_ms);
    out.triangles_per_frame = med(&DeskBenchRow::triangles_per_frame);
    out.passes = nlohmann::json::object();  // per run only
    out.present = nlohmann::json();
    out.frame_budget = nlohmann::json();
    judge(out);
    return out;
}

// Fewer timed cursor targets than this, and the lag's p99 is within a sample or two of their largest.
constexpr std::uint64_t kLagTimedForP99 = 100;

// Prints one row of the table and, for a run (not a median), its detail lines.
void print_row(const DeskBenchRow& r) {
    std::printf("%5d %-13s %5.3g %5.3g %6llu %9.1f %9.1f %10.1f %8.1f %8.1f %8.2f %10.0f %6.2f %s\n", r.resolution,
                r.stereo.c_str(), r.min_scale, r.max_lod_px, static_cast<unsigned long long>(r.frames),
                r.frame_median_ms, r.frame_p99_ms, r.interval_median_ms, r.lag_median_ms, r.lag_p99_ms, r.lag_frames,
                r.triangles_per_frame, r.frame_ratio, verdict_text(r.verdict));
    if (r.repeat == 0) {  // a median over runs: the runs' rows have the details
        std::fflush(stdout);
        return;
    }
    std::printf("  GPU passes (median ms):");
    for (const auto& [name, ms] : r.passes.items()) std::printf(" %s %.2f", name.c_str(), ms.get<double>());
    if (r.present.is_object() && r.present.contains("blit_gpu_ms"))
        std::printf("; present pass%s %.2f", r.stereo == "anaglyph" ? " (anaglyph compose and blit)" : " (blit)",
                    r.present.at("blit_gpu_ms").value("p50_ms", 0.0));
    std::printf("\n");
    if (r.frame_budget.is_object()) {
        std::printf("  frames per step of the %.0f ms frame budget (occlusion, levels' error, render scale):",
                    r.frame_budget.value("target_ms", 0.0));
        for (const nlohmann::json& step : r.frame_budget.value("ladder", nlohmann::json::array()))
            std::printf(" %s %gpx %.3f: %llu,", step.value("occlusion", "").c_str(), step.value("lod_px", 1.0),
                        step.value("scale", 1.0),
                        static_cast<unsigned long long>(step.value("frames", std::uint64_t{0})));
        std::printf(" %llu switches\n", static_cast<unsigned long long>(r.frame_budget.value("switches", 0)));
        const nlohmann::json calm = r.frame_budget.value("now_calm", nlohmann::json::object());
        const nlohmann::json carving = r.frame_budget.value("now_sculpting", nlohmann::json::object());
        std::printf("  %llu frames drawn while carving; the step at the end: calm %s %gpx %.3f, carving %s %gpx %.3f\n",
                    static_cast<unsigned long long>(r.frame_budget.value("frames_sculpting", std::uint64_t{0})),
                    calm.value("occlusion", "").c_str(), calm.value("lod_px", 1.0), calm.value("scale", 1.0),
                    carving.value("occlusion", "").c_str(), carving.value("lod_px", 1.0), carving.value("scale", 1.0));
    }
    std::printf(
        "  the frame's wait for the loop to take the cursor's target: median %.2f ms, p99 %.2f ms; "
        "%llu of %llu targets drawn by the frame that set them\n",
        r.hand_wait_median_ms, r.hand_wait_p99_ms, static_cast<unsigned long long>(r.same_frame),
        static_cast<unsigned long long>(r.targets));
    std::printf("  lag timed on %llu of %llu cursor targets (the others were superseded before the tool reached them)%s\n",
                static_cast<unsigned long long>(r.lag_timed), static_cast<unsigned long long>(r.targets),
                r.lag_timed < kLagTimedForP99 ? ": its p99 is close to the largest of those few" : "");
    std::fflush(stdout);
}

// One row of desk_bench.json.
nlohmann::json row_json(const DeskBenchOptions& o, const DeskBenchRow& r) {
    return nlohmann::json{{"stereo", r.stereo},
                          {"resolution", r.resolution},
                          {"repeat", r.repeat},
                          {"min_render_scale", r.min_scale},
                          {"max_lod_px", r.max_lod_px},
                          {"display", r.display},
                          {"width", o.width},
                          {"height", o.height},
                          {"seconds", o.seconds},
                          {"lead_in_s", o.lead_in_s},
                          {"lod", o.lod},
                          {"stroke_contour", o.stroke_contour},
                          {"frames", r.frames},
                          {"frame_ms_median", r.frame_median_ms},
                          {"frame_ms_p99", r.frame_p99_ms},
                          {"interval_ms_median", r.interval_median_ms},
                          {"lag_ms_median", r.lag_median_ms},
                          {"lag_ms_p99", r.lag_p99_ms},
                          {"lag_frames", r.lag_frames},
                          {"hand_wait_ms_median", r.hand_wait_median_ms},
                          {"hand_wait_ms_p99", r.hand_wait_p99_ms},
                          {"targets", r.targets},
                          {"lag_timed", r.lag_timed},
                          {"targets_same_frame", r.same_frame},
                          {"passes_median_ms", r.passes},
                          {"present", r.present},
                          {"frame_budget", r.frame_budget},
                          {"triangles_per_frame", r.triangles_per_frame},
                          {"frame_ms_median_over_first_n", std::isfinite(r.frame_ratio) ? nlohmann::json(r.frame_ratio)
                                                                                         : nlohmann::json()},
                          {"target_median_ms", kTargetMedianMs},
                          {"target_p99_ms", kTargetP99Ms},
                          {"target_lag_frames", kTargetLagFrames},
                          {"verdict", verdict_text(r.verdict)},
                          {"target_met", r.target_met}};
}

BenchRun setup_desk(CLI::App& bench) {
    auto c = std::make_shared<DeskCli>();
    bench.add_option("--desk-seconds", c->o.seconds, "With --desk: session length per output, s (default 12)");
    bench.add_option("--desk-stereo", c->stereo,
                     "With --desk: the outputs to time, comma-separated: mono, anaglyph, side-by-side "
                     "(default mono,anaglyph)");
    bench.add_option("--desk-width", c->o.width, "With --desk: window width, px (default 960)");
    bench.add_option("--desk-height", c->o.height, "With --desk: window height, px (default 540)");
    bench.add_option("--desk-display", c->o.display,
                     "With --desk: window or offscreen (default: window when DISPLAY is set, e.g. under Xvfb)");
    bench.add_option("--desk-lod", c->o.lod, "With --desk: levels of detail on or off (default on)")
        ->check(CLI::IsMember({"on", "off"}));
    bench.add_option("--desk-scales", c->scales,
                     "With --desk: the lowest render scales (--min-render-scale) to time each output at, "
                     "comma-separated, 0.5..1 (default 1,0.75: the eyes always at the window's size, then scaled down "
                     "on the frame budget)");
    bench
        .add_option("--desk-lod-px", c->o.lod_px,
                    "With --desk: the coarsest levels of detail (--max-lod-px, 1..8 pixels) the budget may draw in "
                    "the rows whose scale is below 1 (default 2; the scale-1 row keeps them within 1 pixel)")
        ->check(CLI::Range(1.0, 8.0));
    bench.add_option("--desk-n", c->resolutions,
                     "With --desk: workpiece resolutions N to time, comma-separated, 16..4096 (default: the scene's; "
                     "the first is the baseline of the frame-time ratios), e.g. 256,1024");
    bench
        .add_option("--desk-stroke-contour", c->o.stroke_contour,
                    "With --desk: coarse | full (default coarse): a stroke drawn from the coarse levels while its tiles "
                    "wait, or contoured at full resolution every step (--stroke-contour)")
        ->check(CLI::IsMember({"coarse", "full"}));
    bench
        .add_option("--desk-lead-in", c->o.lead_in_s,
                    "With --desk: seconds the cursor hovers before the first groove, 0..300 (default 0); the row's "
                    "frames are then those after it, once start-up's work is done")
        ->check(CLI::Range(0.0, 300.0));
    bench.add_option("--desk-repeats", c->o.repeats,
                     "With --desk: runs of every row, in turn, and the median over them per row (1..20; default 1)");
    return [c](const BenchCommon& common) {
        DeskBenchOptions o = c->o;
        o.stereo = split_list(c->stereo);
        o.min_scales.clear();
        for (const std::string& s : split_list(c->scales)) {
            char* end = nullptr;
            const double v = std::strtod(s.c_str(), &end);
            if (s.empty() || end != s.c_str() + s.size())
                throw Error("--desk-scales: a comma-separated list of numbers in 0.5..1, got '" + s + "'");
            o.min_scales.push_back(v);
        }
        if (!c->resolutions.empty())
            for (const std::string& s : split_list(c->resolutions)) {
                char* end = nullptr;
                const long v = std::strtol(s.c_str(), &end, 10);
                if (s.empty() || end != s.c_str() + s.size())
                    throw Error("--desk-n: a comma-separated list of whole numbers in 16..4096, got '" + s + "'");
                o.resolutions.push_back(static_cast<int>(std::clamp(v, -1L, 100000L)));
            }
        o.out = common.out;
        run_desk_bench(o);
    };
}

const BenchmarkRegistration kRegistration{
    {"desk",
     "Frames at the desk: a live mouse session in a window (default scene, 960x540), mono and anaglyph; frame time "
     "median and p99, time per pass, mouse-to-photon lag, beside the target",
     44, setup_desk}};

}  // namespace

std::vector<DeskBenchRow> run_desk_bench(const DeskBenchOptions& o) {
    if (!(o.seconds >= 4.0 && o.seconds <= 600.0))
        throw Error("--desk-seconds: must be between 4 and 600, got " + std::to_string(o.seconds));
    if (!(o.lead_in_s >= 0.0 && o.lead_in_s <= 300.0))
        throw Error("--desk-lead-in: must be between 0 and 300 s, got " + std::to_string(o.lead_in_s));
    if (o.width < 64 || o.width > 7680 || o.height < 64 || o.height > 4320)
        throw Error("--desk-width, --desk-height: width 64..7680 and height 64..4320 pixels");
    const char* x = std::getenv("DISPLAY");
    const std::string display = !o.display.empty() ? o.display : (x && *x) ? "window" : "offscreen";
    if (display != "window" && display != "offscreen")
        throw Error("--desk-display: window or offscreen, got '" + o.display + "'");
    if (o.stereo.empty()) throw Error("--desk-stereo: name at least one output");
    for (const std::string& m : o.stereo)
        if (m != "mono" && m != "anaglyph" && m != "side-by-side")
            throw Error("--desk-stereo: a comma-separated list of mono, anaglyph, side-by-side; got '" + m + "'");
    if (!(o.lod_px >= 1.0 && o.lod_px <= 8.0))
        throw Error("--desk-lod-px: must lie in 1..8 pixels, got " + std::to_string(o.lod_px));
    if (o.repeats < 1 || o.repeats > 20)
        throw Error("--desk-repeats: must lie in 1..20, got " + std::to_string(o.repeats));
    if (o.min_scales.empty()) throw Error("--desk-scales: name at least one scale");
    for (const int n : o.resolutions)
        if (n < 16 || n > 4096) throw Error("--desk-n: each N must lie in 16..4096, got " + std::to_string(n));
    const std::vector<int> ns = o.resolutions.empty() ? std::vector<int>{0} : o.resolutions;
    for (const double s : o.min_scales)
        if (!(s >= 0.5 && s <= 1.0))
            throw Error("--desk-scales: each scale must lie in 0.5..1, got " + std::to_string(s));
    prepare_output_dir(o.out, "--out");
    const fs::path dir = fs::path(o.out) / "desk";
    fs::create_directories(dir);
    std::printf("frames at the desk: the default scene in a %dx%d %s, the mouse carving a groove every 1.6 s, "
                "%.0f s per output, levels of detail %s, strokes contoured %s\n",
                o.width, o.height, display == "window" ? "window" : "offscreen frame (paced; no X display)",
                o.seconds, o.lod.c_str(), o.stroke_contour == "coarse" ? "coarse while open" : "at full resolution");
    if (o.lead_in_s > 0.0)
        std::printf("the cursor hovers for %.0f s first; each row's frames, median and p99 are those after it\n",
                    o.lead_in_s);
    std::printf("target: frame median <= %.0f ms, p99 <= %.0f ms, mouse-to-photon lag <= %.0f frames\n",
                kTargetMedianMs, kTargetP99Ms, kTargetLagFrames);
    std::printf("%5s %-13s %5s %5s %6s %9s %9s %10s %8s %8s %8s %10s %6s %s\n", "N", "stereo", "scale", "lodpx",
                "frames", "frame50", "frame99", "interval50", "lag50", "lag99", "lag/frm", "tris/frm", "xN1", "verdict");
    // The row at the first N of the same output and scale (the baseline of the ratios), per repeat.
    const auto ratio = [&](DeskBenchRow& r, const std::vector<DeskBenchRow>& done) {
        r.frame_ratio = std::nan("");
        if (r.resolution == done.front().resolution) return;
        for (const DeskBenchRow& b : done)
            if (b.resolution == done.front().resolution && b.repeat == r.repeat && b.stereo == r.stereo &&
                b.min_scale == r.min_scale && b.frame_median_ms > 0.0)
                r.frame_ratio = r.frame_median_ms / b.frame_median_ms;
    };
    std::vector<DeskBenchRow> rows;
    nlohmann::json table = nlohmann::json::array();
    for (int rep = 1; rep <= o.repeats; ++rep)
        for (const int n : ns)
            for (const std::string& m : o.stereo)
                for (const double min_scale : o.min_scales) {
                    char tag[64];
                    std::snprintf(tag, sizeof tag, "n%d_%s_scale%.3g_run%d", n, m.c_str(), min_scale, rep);
                    DeskBenchRow r = run_one(o, write_scene(dir, o, m, n), m, min_scale, display, dir / tag);
                    r.repeat = rep;
                    const double frame = std::max(r.interval_median_ms, r.frame_median_ms);
                    r.lag_frames = frame > 0.0 ? r.lag_median_ms / frame : std::nan("");
                    judge(r);
                    rows.push_back(std::move(r));
                    ratio(rows.back(), rows);
                    print_row(rows.back());
                    table.push_back(row_json(o, rows.back()));
                }
    if (o.repeats > 1) {
        std::printf("median over %d runs:\n", o.repeats);
        const std::size_t runs = rows.size();
        for (const int n : ns)
            for (const std::string& m : o.stereo)
                for (const double min_scale : o.min_scales) {
                    DeskBenchRow r = median_row(std::vector<DeskBenchRow>(rows.begin(), rows.begin() + runs),
                                                n == 0 ? rows[0].resolution : n, m, min_scale);
                    rows.push_back(std::move(r));
                    ratio(rows.back(), std::vector<DeskBenchRow>(rows.begin() + runs, rows.end()));
                    print_row(rows.back());
                    table.push_back(row_json(o, rows.back()));
                }
    }
    write_json_file((fs::path(o.out) / "desk_bench.json").string(), table);
    return rows;
}

}  // namespace tridex::bench
