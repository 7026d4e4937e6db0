// app/session/report/report.cpp - report.json, haptics.csv and the summary lines of `tridex demo`.
#include "app/session/report/report.hpp"

#include "compute/model/volume.hpp"

#include <cmath>
#include <bit>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/summary.hpp"
#include "app/support/json_file.hpp"
#include "app/session/report/session_report.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "haptics/realtime.hpp"

namespace tridex::app {

namespace {

nlohmann::json summary_json(const Summary& s, bool with_max) {
    nlohmann::json j{{"median", s.median}, {"p99", s.p99}, {"mean", s.mean}};
    if (with_max) j["max"] = s.max;
    return j;
}

std::vector<double> field(const std::vector<haptics::TickRecord>& recs, float haptics::TickRecord::*member, std::size_t skip) {
    std::vector<double> v;
    v.reserve(recs.size());
    for (std::size_t i = skip; i < recs.size(); ++i) v.push_back(recs[i].*member);
    return v;
}

}  // namespace

void write_haptics_csv(const std::string& path, const std::vector<haptics::TickRecord>& records) {
    AtomicFile file(path);  // whole or not at all
    std::FILE* f = file.stream();
    std::fprintf(f, "t_s,hip_x,hip_y,hip_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,hip_inside\n");
    for (const auto& r : records)
        std::fprintf(f, "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g,%.6g,%d,%d\n", r.t_s, r.hip_m.x, r.hip_m.y,
                     r.hip_m.z, r.proxy_m.x, r.proxy_m.y, r.proxy_m.z, r.force_n.x, r.force_n.y, r.force_n.z,
                     r.contact ? 1 : 0, r.hip_inside ? 1 : 0);
    file.commit();
}

nlohmann::json gpu_contour_json(const compute::GpuContourStats& s) {
    return {{"updates", s.updates},
            {"tiles", s.tiles_gpu + s.tiles_cpu},
            {"tiles_gpu", s.tiles_gpu},
            {"host_fallback_tiles", s.tiles_cpu},
            {"split_faces", s.split_faces_gpu},
            {"region_retries", s.region_retries},
            {"pool_grows", s.pool_grows},
            {"dispatches", s.dispatches}};
}

nlohmann::json tool_json(const SessionSpec& spec) {
    nlohmann::json j{{"shape", to_string(spec.tool.kind)}, {"radius_m", spec.tool.radius_m}, {"points", spec.points}};
    if (spec.tool.kind == ToolKind::kFlatEnd) j["length_m"] = spec.tool.length_m;
    j["op"] = spec.op;
    if (spec.op != "subtract") j["material"] = spec.material;
    if (spec.symmetry != "off") j["symmetry"] = spec.symmetry;  // the session's start; keys may toggle it
    return j;
}

nlohmann::json journal_report_json(const compute::JournalStats* journal, const SculptStats& sculpt, double session_s) {
    if (!journal) return nullptr;
    const compute::JournalStats& s = *journal;
    return {{"path", s.path},
            {"records", s.records},
            {"samples", s.samples},
            {"intake_records", s.intake_records},
            {"intake_samples", s.intake_samples},
            {"bytes", s.bytes},
            {"bytes_per_min", session_s > 0.0 ? static_cast<double>(s.bytes) * 60.0 / session_s : 0.0},
            {"flushes", s.flushes},
            {"append_ms_total", s.append_ms_total},
            {"flush_ms_total", s.flush_ms_total},
            {"sync_thread_ms_total", s.sync_thread_ms_total},
            {"synced_bytes", s.synced_bytes},
            {"sculpt_busy_ms_total", sculpt.busy_ms},
            {"error", s.error.empty() ? nlohmann::json(nullptr) : nlohmann::json(s.error)},
            {"checkpoints", sculpt.checkpoints},
            {"checkpoint_ms_total", sculpt.checkpoint_ms_total},
            {"checkpoint_error", sculpt.checkpoint_error.empty() ? nlohmann::json(nullptr) : nlohmann::json(sculpt.checkpoint_error)}};
}

nlohmann::json coarseness_json(const std::vector<CoarsenessChange>& changes) {
    nlohmann::json out = nlohmann::json::array();
    for (const CoarsenessChange& c : changes) {
        const compute::ResampleStats& s = c.resample;
        out.push_back({{"serial", c.serial},
                       {"resolution_before", s.resolution_before},
                       {"resolution_after", s.resolution_after},
                       {"cell_before_m", s.cell_before_m},
                       {"cell_after_m", s.cell_after_m},
                       {"volume_before_m3", s.volume_before_m3},
                       {"volume_after_m3", s.volume_after_m3},
                       {"seconds", c.seconds},
                       {"resample_s", c.resample_s}});
    }
    return out;
}

nlohmann::json history_report_json(const SculptStats& sculpt) {
    const compute::HistoryStats& h = sculpt.history;
    return {{"budget_bytes", h.budget_bytes},
            {"bytes", h.bytes},
            {"undo_steps", h.undo_steps},
            {"redo_steps", h.redo_steps},
            {"strokes", h.strokes},
            {"dropped_steps", h.dropped_steps},
            {"oversize_strokes", h.oversize_strokes},
            {"undos", h.undos},
            {"redos", h.redos},
            {"undo_requests", sculpt.undo_requests},
            {"redo_requests", sculpt.redo_requests},
            {"held_requests", sculpt.held_requests},
            {"held_requests_dropped", sculpt.held_requests_dropped},
            {"undo_ms", summary_json(summarize(sculpt.undo_ms), true)},
            {"coarseness", coarseness_json(sculpt.coarseness)}};
}

namespace {

// How closely the god-object followed the HIP over the recorded ticks: the largest proxy-to-HIP distance (m), that
// distance and the ticks over the tool's radius while the HIP lay outside material (by the snapshot), and the
// largest tick-to-tick change and rise of the force sent (N).
nlohmann::json proxy_follow_json(const std::vector<haptics::TickRecord>& records, double radius_m) {
    double gap = 0.0, gap_outside = 0.0, step = 0.0, rise = 0.0;
    std::size_t over = 0;
    const haptics::TickRecord* prev = nullptr;
    for (const auto& t : records) {
        const double g = glm::length(t.proxy_m - t.hip_m);
        gap = std::max(gap, g);
        if (t.valid_sample && !t.hip_inside) {
            gap_outside = std::max(gap_outside, g);
            over += g > radius_m + 1e-9 ? 1 : 0;
        }
        if (prev) {
            step = std::max(step, glm::length(t.force_n - prev->force_n));
            rise = std::max(rise, glm::length(t.force_n) - glm::length(prev->force_n));
        }
        prev = &t;
    }
    return {{"max_gap_m", gap},
            {"max_gap_hip_outside_m", gap_outside},
            {"ticks_over_radius_hip_outside", over},
            {"max_force_step_n", step},
            {"max_force_rise_n", rise}};
}

}  // namespace

nlohmann::json haptics_report_json(const SessionSpec& spec, const haptics::LoopStats& loop,
                                   const std::vector<haptics::TickRecord>& records, double session_s,
                                   const std::string& device_profile, double device_max_force_n,
                                   const devices::DeviceStatus& device_status) {
    double max_force = 0.0, max_object_force = 0.0;
    std::size_t contact_ticks = 0, object_ticks = 0, presses = 0, paused = 0;
    Aabb tool_span, device_span;  // where the tool went in the world, and the stylus in the device
    std::uint32_t prev_buttons = 0;
    for (const auto& t : records) {
        max_force = std::max(max_force, glm::length(t.force_n));
        contact_ticks += t.contact ? 1 : 0;
        const double object_force = glm::length(t.object_force_n);
        max_object_force = std::max(max_object_force, object_force);
        object_ticks += object_force > 0.0 ? 1 : 0;
        presses += static_cast<std::size_t>(std::popcount(t.device.buttons & ~prev_buttons));  // any button going down
        prev_buttons = t.device.buttons;
        paused += t.modelling_paused ? 1 : 0;
        if (!t.valid_sample) continue;
        tool_span.add(t.tool_world.position);
        device_span.add(t.device.pose.position);
    }
    auto extent = [](const Aabb& b) {
        return b.empty() ? nlohmann::json{0.0, 0.0, 0.0} : nlohmann::json{b.size().x, b.size().y, b.size().z};
    };
    // A refusal of the system, with its errno: "EPERM (Operation not permitted)"; null when granted or not asked.
    auto refusal = [](int err) {
        return err == 0 ? nlohmann::json(nullptr)
                        : nlohmann::json(std::string(strerrorname_np(err) ? strerrorname_np(err) : "E?") + " (" +
                                         std::strerror(err) + ")");
    };
    auto histogram_us = [](const haptics::Histogram& h) {
        return nlohmann::json{{"median", 1e6 * h.quantile(0.5)}, {"p99", 1e6 * h.quantile(0.99)}, {"max", 1e6 * h.max_s}};
    };
    return {{"workspace_mode", spec.workspace_mode},
            {"points", spec.points},
            {"device", device_profile},
            {"device_driver", spec.device_driver},
            {"ticks", loop.ticks},
            {"rate_hz", session_s > 0.0 ? static_cast<double>(loop.ticks) / session_s : 0.0},
            {"period_us", histogram_us(loop.period_histogram)},
            {"compute_us", histogram_us(loop.compute_histogram)},
            {"watchdog_trips", loop.watchdog_trips},
            {"passivity_energy_j", loop.passivity_energy_j},
            {"realtime_scheduling", loop.realtime_scheduling},
            {"memory_locked", loop.memory_locked},
            {"realtime_refused", refusal(loop.realtime_errno)},
            {"memory_lock_refused", refusal(loop.memory_lock_errno)},
            {"reserved_cpu", loop.reserved_cpu >= 0 ? nlohmann::json(loop.reserved_cpu) : nlohmann::json(nullptr)},
            {"periods_over_2ms", loop.periods_over_2ms},
            {"periods_over_5ms", loop.periods_over_5ms},
            {"kernel_preemption", haptics::kernel_preemption()},
            {"velocity_limit_ticks", loop.velocity_limit_ticks},
            {"static_friction", spec.static_friction},
            {"dynamic_friction", spec.dynamic_friction},
            {"materials", spec.materials.size()},
            {"cutting", spec.cutting},
            {"contact_ticks", contact_ticks},
            {"max_force_n", max_force},
            {"object_contact_ticks", object_ticks},
            {"max_object_force_n", max_object_force},
            {"device_max_force_n", device_max_force_n},
            {"stiffness_n_per_m", spec.stiffness_n_per_m},
            {"tool_radius_m", spec.tool.radius_m},
            {"proxy", proxy_follow_json(records, spec.tool.radius_m)},
            {"overruns", loop.overruns},
            {"samples_dropped", loop.samples_dropped},
            {"samples_tap_dropped", loop.tap_dropped},
            {"invalid_samples", loop.invalid_samples},
            {"device_lost", loop.device_lost},
            {"button_presses", presses},
            {"modelling_paused_ticks", paused},
            {"tool_world_extent_m", extent(tool_span)},
            {"device_extent_m", extent(device_span)},
            {"device_status",
             {{"state", devices::to_string(device_status.state)},
              {"faults", devices::fault_names(device_status.faults)},
              {"writes", device_status.writes},
              {"writes_suppressed", device_status.writes_suppressed},
              {"writes_clamped", device_status.writes_clamped}}}};
}

nlohmann::json device_link_json(const devices::DeviceLinkStats& link) {
    if (link.exchanges == 0) return nullptr;
    return {{"exchanges", link.exchanges},
            {"missed_frames", link.missed_frames},
            {"malformed_frames", link.malformed_frames},
            {"zeroed_ticks", link.zeroed_ticks},
            {"exchange_us", {{"mean", 1e6 * link.exchange_mean_s}, {"max", 1e6 * link.exchange_max_s}}},
            {"homed_at_s", link.homed_at_s},
            {"firmware_attempts", link.firmware_attempts}};
}

nlohmann::json link_json(const devices::DeviceLinkStats& link) {
    if (link.link_mode.empty()) return nullptr;
    return {{"mode", link.link_mode},
            {"sealed", link.sealed},
            {"seal_refused", link.seal_refused},
            {"rtt_us", {{"median", link.rtt_median_us}, {"p99", link.rtt_p99_us}}},
            {"lost", link.lost},
            {"rate_hz", link.rate_hz},
            {"stale_snapshots", link.stale_snapshots},
            {"stale_tool_samples", link.stale_tool_samples},
            {"outages", link.link_outages},
            {"server_watchdog_trips", link.server_watchdog_trips},
            {"malformed", link.malformed_frames},
            {"events", link.link_events}};
}

nlohmann::json demo_report_json(const DemoReport& r) {
    const auto& recs = *r.records;
    const auto [period, compute] = tick_summary_json(recs);
    nlohmann::json j;
    j["command"] = r.command;
    j["scene"] = nullptr;
    j["mesh_file"] = r.mesh_path;
    j["resolution"] = r.resolution;
    j["settings"] = nlohmann::json::parse(spec_to_json(*r.settings));
    j["tool"] = tool_json(*r.settings);
    const Pose start = workpiece_pose(*r.settings);
    j["workpiece"] = workpiece_report_json(*r.workpiece, start);
    add_pose_end(j["workpiece"], start, r.workpiece_pose_end);
    j["volume_before_m3"] = r.volume_dexel_m3;
    j["volume_after_m3"] = r.volume_after_m3;
    j["volume_removed_m3"] = r.volume_dexel_m3 - r.volume_after_m3;
    j["mesh"] = {{"vertices", r.vertices},
                 {"triangles", r.triangles},
                 {"boundary_edges", r.edges.boundary_edges},
                 {"nonmanifold_edges", r.edges.nonmanifold_edges},
                 {"misoriented_edges", r.edges.misoriented_edges},
                 {"components", r.components}};
    j["ticks"] = recs.size();
    j["period_us"] = period;
    j["tick_compute_us"] = compute;
    j["booleans"] = r.sculpt->booleans;
    j["tiles_recontoured"] = r.sculpt->tiles_recontoured;
    j["haptics"] = haptics_report_json(*r.settings, r.loop, recs, r.session_s, r.device_profile, r.max_force_n,
                                       r.device_status);
    j["haptics"]["stiffness_n_per_m"] = r.stiffness_n_per_m;
    j["haptics"]["device_link"] = device_link_json(r.device_link);
    j["haptics"]["link"] = link_json(r.device_link);
    j["link"] = link_json(r.device_link);
    j["sculpt"] = sculpt_report_json(*r.sculpt, r.tiles_initial, r.tiles_total, r.session_s, r.sculpt_path,
                                     r.sculpt_backend_reason);
    j["journal"] = journal_report_json(r.journal, *r.sculpt, r.session_s);
    j["history"] = history_report_json(*r.sculpt);
    j["key_requests_sent"] = 0;
    j["stopped_by"] = string_or_null(r.stopped_by);
    if (r.deformation_max_displacement_m)
        j["deformation"] = {{"max_displacement_m", *r.deformation_max_displacement_m}};
    j["more_workpieces"] = r.more_workpieces;
    j["sculpt_path"] = r.sculpt_path;
    j["sculpt_path_reason"] = string_or_null(r.sculpt_path_reason);
    j["sculpt_device"] = r.sculpt_device;
    j["clay_path"] = r.clay_path;
    j["clay_path_reason"] = string_or_null(r.clay_path_reason);
    j["spilled_intervals"] = r.spilled_intervals;
    j["sculpt_validation_messages"] = r.sculpt_validation_messages;
    j["model_bytes"] = model_bytes_json(r.model_bytes);
    j["contour_path"] = r.contour_path;
    j["contour_path_reason"] = string_or_null(r.contour_reason);
    j["contour"] = {{"path", r.contour_path},
                    {"tiles_initial", r.tiles_initial},
                    {"initial_s", r.contour_s},
                    {"gpu", gpu_contour_json(r.gpu_contour)}};
    j["contour"]["gpu"]["lock_wait_ms_total"] = r.contour_lock_wait_ms_total;
    j["contour"]["gpu"]["lock_wait_ms_max"] = r.contour_lock_wait_ms_max;
    j["device"] = r.device;
    j["eye_strategy"] = r.eye_strategy;
    j["validation_messages"] = r.validation_messages;
    j["display"] = "offscreen";
    j["stereo"] = "side_by_side";
    j["swap_eyes"] = false;
    j["eye_resolution"] = {r.eye_width, r.eye_height};
    j["eye_separation_m"] = r.eye_separation_m;
    j["present_mode"] = "offscreen";
    j["head"] = {{"provider", "fixed"}, {"frames_held", 0}};
    j["wand"] = {{"provider", "none"}};
    j["controls"] = nullptr;  // the hands' controls are a live session's
    j["render"] = {{"device", r.device},
                   {"eye_strategy", r.eye_strategy},
                   {"validation_messages", r.validation_messages},
                   {"render_s", r.render_s},
                   {"ambient_occlusion", r.ambient_occlusion}};
    j["timing_s"] = {{"scan_convert", r.scan_s}, {"contour_initial", r.contour_s}, {"session", r.session_s}};
    j["session_s"] = r.session_s;
    j["wall_s"] = r.wall_s;
    j["notes"] = r.notes;
    j["files"] = r.files;
    conform_report(j);
    return j;
}

void write_report_json(const std::string& path, const DemoReport& r) { write_json_file(path, demo_report_json(r)); }

void print_summary(const DemoReport& r, const std::string& out_dir, const std::string& command) {
    const auto& recs = *r.records;
    const Summary period = summarize(field(recs, &haptics::TickRecord::period_us, 1));
    const Summary compute = summarize(field(recs, &haptics::TickRecord::compute_us, 0));
    std::printf("tridex %s: %s at %d cells (cell %.3f mm)\n", command.c_str(), r.mesh_path.c_str(), r.resolution,
                r.lattice.cell_m * 1e3);
    if (!r.stopped_by.empty())
        std::printf("  %s ended the session early; the outputs hold the model as it was then\n", r.stopped_by.c_str());
    std::printf("  haptic loop: %zu ticks, period median %.1f us, p99 %.1f us; tick compute median %.2f us, p99 %.2f us\n",
                recs.size(), period.median, period.p99, compute.median, compute.p99);
    if (r.device_link.exchanges > 0)
        std::printf(
            "  device link: homed at %.3f s; %llu exchanges, mean %.1f us, max %.1f us; %llu missed, %llu malformed\n",
            r.device_link.homed_at_s, static_cast<unsigned long long>(r.device_link.exchanges),
            1e6 * r.device_link.exchange_mean_s, 1e6 * r.device_link.exchange_max_s,
            static_cast<unsigned long long>(r.device_link.missed_frames),
            static_cast<unsigned long long>(r.device_link.malformed_frames));
    if (!r.device_link.link_mode.empty()) {
        const devices::DeviceLinkStats& l = r.device_link;
        std::printf("  link (%s haptic rendering): rtt median %.0f us, p99 %.0f us; %.0f states/s; %llu lost, %llu stale "
                    "snapshots, %llu outages\n",
                    l.link_mode.c_str(), l.rtt_median_us, l.rtt_p99_us, l.rate_hz, static_cast<unsigned long long>(l.lost),
                    static_cast<unsigned long long>(l.stale_snapshots), static_cast<unsigned long long>(l.link_outages));
        if (!l.link_events.empty()) std::printf("  link events: %s\n", l.link_events.c_str());
    }
    const double removed_cm3 = (r.volume_dexel_m3 - r.volume_after_m3) * 1e6;
    std::printf("  sculpt: %llu Booleans, %llu tiles re-contoured; %s %.3f cm^3 (workpiece %.3f cm^3)\n",
                static_cast<unsigned long long>(r.sculpt->booleans),
                static_cast<unsigned long long>(r.sculpt->tiles_recontoured), removed_cm3 < 0.0 ? "added" : "removed",
                std::fabs(removed_cm3), r.volume_dexel_m3 * 1e6);
    std::printf("  mesh: %zu vertices, %zu triangles, %zu boundary edges, %zu non-manifold edges, %zu part%s\n",
                r.vertices, r.triangles, r.edges.boundary_edges, r.edges.nonmanifold_edges, r.components,
                r.components == 1 ? "" : "s");
    if (r.sculpt->islands.specks > 0)
        std::printf("  specks removed: %llu (%.3g mm^3; --keep-islands keeps them)\n",
                    static_cast<unsigned long long>(r.sculpt->islands.specks), r.sculpt->islands.volume_m3 * 1e9);
    std::printf("  sculpt path: %s%s%s\n", r.sculpt_path.c_str(), r.sculpt_path == "gpu" ? (" on " + r.sculpt_device).c_str() : "",
                r.sculpt_path_reason.empty() ? "" : (" (" + r.sculpt_path_reason + ")").c_str());
    if (r.deformation_max_displacement_m)  // a clay session
        std::printf("  clay path: %s%s\n", r.clay_path.c_str(),
                    r.clay_path_reason.empty() ? "" : (" (" + r.clay_path_reason + ")").c_str());
    std::printf("  contour path: %s%s\n", r.contour_path.c_str(),
                r.contour_reason.empty() ? "" : (" (" + r.contour_reason + ")").c_str());
    // The eye strategy in a few words; why it was chosen (the start-up check's pixel counts) is report.json's eye_strategy.
    const std::string strategy = r.eye_strategy.substr(0, r.eye_strategy.find(':'));
    std::printf("  render: %s, %s%s\n", r.device.c_str(), strategy.c_str(),
                strategy.size() < r.eye_strategy.size() ? " (why: report.json eye_strategy)" : "");
    std::string names;
    for (const std::string& f : r.files) names += (names.empty() ? "" : ", ") + std::filesystem::path(f).filename().string();
    std::printf("  wrote %s/: %s in %.1f s\n", out_dir.c_str(), names.empty() ? "nothing" : names.c_str(), r.wall_s);
}

nlohmann::json more_workpieces_report_json(SessionRuntime& rt, const haptics::LoopView& last) {
    if (rt.workpiece_count() < 2) return nullptr;
    nlohmann::json all = nlohmann::json::array();
    for (std::size_t k = 1; k < rt.workpiece_count(); ++k) {
        MoreWorkpiece& m = rt.more_workpiece(k);
        nlohmann::json j = workpiece_report_json(m.workpiece(), m.pose());
        add_pose_end(j, m.pose(), k < last.workpiece_count ? last.workpiece_poses[k] : m.pose());
        j["index"] = k;
        const double after = compute::dexel_volume_m3(m.workpiece().model);
        j["volume_before_m3"] = m.workpiece().volume_dexel_m3;
        j["volume_after_m3"] = after;
        j["volume_removed_m3"] = m.workpiece().volume_dexel_m3 - after;
        const SculptStats& st = m.sculpt_stats();
        j["sculpt"] = {{"samples", st.samples}, {"booleans", st.booleans}, {"steps", st.steps}};
        const compute::JournalStats* js = m.journal_stats();
        j["journal"] = js && js->error.empty() ? nlohmann::json(js->path) : nlohmann::json(nullptr);
        all.push_back(std::move(j));
    }
    return all;
}

}  // namespace tridex::app
