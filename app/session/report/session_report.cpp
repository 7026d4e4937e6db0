// app/session/report/session_report.cpp - the report.json schema and the blocks every session computes alike.
#include "app/session/report/session_report.hpp"

#include <set>
#include <string_view>

#include "core/summary.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::app {

namespace {

using nlohmann::json;


std::vector<double> tick_field(const std::vector<haptics::TickRecord>& recs, float haptics::TickRecord::*member,
                               std::size_t skip) {
    std::vector<double> v;
    v.reserve(recs.size());
    for (std::size_t i = skip; i < recs.size(); ++i) v.push_back(recs[i].*member);
    return v;
}

// The direct children of `prefix` ("" = the top) named by the schema, and whether `path` has children.
std::vector<std::string> children_of(const std::string& prefix) {
    std::vector<std::string> out;
    for (const ReportField& f : report_schema()) {
        const std::string_view p = f.path;
        if (!prefix.empty() && (p.size() <= prefix.size() + 1 || p.substr(0, prefix.size()) != prefix ||
                                p[prefix.size()] != '.'))
            continue;
        const std::string_view rest = prefix.empty() ? p : p.substr(prefix.size() + 1);
        if (rest.find('.') == std::string_view::npos) out.emplace_back(rest);
    }
    return out;
}

void conform_at(json& j, const std::string& prefix) {
    for (const std::string& key : children_of(prefix)) {
        const std::string path = prefix.empty() ? key : prefix + "." + key;
        if (!j.contains(key)) j[key] = nullptr;
        json& v = j[key];
        if (v.is_object() && !children_of(path).empty()) conform_at(v, path);
    }
}

void violations_at(const json& j, const std::string& prefix, std::vector<std::string>& out) {
    const std::vector<std::string> keys = children_of(prefix);
    const std::set<std::string> listed(keys.begin(), keys.end());
    for (const std::string& key : keys) {
        const std::string path = prefix.empty() ? key : prefix + "." + key;
        if (!j.contains(key)) {
            out.push_back(path + ": missing key");
            continue;
        }
        const json& v = j.at(key);
        if (v.is_object() && !children_of(path).empty()) violations_at(v, path, out);
    }
    for (const auto& [key, value] : j.items())
        if (!listed.count(key)) out.push_back((prefix.empty() ? key : prefix + "." + key) + ": extra key (not in the schema)");
}

}  // namespace

nlohmann::json summary_report_json(const std::vector<double>& v) {
    const Summary s = summarize(v);
    return json{{"median", s.median}, {"p99", s.p99}, {"mean", s.mean}, {"max", s.max}};
}

nlohmann::json summary_report_json(const DurationHistogram& h) {
    return json{
        {"median", h.percentile_ms(0.5)}, {"p99", h.percentile_ms(0.99)}, {"mean", h.mean_ms()}, {"max", h.max_ms()}};
}

namespace {

// The renderer's fields of the schema (report_schema).
std::vector<ReportField> render_fields() {
    return {
        {"render", "the renderer"},
        {"render.device", "the Vulkan device that rendered"},
        {"render.eye_strategy", "as eye_strategy"},
        {"render.validation_messages", "as validation_messages"},
        {"render.render_s", "wall time rendering, s"},
        {"render.tiled", "run: the workpiece was drawn as per-tile meshes; null for demo and replay"},
        {"render.tiles_last", "run: tiles in the last mesh drawn; null for demo and replay"},
        {"render.items", "run: proxy, force arrow and overlay drawn; null for demo and replay"},
        {"render.cull", "run: tiles culled per eye; null for demo and replay"},
        {"render.ambient_occlusion", "ambient occlusion on at the end"},
        {"render.ambient_occlusion_while_sculpting",
         "run: the occlusion on frames drawn while sculpting {on, reason, frames_held (frames drawn without it because "
         "they were sculpting)}; null for demo and replay"},
        {"render.lod",
         "run: tile levels of detail {on, tiles_built, groups_built, discarded (builds thrown away: their tile or "
         "group had changed again), build_ms, pending_at_end, "
         "all_built_after_first_frame_ms, latency {count, median_ms, p99_ms, max_ms}, frames_over_bound (frames that "
         "drew a group over its pixel bound: nothing under it could stand in yet), tile_triangles_per_frame}; null "
         "otherwise"},
        {"render.startup",
         "run: start-up {coarse_first (a first mesh of coarse group levels, the tiles contoured after it), "
         "load_to_first_frame_ms (the workpiece scan-converted or loaded to the first frame done), "
         "first_frame_triangles and first_frame_groups (both eyes), load_to_refined_ms (to the first mesh publish with "
         "every tile at full resolution), tiles_refined (tiles contoured after the first mesh)}; null otherwise"},
        {"render.frame_budget",
         "run: the frame-time budget {target_ms, window, react, min_scale, coarse_lod_px, frames_half, "
         "frames_quarter, frames_coarse_lod, frames_scaled, frames_sculpting, switches, ladder [{occlusion, lod_px, "
         "scale, frames}], now {occlusion, lod_px, scale}, now_calm, now_sculpting}; null for demo and replay"},
        {"render.force_m_per_newton", "force arrow scale, m per N (0 without items); null for demo and replay"},
        {"render.timing", "run: how pass times were measured; null for demo and replay"},
        {"render.tiles", "run: tiles drawn and skipped per frame and eye; null for demo and replay"},
        {"render.passes",
         "run: per pass and eye, {count, total_ms, median_ms, p99_ms, max_ms} (occlusion: the frames that ran it); "
         "null otherwise"},
    };
}

// The sculpt thread's fields of the schema (report_schema).
std::vector<ReportField> sculpt_fields() {
    return {
        {"sculpt", "the sculpt thread's counters"},
        {"sculpt.samples", "tool samples drained from the haptic loop"},
        {"sculpt.booleans", "swept-volume Booleans applied (one per segment)"},
        {"sculpt.steps", "sculpt steps that changed the model"},
        {"sculpt.rays_changed", "rays whose intervals changed, summed over Booleans"},
        {"sculpt.tiles_recontoured", "dirty tiles re-contoured, summed over steps"},
        {"sculpt.tiles_deferred",
         "strokes drawn coarse (--stroke-contour coarse): tiles whose contour waited for the stroke, summed over steps"},
        {"sculpt.deferred_tiles_contoured", "of those, tiles contoured later (after the stroke, or asked for by a frame)"},
        {"sculpt.background_yields",
         "times background work (start-up's refinement, deferred tiles, their mesh publish) stopped early or waited "
         "for a cutting sample or a request"},
        {"sculpt.publishes", "active-surface snapshots published to the haptic loop"},
        {"sculpt.rate_hz", "changing steps per second of session_s"},
        {"sculpt.boolean_ms",
         "per changing step: Booleans and active-surface publish, ms {median, p99, mean, max}"},
        {"sculpt.contour_ms", "per changing step: dirty-tile re-contouring, ms {median, p99, mean, max}"},
        {"sculpt.tiles_initial", "tiles contoured before the session"},
        {"sculpt.tiles_total", "tiles in the model's tile grid"},
        {"sculpt.backend",
         "where the Booleans ran: cpu (the CPU pool) or gpu (the Vulkan compute path); as sculpt_path"},
        {"sculpt.backend_reason",
         "why: --cpu given, --gpu given, or auto by the Vulkan device's type, e.g. \"auto: the "
         "Vulkan device is a CPU implementation (llvmpipe ...)\""},
        {"sculpt.islands_removed",
         "specks removed: pieces a stroke cut loose, smaller than its tool's ball (0 with "
         "--keep-islands)"},
        {"sculpt.island_volume_m3", "their volume, m^3"},
        {"sculpt.island_searches", "strokes searched for specks (strokes that cut; 0 with --keep-islands)"},
        {"sculpt.island_search_ms", "per stroke searched: the search and the removal, ms {median, p99, mean, max}"},
    };
}

}  // namespace

const std::vector<ReportField>& report_schema() {
    static const std::vector<ReportField> schema = [] {
        std::vector<ReportField> fields = {
            {"command", "the command that ran the session: demo, replay or run"},
            {"scene", "run: the scene file; null for demo and replay"},
            {"mesh_file", "the workpiece's mesh file (or the .tdx model it started from)"},
            {"resolution", "lattice cells along the workpiece's longest side"},
            {"settings", "the session spec that decides the model (spec_to_json): tool, op, device, workspace, ..."},
            {"tool", "the tool: shape, radius_m, length_m (flat_end), points, op, material (union, paint), symmetry (when on)"},
            {"workpiece", "the workpiece as loaded"},
            {"workpiece.transform", "4x4 row-major matrix, mesh units -> world m"},
            {"workpiece.volume_mesh_m3", "exact volume of the transformed input mesh, m^3 (0 for a .tdx model)"},
            {"workpiece.volume_dexel_m3", "tri-dexel volume before the session, m^3"},
            {"workpiece.volume_dexel_error_rel", "(volume_dexel - volume_mesh) / volume_mesh; null for a .tdx model"},
            {"workpiece.resolution", "cells along the longest side"},
            {"workpiece.cell_m", "lattice cell size, m"},
            {"workpiece.cells", "lattice cells along x, y, z"},
            {"volume_before_m3", "tri-dexel volume before the session, m^3"},
            {"volume_after_m3", "tri-dexel volume after the session, m^3"},
            {"volume_removed_m3", "volume_before_m3 - volume_after_m3, m^3 (negative when material was added)"},
            {"mesh", "the carved mesh (sculpted.ply): the CPU contour of the final model"},
            {"mesh.vertices", "vertices"},
            {"mesh.triangles", "triangles"},
            {"mesh.boundary_edges", "edges with one triangle (0 for a closed mesh)"},
            {"mesh.nonmanifold_edges", "edges with more than two triangles (0 expected)"},
            {"mesh.misoriented_edges", "edges whose two triangles disagree in orientation (0 expected)"},
            {"mesh.components",
             "connected parts of the mesh (1 for one solid; specks a cut left floating add one each)"},
            {"ticks", "haptic ticks recorded"},
            {"period_us", "haptic tick period, us: {median, p99, mean, max} (the first tick skipped)"},
            {"tick_compute_us", "haptic tick compute time, us: {median, p99, mean, max}"},
            {"booleans", "swept-volume Booleans applied (as sculpt.booleans)"},
            {"tiles_recontoured", "dirty tiles re-contoured (as sculpt.tiles_recontoured)"},
            {"haptics",
             "the haptic loop: ticks, rate, period and compute quantiles, contact, forces, device status, "
             "stiffness_n_per_m, device_link (null without a device transport)"},
            {"link", "a device served by `tridex device-server`: {mode, rtt_us, lost, rate_hz, ...}; null otherwise"},
        };
        for (ReportField& f : sculpt_fields()) fields.push_back(std::move(f));
        for (ReportField& f : std::vector<ReportField>{
            {"journal", "the session journal's counters; null with --no-journal"},
            {"history", "the undo history at the end: budget, steps, undos, redos, undo_ms"},
            {"saves", "Ctrl+S saves during the session; null for demo and replay (no keys)"},
            {"saves.count", "saves that succeeded"},
            {"saves.failures", "saves that failed"},
            {"saves.last", "what the last save said, or null"},
            {"saves.requests", "Ctrl+S requests sent to the sculpt thread"},
            {"key_requests_sent", "undo, redo and save requests sent to the sculpt thread (0 for demo and replay)"},
            {"stopped_by", "SIGINT or SIGTERM when a signal ended the session early; else null"},
            {"stroke_completed", "run with a scripted stroke: the loop played all of it; null for demo and replay"},
            {"deformation", "clay: {max_displacement_m}; scene objects (run): the elastic objects' report; else null"},
            {"references", "run with reference objects: per object its name, mesh, triangles, size_m, position_m, distance grid "
                           "(nodes, cell_m, bytes) and build_s; else null"},
            {"more_workpieces",
             "a scene of several workpieces: per further workpiece its index (1..), source, lattice, pose and "
             "pose_end, volume_before_m3, volume_after_m3, volume_removed_m3, sculpt {samples, booleans, steps} and "
             "journal; else null"},
            {"sculpt_path", "where the Booleans ran: gpu or cpu"},
            {"sculpt_path_reason", "why the Booleans ran on the CPU; null on the GPU path"},
            {"sculpt_device", "the Vulkan device that sculpted; empty on the CPU path"},
            {"clay_path", "where push, smooth, pull and grab ran: gpu or cpu"},
            {"clay_path_reason", "why clay ran on the CPU on the GPU path; null otherwise"},
            {"spilled_intervals", "intervals in the GPU spill pool at the end (0 on the CPU path)"},
            {"sculpt_validation_messages", "Vulkan validation messages on the sculpting device (0 expected)"},
            {"model_bytes", "bytes of the model per ray set on the sculpting path"},
            {"model_bytes.x", "X rays"},
            {"model_bytes.y", "Y rays"},
            {"model_bytes.z", "Z rays"},
            {"model_bytes.total", "all three"},
            {"contour_path", "where dirty tiles were contoured during the session: gpu or cpu"},
            {"contour_path_reason", "why contouring ran on the CPU; null on the GPU path"},
            {"contour", "contouring"},
            {"contour.path", "as contour_path"},
            {"contour.tiles_initial", "tiles contoured before the session"},
            {"contour.initial_s", "wall time of that initial contouring, s"},
            {"contour.gpu", "the GPU contourer's counters (updates, tiles, host_fallback_tiles, ...)"},
            {"device", "the Vulkan device that rendered the images"},
            {"eye_strategy", "how the two eyes were rendered, and why (the start-up self-test)"},
            {"validation_messages", "Vulkan validation messages while rendering (0 expected)"},
            {"display", "window, fullscreen or offscreen"},
            {"stereo", "the stereo output: mono, anaglyph, side_by_side, top_bottom, frame_sequential or quad"},
            {"swap_eyes", "the eyes were swapped"},
            {"eye_resolution", "per-eye image [width, height], px"},
            {"refresh_hz", "the display's refresh rate, Hz; null for demo and replay (one frame at the end)"},
            {"eye_separation_m", "distance between the eyes, m"},
            {"present_mode", "window: the swap chain's present mode; offscreen: offscreen"},
            {"head",
             "where the head pose came from: {provider, frames_held (frames drawn from the last good head pose: the "
             "head was at or behind the screen, or not finite), ...} (DTrack: frames tracked, stale, latency)"},
            {"wand", "the navigation wand: {provider: none} or the DTrack wand's report"},
            {"controls",
             "run: the hands' controls: bindings {source, tool {buttons}, wand {buttons, joystick_y}}, menu {opens, "
             "flicks, cancels, choices {action: n}, radius_m}, actions {action: {key, button, menu, axis: n}}; null "
             "for demo and replay"},
            {"frames",
             "run: frames rendered, presents, frame_ms, interval_ms, gpu_ms histograms; null for demo and "
             "replay"},
             })
            fields.push_back(std::move(f));
        for (ReportField& f : render_fields()) fields.push_back(std::move(f));
        for (ReportField& f : std::vector<ReportField>{
                 {"meshes",
                  "run: meshes drawn and published {versions_drawn, last_version, published, publish_ms, "
                  "sample_to_drawn_ms "
                  "(to the frame done: the device finished and presented), sample_to_submitted_ms, drawn_clock (gpu, "
                  "submit, "
                  "mixed or null), "
                  "sample_to_published_ms, triangles}; null for demo and replay"},
                 {"mouse", "the mouse stylus's counters (--device mouse); null otherwise"},
                 {"study", "a study scene's trial report; null otherwise"},
                 {"cluster",
                  "run --cluster, rank 0: the render ranks kept in step (frames, bytes, checks, latency, swap spread, "
                  "each rank's report, failure); null otherwise"},
                 {"timing_s", "wall times, s"},
                 {"timing_s.scan_convert", "scan conversion (or model loading)"},
                 {"timing_s.contour_initial", "the initial contouring"},
                 {"timing_s.session", "the haptic loop and sculpt thread running (as session_s)"},
                 {"session_s", "the haptic loop and sculpt thread running, s"},
                 {"wall_s", "the whole command, s"},
                 {"notes", "one line each: how the session ended, which paths ran on the CPU and why, failures"},
                 {"files", "the files written, full paths"},
             })
            fields.push_back(std::move(f));
        return fields;
    }();
    return schema;
}

void conform_report(nlohmann::json& report) { conform_at(report, ""); }

std::vector<std::string> report_schema_violations(const nlohmann::json& report) {
    std::vector<std::string> out;
    if (!report.is_object()) return {"(top): not an object"};
    violations_at(report, "", out);
    return out;
}

nlohmann::json workpiece_report_json(const Workpiece& wp, const Pose& world_from_model) {
    json transform = json::array();
    for (int row = 0; row < 4; ++row) {
        json rj = json::array();
        for (int col = 0; col < 4; ++col) rj.push_back(wp.to_world[col][row]);  // row-major in the file
        transform.push_back(rj);
    }
    const compute::Lattice& lat = wp.model.lattice;
    json out{{"transform", transform},
            {"volume_mesh_m3", wp.volume_mesh_m3},
            {"volume_dexel_m3", wp.volume_dexel_m3},
            {"volume_dexel_error_rel",
             wp.volume_mesh_m3 > 0.0 ? json((wp.volume_dexel_m3 - wp.volume_mesh_m3) / wp.volume_mesh_m3) : json(nullptr)},
            {"resolution", wp.resolution},
            {"cell_m", lat.cell_m},
            {"cells", lat.cells}};
    if (!world_from_model.is_identity()) out["pose"] = pose_report_json(world_from_model);
    return out;
}

void add_pose_end(nlohmann::json& workpiece, const Pose& start, const Pose& end) {
    if (end.position != start.position || end.orientation != start.orientation)
        workpiece["pose_end"] = pose_report_json(end);
}

nlohmann::json pose_report_json(const Pose& pose) {
    const Vec3& p = pose.position;
    const Quat& q = pose.orientation;
    return {{"position_m", {p.x, p.y, p.z}}, {"orientation", {q.w, q.x, q.y, q.z}}};
}

nlohmann::json carved_mesh_report_json(const TriMesh& carved) {
    const EdgeStats e = edge_stats(carved);
    return {{"vertices", carved.positions.size()},
            {"triangles", carved.triangles.size()},
            {"boundary_edges", e.boundary_edges},
            {"nonmanifold_edges", e.nonmanifold_edges},
            {"misoriented_edges", e.misoriented_edges},
            {"components", mesh_components(carved)}};
}

std::array<nlohmann::json, 2> tick_summary_json(const std::vector<haptics::TickRecord>& records) {
    return {summary_report_json(tick_field(records, &haptics::TickRecord::period_us, 1)),
            summary_report_json(tick_field(records, &haptics::TickRecord::compute_us, 0))};
}

nlohmann::json sculpt_report_json(const SculptStats& s, std::size_t tiles_initial, std::size_t tiles_total,
                                  double session_s, const std::string& backend, const std::string& backend_reason) {
    return {{"samples", s.samples},
            {"booleans", s.booleans},
            {"steps", s.steps},
            {"rays_changed", s.rays_changed},
            {"tiles_recontoured", s.tiles_recontoured},
            {"tiles_deferred", s.tiles_deferred},
            {"deferred_tiles_contoured", s.deferred_tiles_contoured},
            {"background_yields", s.background_yields},
            {"publishes", s.publishes},
            {"rate_hz", session_s > 0.0 ? static_cast<double>(s.steps) / session_s : 0.0},
            {"boolean_ms", summary_report_json(s.boolean_ms)},
            {"contour_ms", summary_report_json(s.contour_ms)},
            {"tiles_initial", tiles_initial},
            {"tiles_total", tiles_total},
            {"backend", backend},
            {"backend_reason", string_or_null(backend_reason)},
            {"islands_removed", s.islands.specks},
            {"island_volume_m3", s.islands.volume_m3},
            {"island_searches", s.islands.searches},
            {"island_search_ms", summary_report_json(s.island_search_ms)}};
}

nlohmann::json model_bytes_json(const std::array<std::size_t, 3>& b) {
    return {{"x", b[0]}, {"y", b[1]}, {"z", b[2]}, {"total", b[0] + b[1] + b[2]}};
}

nlohmann::json string_or_null(const std::string& s) { return s.empty() ? json(nullptr) : json(s); }

}  // namespace tridex::app
