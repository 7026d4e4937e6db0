// app/session/report/report.hpp - the demo's outputs: report.json, haptics.csv and the printed summary.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compute/runtime/sculpt_thread.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "app/scene/session_spec.hpp"
#include "compute/gpu/gpu_contourer.hpp"
#include "compute/model/lattice.hpp"
#include "devices/haptic_device.hpp"
#include "core/tri_mesh.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// Everything report.json says about one demo run (SI units; times in s unless named _us / _ms).
struct DemoReport {
    std::string mesh_path;            ///< the workpiece file that was loaded
    int resolution = 0;               ///< --resolution: cells along the longest side
    compute::Lattice lattice;         ///< the lattice the model used (origin, cell size, cells)
    Mat4 transform{1.0};              ///< input mesh units -> world metres
    double volume_mesh_m3 = 0.0;      ///< exact volume of the transformed input mesh
    double volume_dexel_m3 = 0.0;     ///< tri-dexel volume before carving
    double volume_after_m3 = 0.0;     ///< tri-dexel volume after carving
    EdgeStats edges;                  ///< of the carved mesh
    std::size_t vertices = 0, triangles = 0;  ///< of the carved mesh
    std::size_t components = 0;               ///< connected parts of the carved mesh (mesh_components)
    /// Per-tick haptic records; not owned, must outlive the writers below (non-null).
    const std::vector<haptics::TickRecord>* records = nullptr;
    haptics::LoopStats loop{};                ///< haptic loop counters (overruns, drops, invalid samples)
    const SculptStats* sculpt = nullptr;      ///< sculpt thread counters; not owned, non-null
    std::size_t tiles_initial = 0;            ///< tiles contoured after scan conversion
    std::size_t tiles_total = 0;              ///< tiles in the model's tile grid
    double scan_s = 0.0, contour_s = 0.0, session_s = 0.0, render_s = 0.0, wall_s = 0.0;  ///< wall times, s
    double stiffness_n_per_m = 0.0;           ///< contact stiffness kp, N/m
    double max_force_n = 0.0;                 ///< the device profile's force limit, N
    std::string device;                       ///< Vulkan device name
    std::string eye_strategy;                 ///< which eye strategy rendered, and why (self-test result)
    std::uint32_t validation_messages = 0;    ///< Vulkan validation messages seen (0 expected)
    const SessionSpec* settings = nullptr;///< the session's settings; not owned, non-null
    std::string device_profile;               ///< haptic device profile name
    devices::DeviceStatus device_status;      ///< the device's status channel at the end
    devices::DeviceLinkStats device_link;     ///< the driver's transport measurements (exchanges = 0: none)
    std::string stopped_by;                   ///< "SIGINT" / "SIGTERM" when a signal ended the session early
    /// Clay sessions (op push, smooth, pull or grab): how far the surface moved, m (report.json `deformation`); unset otherwise.
    std::optional<double> deformation_max_displacement_m;
    /// A session of several workpieces: the further ones (more_workpieces_report_json); null otherwise.
    nlohmann::json more_workpieces;
    std::string sculpt_path;                  ///< "gpu" or "cpu": where the Booleans ran
    std::string sculpt_device;                ///< Vulkan device that sculpted ("" on the CPU path)
    std::string sculpt_path_reason;           ///< why the CPU path ran ("--cpu given", "no usable Vulkan device: ...")
    std::string sculpt_backend_reason;        ///< why this backend (decide_backend; report.json `sculpt.backend_reason`)
    std::string clay_path;                    ///< "gpu" or "cpu": where clay sweeps ran (report.json `clay_path`)
    std::string clay_path_reason;             ///< why clay ran on the CPU on the GPU path; "" otherwise
    std::uint64_t spilled_intervals = 0;      ///< intervals in the GPU spill pool at the end (0 on the CPU path)
    std::array<std::size_t, 3> model_bytes{}; ///< bytes of the model per ray set (X, Y, Z) on the sculpting path
    std::uint32_t sculpt_validation_messages = 0;  ///< Vulkan validation messages on the sculpting device (0 expected)
    std::string contour_path;                 ///< "gpu" or "cpu": where dirty tiles were contoured during the session
    std::string contour_reason;               ///< why contouring ran on the CPU ("" on the GPU path)
    compute::GpuContourStats gpu_contour{};   ///< GPU path: the contourer's counters
    /// GPU contour path: time the sculpt thread waited for a frame before re-contouring, summed / longest, ms.
    double contour_lock_wait_ms_total = 0.0, contour_lock_wait_ms_max = 0.0;
    const compute::JournalStats* journal = nullptr;  ///< the session journal's counters; nullptr = no journal
    const Workpiece* workpiece = nullptr;     ///< the session's workpiece (report.json `workpiece`); not owned, non-null
    /// Where the session left the workpiece (its pose, model -> world): report.json `workpiece.pose_end` when the tool
    /// placed it elsewhere than the settings' pose.
    Pose workpiece_pose_end{};
    std::string command = "demo";             ///< the command that ran the session: demo or replay
    int eye_width = 0, eye_height = 0;        ///< per-eye image size, px
    double eye_separation_m = 0.0;            ///< distance between the eyes, m
    bool ambient_occlusion = true;            ///< ambient occlusion in the images
    std::vector<std::string> files;           ///< the files written, full paths (report.json last)
    std::vector<std::string> notes;           ///< one line each: which paths ran on the CPU and why, failures
};

/// Writes one row per haptic tick: t_s, hip_x, hip_y, hip_z, proxy_x, proxy_y, proxy_z, fx, fy, fz,
/// contact (metres, newtons, 0/1). Throws tridex::Error "<path>: ..." when it cannot write.
void write_haptics_csv(const std::string& path, const std::vector<haptics::TickRecord>& records);

/// The GPU contour's counters as report.json writes them under `contour.gpu` (demo, replay and run):
/// updates, tiles, tiles_gpu, host_fallback_tiles, split_faces, region_retries, pool_grows, dispatches.
nlohmann::json gpu_contour_json(const compute::GpuContourStats& stats);

/// The `journal` block of report.json (demo, run): null without a journal (`--no-journal`), else {path, records,
/// samples, bytes (written to the file, header included), bytes_per_min (bytes per minute of the session's wall
/// time session_s, s), flushes (fdatasync rounds), append_ms_total and flush_ms_total (sculpt-thread wall time
/// encoding records, writing them out and syncing: the journal's cost on the sculpt thread, ms),
/// sync_thread_ms_total (the journal's syncing thread's fdatasync time, off the sculpt thread, ms), synced_bytes
/// (bytes made durable), sculpt_busy_ms_total (the sculpt thread's whole busy time, ms, for comparison), error
/// (null, or why the journal stopped: the session went on), checkpoints (checkpoint models written),
/// checkpoint_ms_total (sculpt-thread wall time writing them, ms), checkpoint_error (null, or why checkpoints
/// stopped)}.
nlohmann::json journal_report_json(const compute::JournalStats* journal, const SculptStats& sculpt, double session_s);

/// The `history` block of report.json (demo, run): the undo history at the end {budget_bytes, bytes, undo_steps,
/// redo_steps, strokes (strokes that changed the model), dropped_steps (oldest steps dropped for the budget),
/// oversize_strokes (strokes larger than the budget: applied, not undoable), undos, redos, undo_requests,
/// redo_requests, held_requests (waited for a held button's release), held_requests_dropped, undo_ms (per undo or
/// redo that changed the model: rays written back, active surface published, dirty tiles re-contoured; summary)}.
nlohmann::json history_report_json(const SculptStats& sculpt);
/// report.json `history.coarseness`: each coarseness change the sculpt thread made (SculptStats::coarseness), in order:
/// its serial, the resolutions, cell sizes (m) and volumes (m^3) before and after, and its wall time (s).
nlohmann::json coarseness_json(const std::vector<CoarsenessChange>& changes);

/// The `tool` block of report.json (every session): shape, radius_m, length_m (flat_end), points, op,
/// for union and paint material, and the start symmetry when it is not off.
nlohmann::json tool_json(const SessionSpec& spec);

/// The `haptics` block of report.json, the same for demo, replay and run: the spec's workspace technique,
/// points, device and friction; the loop's ticks, rate (ticks / session_s, Hz), period and compute-time
/// quantiles (us), watchdog trips, passivity energy (J), real-time scheduling, drops and faults; contact
/// ticks and the largest force sent (N) over `records`; `device_status` {state, faults, writes,
/// writes_suppressed, writes_clamped}: the device's status channel at the end (devices::DeviceStatus).
nlohmann::json haptics_report_json(const SessionSpec& spec, const haptics::LoopStats& loop,
                                   const std::vector<haptics::TickRecord>& records, double session_s,
                                   const std::string& device_profile, double device_max_force_n,
                                   const devices::DeviceStatus& device_status);

/// The `haptics.device_link` block of report.json for a driver with a transport (the Falcon): {exchanges,
/// missed_frames, malformed_frames, zeroed_ticks, exchange_us {mean, max}, homed_at_s, firmware_attempts}; null when
/// the driver has none (link.exchanges == 0).
nlohmann::json device_link_json(const devices::DeviceLinkStats& link);
/// The `link` object of a networked device (net driver): {mode, rtt_us {median, p99}, lost, rate_hz,
/// stale_snapshots, outages, server_watchdog_trips, malformed, events}; null for other drivers.
nlohmann::json link_json(const devices::DeviceLinkStats& link);

/// The report.json of a demo or replay session, in the schema every session writes (app/session/report/session_report.hpp,
/// docs/report.md): the keys a demo has no value for (frames, meshes, saves, ...) are null.
nlohmann::json demo_report_json(const DemoReport& report);

/// Writes demo_report_json(report) to `path`. Throws tridex::Error when it cannot write.
void write_report_json(const std::string& path, const DemoReport& report);

/// Prints a few lines: where the outputs went and the headline numbers, the first naming `command` ("tridex
/// demo: ...", "tridex replay: ...").
void print_summary(const DemoReport& report, const std::string& out_dir, const std::string& command = "demo");

/// report.json `more_workpieces` of a stopped session of several workpieces: per further workpiece (k = 1..), its
/// index, source and pose (workpiece_report_json, with "pose_end" where the loop held it last: `last`, the loop's
/// final view), its volumes before and after (m^3), its sculpt thread's samples, Booleans and steps, and its journal;
/// null with one workpiece.
nlohmann::json more_workpieces_report_json(SessionRuntime& rt, const haptics::LoopView& last);

}  // namespace tridex::app
