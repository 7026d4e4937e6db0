// app/session/run/run_report.cpp - report.json of `tridex run`.
#include "app/session/run/run_report.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <string>

#include "app/support/json_file.hpp"
#include "app/session/report/report.hpp"
#include "app/session/report/session_report.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {

using nlohmann::json;

// What meshes.sample_to_drawn_ms read: the device's clock with the frame's present ("gpu"), the frame's submit and
// present alone ("submit": no calibrated timestamps), both ("mixed"), or null when no frame drew a sculpted change.
json drawn_clock(const RunResult& r) {
    if (r.drawn_on_gpu_clock + r.drawn_on_submit_clock == 0) return nullptr;
    return r.drawn_on_submit_clock == 0 ? "gpu" : r.drawn_on_gpu_clock == 0 ? "submit" : "mixed";
}

double rate_hz(double count, double seconds) { return seconds > 0.0 ? count / seconds : 0.0; }

// render.lod: whether levels were on, what the worker built and when, and the triangles drawn.
json lod_json(const RunResult& r, const RenderLog& log) {
    const SculptStats& s = r.sculpt;
    json ready = nullptr;  // all levels in, ms after the first frame started (0: before it)
    if (s.lod_all_built_s >= 0.0 && r.first_frame_s >= 0.0)
        ready = std::max(0.0, 1000.0 * (s.lod_all_built_s - r.first_frame_s));
    json latency = nullptr;
    if (s.lod_latency_ms.count() > 0) {
        const DurationHistogram& l = s.lod_latency_ms;
        latency = json{{"count", l.count()},
                       {"median_ms", l.percentile_ms(0.5)},
                       {"p99_ms", l.percentile_ms(0.99)},
                       {"max_ms", l.max_ms()}};
    }
    const double frames = static_cast<double>(log.frames);
    const auto per_frame = [&](std::uint64_t sum) { return frames > 0.0 ? static_cast<double>(sum) / frames : 0.0; };
    return json{{"on", r.setup.lod},
                {"tiles_built", s.lod_tiles_built},
                {"groups_built", s.lod_groups_built},
                {"discarded", s.lod_discarded},
                {"build_ms", s.lod_build_ms},
                {"pending_at_end", s.lod_pending},
                {"all_built_after_first_frame_ms", ready},
                {"latency", latency},
                {"tile_triangles_last_frame", {log.tile_triangles_last[0], log.tile_triangles_last[1]}},
                {"groups_drawn_last_frame", {log.groups_drawn_last[0], log.groups_drawn_last[1]}},
                {"frames_over_bound", log.frames_over_bound},
                {"tile_triangles_per_frame", {per_frame(log.tile_triangles[0]), per_frame(log.tile_triangles[1])}},
                {"groups_per_frame", {per_frame(log.groups_drawn[0]), per_frame(log.groups_drawn[1])}},
                {"groups_own_only_per_frame", {per_frame(log.groups_own_only[0]), per_frame(log.groups_own_only[1])}}};
}

// render.startup: from the workpiece loaded to the first frame done and to every tile at full resolution.
json startup_json(const RunResult& r) {
    const auto after_load_ms = [&](double t_s) -> json {
        if (t_s < 0.0 || r.loaded_s < 0.0) return nullptr;
        return 1000.0 * (t_s - r.loaded_s);
    };
    return json{{"coarse_first", r.coarse_first},
                {"load_to_first_frame_ms", after_load_ms(r.first_frame_done_s)},
                {"first_frame_triangles", r.first_frame_triangles},
                {"first_frame_groups", r.first_frame_groups},
                {"load_to_refined_ms", after_load_ms(r.sculpt.startup_refined_s)},
                {"tiles_refined", r.sculpt.startup_tiles_refined}};
}

json render_json(const RunResult& r) {
    const RenderLog& log = r.render;
    json per_frame = json::array();
    for (const auto& f : log.tiles) per_frame.push_back({f[0].drawn, f[0].skipped, f[1].drawn, f[1].skipped});
    json passes = json::object();
    for (const auto& [name, ms] : log.pass_ms)
        passes[name] = json{{"count", ms.count()},
                            {"total_ms", ms.sum_ms()},
                            {"median_ms", ms.percentile_ms(0.5)},
                            {"p99_ms", ms.percentile_ms(0.99)},
                            {"max_ms", ms.max_ms()}};
    return json{{"device", r.device},
                {"eye_strategy", r.eye_strategy},
                {"validation_messages", r.validation_messages},
                {"render_s", r.render_s},
                {"tiled", r.tiled},
                {"tiles_last", r.tiles_last},
                {"items", r.setup.items},
                {"cull", r.setup.cull},
                {"ambient_occlusion", r.setup.ao},
                {"ambient_occlusion_while_sculpting",
                 {{"on", r.ao_sculpting}, {"reason", r.ao_sculpting_reason}, {"frames_held", r.frames_occlusion_held}}},
                {"frame_budget", r.frame_budget},
                {"lod", lod_json(r, log)},
                {"startup", startup_json(r)},
                {"force_m_per_newton", r.force_m_per_newton},
                {"timing", log.timing_note},
                {"tiles",
                 {{"per_frame_columns", {"left_drawn", "left_skipped", "right_drawn", "right_skipped"}},
                  {"per_frame", per_frame},
                  {"per_frame_kept", RenderLog::kTileFramesKept},
                  {"drawn_total", log.tiles_drawn},
                  {"skipped_total", log.tiles_skipped},
                  {"uploads_total", log.tile_uploads}}},
                {"passes", passes}};
}

}  // namespace

void RenderLog::add(const renderer::FrameStats& stats) {
    ++frames;
    if (tiles.size() < kTileFramesKept) tiles.push_back(stats.tiles);
    for (int e = 0; e < 2; ++e) {
        tiles_drawn[e] += stats.tiles[e].drawn;
        tiles_skipped[e] += stats.tiles[e].skipped;
        tile_triangles[e] += stats.tile_triangles[e];
        tile_triangles_last[e] = stats.tile_triangles[e];
        groups_drawn_last[e] = stats.groups_drawn[e];
        groups_drawn[e] += stats.groups_drawn[e];
        groups_own_only[e] += stats.groups_own_only[e];
    }
    tile_uploads += stats.tile_uploads;
    if (!stats.groups_wanting_detail.empty()) ++frames_over_bound;
    for (const renderer::PassTime& p : stats.passes) {
        const std::string name = p.pass + (p.eye == 0 ? ".left" : p.eye == 1 ? ".right" : "");
        pass_ms.try_emplace(name, DurationHistogram::fine()).first->second.add(p.ms);
    }
    timing_note = stats.timing_note;
}

json run_report_json(const RunResult& r) {
    const RunSetup& su = r.setup;
    const RunScene& sc = su.scene;
    json gpu = gpu_contour_json(r.gpu_contour);
    gpu["lock_wait_ms_total"] = r.contour_lock_wait_ms_total;
    gpu["lock_wait_ms_max"] = r.contour_lock_wait_ms_max;
    json frames{{"count", r.frames},
                {"presents", r.presents},
                {"pacing", r.pacing},
                {"early", r.frames_early},
                {"last_eye", r.last_eye},
                {"window_resizes", r.window_resizes},
                {"render_scale_changes", r.render_scale_changes},
                {"eye_resolution_last", {r.eye_resolution_last.first, r.eye_resolution_last.second}},
                {"eye_resolution_window", {r.eye_resolution_window.first, r.eye_resolution_window.second}},
                {"render_s", r.render_s},
                {"rate_hz", rate_hz(static_cast<double>(r.frames), r.render_s)},
                {"frame_ms", renderer::histogram_json(r.frame_ms)},
                {"interval_ms", renderer::histogram_json(r.interval_ms)},
                {"gpu_ms", renderer::histogram_json(r.gpu_ms)}};
    if (!r.present_timings.is_null()) frames["present"] = r.present_timings;
    json haptics = r.haptics;
    if (haptics.is_object()) {
        if (!haptics.contains("device_link")) haptics["device_link"] = nullptr;
        if (!haptics.contains("link")) haptics["link"] = nullptr;
    }
    json sculpt = sculpt_report_json(r.sculpt, r.contour_tiles_initial, r.tiles_total, r.session_s, r.sculpt_path,
                                     r.sculpt_backend_reason);
    json j{
        {"command", "run"},
        {"scene", sc.source},
        {"mesh_file", sc.spec.model_path.empty() ? sc.spec.mesh_path : sc.spec.model_path},
        {"resolution", sc.spec.resolution},
        {"settings", json::parse(spec_to_json(r.spec))},
        {"tool", r.tool},
        {"workpiece", r.workpiece},
        {"volume_before_m3", r.volume_before_m3},
        {"volume_after_m3", r.volume_after_m3},
        {"volume_removed_m3", r.volume_before_m3 - r.volume_after_m3},
        {"mesh", r.carved_mesh},
        {"ticks", r.ticks},
        {"period_us", r.period_us},
        {"tick_compute_us", r.tick_compute_us},
        {"booleans", r.sculpt.booleans},
        {"tiles_recontoured", r.sculpt.tiles_recontoured},
        {"haptics", haptics},
        {"link", haptics.is_object() ? haptics["link"] : json(nullptr)},
        {"sculpt", sculpt},
        {"journal", r.journal},
        {"history", history_report_json(r.sculpt)},
        {"saves",
         {{"count", r.saves.saves},
          {"failures", r.saves.failures},
          {"last", r.saves.message.empty() ? json(nullptr) : json(r.saves.message)},
          {"requests", r.save_requests_sent}}},
        {"key_requests_sent", r.requests_sent},
        {"stopped_by", string_or_null(r.stopped_by)},
        {"stroke_completed", r.stroke_completed},
        {"deformation", r.deformation},
        {"references", r.references},
        {"more_workpieces", r.more_workpieces},
        {"sculpt_path", r.sculpt_path},
        {"sculpt_path_reason", string_or_null(r.sculpt_path_reason)},
        {"sculpt_device", r.sculpt_device},
        {"clay_path", r.clay_path},
        {"clay_path_reason", string_or_null(r.clay_path_reason)},
        {"spilled_intervals", r.spilled_intervals},
        {"sculpt_validation_messages", r.sculpt_validation_messages},
        {"model_bytes", model_bytes_json(r.model_bytes)},
        {"contour_path", r.contour_path},
        {"contour_path_reason", string_or_null(r.contour_reason)},
        {"contour",
         {{"path", r.contour_path},
          {"tiles_initial", r.contour_tiles_initial},
          {"initial_s", r.contour_initial_s},
          {"gpu", gpu}}},
        {"device", r.device},
        {"eye_strategy", r.eye_strategy},
        {"validation_messages", r.validation_messages},
        {"display", to_string(su.display)},
        {"stereo", std::string(renderer::to_string(sc.display.stereo))},
        {"swap_eyes", su.swap_eyes},
        {"eye_resolution", {sc.display.width_px, sc.display.height_px}},
        {"refresh_hz", sc.display.refresh_hz},
        {"eye_separation_m", sc.display.eye_separation_m},
        {"present_mode", r.present_mode},
        {"head", r.head.is_null() ? nlohmann::json{{"provider", to_string(sc.head)}} : r.head},
        {"wand", r.wand.is_null() ? nlohmann::json{{"provider", "none"}} : r.wand},
        {"controls", r.controls},
        {"frames", frames},
        {"render", render_json(r)},
        {"meshes",
         {{"versions_drawn", r.mesh_versions_drawn},
          {"last_version", r.last_mesh_version},
          {"published", r.sculpt.mesh_publishes},
          {"publish_ms", summary_report_json(r.sculpt.mesh_publish_ms)},
          {"sample_to_drawn_ms", summary_report_json(r.sample_to_drawn_ms)},
          {"sample_to_submitted_ms", summary_report_json(r.sample_to_submitted_ms)},
          {"drawn_clock", drawn_clock(r)},
          {"sample_to_published_ms", summary_report_json(r.sample_to_published_ms)},
          {"triangles", r.triangles}}},
        {"mouse", r.mouse},
        {"study", r.study},
        {"cluster", r.companions.contains("cluster") ? r.companions["cluster"] : nlohmann::json(nullptr)},
        {"timing_s", {{"scan_convert", r.scan_s}, {"contour_initial", r.contour_initial_s}, {"session", r.session_s}}},
        {"session_s", r.session_s},
        {"wall_s", r.wall_s},
        {"notes", r.notes},
        {"files", r.files}};
    for (const auto& [key, value] : r.companions.items()) j[key] = value;  // each companion's part under its key
    conform_report(j);
    return j;
}

void write_run_report(const std::string& path, const RunResult& result) {
    write_json_file(path, run_report_json(result));
}

}  // namespace tridex::app
