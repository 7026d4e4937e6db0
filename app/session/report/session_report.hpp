// app/session/report/session_report.hpp - the one report.json schema every session writes (demo, replay, run), and the blocks
// of it that every session computes the same way.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/session/runtime/session_runtime.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/duration_histogram.hpp"
#include "core/tri_mesh.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// One key of report.json: its dotted path from the top ("workpiece.cell_m") and what it holds, units named.
struct ReportField {
    const char* path;     ///< dotted path; a path with children (e.g. "sculpt") names a closed object
    const char* meaning;  ///< one line: what the value is, in SI units unless the name says _ms / _us
};

/// Every key of report.json, in the order the reference (docs/report.md) lists them. An object whose children are
/// listed here is closed: a session writes exactly those keys (null where it has no value). An object without
/// listed children (settings, haptics, journal, ...) is documented by the function that builds it.
const std::vector<ReportField>& report_schema();

/// Completes a report to the schema: every schema key absent from `report` (or from a closed object in it) is
/// added as null. Keys the schema lacks are left as they are (report_schema_violations names them).
void conform_report(nlohmann::json& report);

/// The keys of `report` that break the schema, as dotted paths with a reason ("extra key", "missing key"): keys of
/// closed objects the schema does not list, and schema keys absent. Empty for a conforming report.
std::vector<std::string> report_schema_violations(const nlohmann::json& report);

/// Order statistics of `v` as report.json writes them: {median, p99, mean, max}, in the units of v (core/summary.hpp;
/// all 0 for an empty v).
nlohmann::json summary_report_json(const std::vector<double>& v);
/// The same from a histogram of durations, ms: median and p99 are the upper edges of their bins (all 0 when empty).
nlohmann::json summary_report_json(const DurationHistogram& h);

/// `workpiece` block: {transform (4x4 row-major, mesh units -> world m), volume_mesh_m3, volume_dexel_m3,
/// volume_dexel_error_rel, resolution, cell_m, cells ([x, y, z])}, from the session's workpiece. volume_dexel_m3 is
/// the model's volume right after scan conversion (or loading); volume_mesh_m3 is 0 for a model loaded from .tdx.
/// A posed workpiece (`world_from_model` not the identity) adds pose: {position_m, orientation [w, x, y, z]}, its
/// model frame -> the world.
nlohmann::json workpiece_report_json(const Workpiece& wp, const Pose& world_from_model = Pose{});

/// A pose as the report writes it: {position_m: [x, y, z], orientation: [w, x, y, z]}.
nlohmann::json pose_report_json(const Pose& pose);

/// Adds `pose_end` (pose_report_json of `end`) to a report's `workpiece` block when the session left the workpiece
/// elsewhere than `start` (the tool placed it, ToolOp::kPlace); adds nothing otherwise.
void add_pose_end(nlohmann::json& workpiece, const Pose& start, const Pose& end);

/// `mesh` block: the carved (final) mesh's {vertices, triangles, boundary_edges, nonmanifold_edges,
/// misoriented_edges}.
nlohmann::json carved_mesh_report_json(const TriMesh& carved);

/// `period_us` and `tick_compute_us`: the haptic loop's tick period (first tick skipped) and per-tick compute time
/// over `records`, {median, p99, mean, max} in microseconds.
std::array<nlohmann::json, 2> tick_summary_json(const std::vector<haptics::TickRecord>& records);

/// `sculpt` block: the sculpt thread's counters {samples, booleans, steps, rays_changed, tiles_recontoured,
/// publishes, rate_hz (changing steps per second of session_s), boolean_ms, contour_ms ({median, p99, mean, max}
/// per changing step), tiles_initial (tiles contoured before the session), tiles_total (tiles of the model),
/// backend ("cpu" or "gpu": where the Booleans ran), backend_reason (why: decide_backend's reason)}.
nlohmann::json sculpt_report_json(const SculptStats& sculpt, std::size_t tiles_initial, std::size_t tiles_total,
                                  double session_s, const std::string& backend, const std::string& backend_reason);

/// `model_bytes` block: bytes of the model per ray set on the sculpting path, {x, y, z, total}.
nlohmann::json model_bytes_json(const std::array<std::size_t, 3>& bytes);

/// A string, or null when it is empty (report.json writes an absent reason as null).
nlohmann::json string_or_null(const std::string& s);

}  // namespace tridex::app
