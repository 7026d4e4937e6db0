// app/session/run/run_report.hpp - report.json of `tridex run`.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "app/session/run/run_session.hpp"

namespace tridex::app {

/// The report of a run (SI units; times in s unless named _ms / _us):
/// { "scene", "display", "stereo", "swap_eyes", "head": {"provider", ... (DTrack: app/input/dtrack_head.hpp report_json)},
///   "wand": {"provider": "none"} or app/input/dtrack_wand.hpp wand_report_json,
///   "eye_resolution": [w, h], "refresh_hz", "device",
///   "eye_strategy", "present_mode", "validation_messages",
///   "frames": { "count", "presents", "last_eye", "render_s",
///               "frame_ms" | "interval_ms" | "gpu_ms": renderer::histogram_json (bins, p50/p95/p99, ...),
///               "present": WindowPresenter timings (window only) },
///   "meshes": { "versions_drawn", "last_version", "published", "publish_ms": {median, p99, max, mean},
///               "triangles" },
///   "haptics": { "ticks", "overruns", "samples_dropped", "invalid_samples", "rate_hz", "realtime_scheduling",
///                "period_us": {median, p99, max}, "compute_us": {median, p99, max} },
///   "sculpt": { "samples", "booleans", "steps", "tiles_recontoured", "rate_hz", "boolean_ms": {...}, "contour_ms": {...} },
///   "sculpt_path" ("gpu" | "cpu"), "sculpt_device", "spilled_intervals",
///   "stroke_completed", "session_s", "volume_before_m3", "volume_after_m3", "wall_s", "notes": [...], "files": [...] }
nlohmann::json run_report_json(const RunResult& result);

/// Writes run_report_json(result) to `path`, indented. Throws tridex::Error "<path>: cannot write" on failure.
void write_run_report(const std::string& path, const RunResult& result);

}  // namespace tridex::app
