// bench/bench_session.hpp - `tridex bench --session`: whole sessions built by the session runtime (the demo's
// scripted stroke on the bundled bunny), timed end to end on each sculpting path.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bench/bench_verdict.hpp"

namespace tridex::bench {

/// One session: its path, resolution and what the haptic loop and the sculpt thread measured.
struct SessionBenchRow {
    int n = 0;                       ///< lattice cells along the longest side
    std::string path;                ///< "cpu" or "gpu" (where the Booleans ran; the report's sculpt_path)
    std::size_t ticks = 0;           ///< haptic ticks
    double period_p50_us = 0.0, period_p99_us = 0.0;    ///< haptic loop period, us
    double compute_p50_us = 0.0, compute_p99_us = 0.0;  ///< haptic tick compute time, us
    std::size_t booleans = 0;        ///< swept Booleans applied
    double boolean_p50_ms = 0.0, boolean_p99_ms = 0.0;  ///< per sculpt step: Booleans + surface publish, ms
    double contour_p50_ms = 0.0, contour_p99_ms = 0.0;  ///< per sculpt step: dirty-tile re-contouring, ms
    bool journal = true;             ///< the session wrote its journal (false: --no-journal)
    double journal_ms = 0.0;         ///< journal time on the sculpt thread (append_ms_total + flush_ms_total), ms
    double journal_sync_thread_ms = 0.0;  ///< the journal's syncing thread's fdatasync time, ms
    double sculpt_busy_ms = 0.0;     ///< the sculpt thread's busy time (SculptStats::busy_ms), ms
    double journal_share = 0.0;      ///< journal_ms / sculpt_busy_ms
    double volume_removed_m3 = 0.0;  ///< what the stroke carved
    double wall_s = 0.0;             ///< the whole command (set-up, session, outputs), s
};

/// What to run.
struct SessionBenchOptions {
    std::vector<int> resolutions{256, 512};          ///< N values
    std::vector<std::string> paths{"cpu", "gpu"};    ///< sculpting paths
    double seconds = 4.0;                            ///< stroke length (device time), s
    std::vector<bool> journal{true};                 ///< journal on (true) and/or off (false, --no-journal) per N and path
    std::string out = "out/bench";                   ///< folder for session_bench.json and the sessions' outputs
    /// N values of the surface-latency rows (run_latency_bench); empty = none.
    std::vector<int> latency_resolutions{256};
};

/// The target of the clay push's surface latency at p99, ms.
inline constexpr double kLatencyTargetMs = 50.0;

/// One surface-latency session (run_latency_bench).
struct LatencyBenchRow {
    int n = 0;                 ///< lattice cells along the longest side
    std::string op;            ///< "subtract" or "push"
    std::size_t group_sweeps =
        0;                 ///< push: the most sweeps per push group (SessionSpec::clay_group_sweeps); 0 for subtract
    double start_s = 0.0;  ///< when the stroke began, s after the session's start (StrokeParams::start_s)
    /// From the workpiece loaded to the first frame done and to every tile at full resolution, ms
    /// (report.json render.startup; -1: none).
    double first_frame_ms = -1.0, refined_ms = -1.0;
    double lod_all_built_ms =
        -1.0;  ///< when the start-up levels of detail were all built, ms after the first frame (-1: never)
    std::string path;          ///< where the Booleans ran (the report's sculpt_path: the device's type decides)
    std::string ao_chosen = "auto";  ///< --ao-while-sculpting of the session (auto, or on for the baseline row)
    std::string pacing;  ///< frames.pacing: "early" (a sculpted change starts a frame early) or "fixed" (--fixed-pace)
    bool ao_sculpting =
        true;  ///< the sculpting frames drew the ambient occlusion (render.ambient_occlusion_while_sculpting)
    std::size_t frames = 0;    ///< frames that first drew a sculpted change
    double p50_ms = 0.0, p99_ms = 0.0, max_ms = 0.0;  ///< tool sample to surface drawn (meshes.sample_to_drawn_ms), ms
    /// What p50_ms..max_ms read (meshes.drawn_clock): "gpu" (the later of the device's end of the frame and its
    /// present), "submit" (its submit and present alone: no calibrated timestamps), "mixed", or "none".
    std::string drawn_clock;
    double sub_p50_ms = 0.0, sub_p99_ms = 0.0;  ///< tool sample to the frame submitted (meshes.sample_to_submitted_ms)
    double step_p50_ms = 0.0, step_p99_ms = 0.0;      ///< per sculpt step: Booleans (or clay) + publish, ms
    double pub_p50_ms = 0.0, pub_p99_ms = 0.0;        ///< its sculpt-side share: sample to mesh published, ms
    double frame_p50_ms = 0.0;                        ///< the run's median frame time (draw + readback), ms
    /// The push target's verdict (latency_verdict) on the rows judged by it; unset for the reference and baseline rows.
    std::optional<Verdict> verdict;
};

/// Runs `tridex run` offscreen (paced at 60 Hz, 960x540 mono) on the bunny scaled as in the demo (0.3 m) at each of
/// options.latency_resolutions, with the demo's 8 mm ball dragged 0.12 m along the surface at 0.1 m/s, once as a
/// subtract and as a clay push in groups of the default size (compute::kClayGroupSweeps) and of 16 sweeps, each once
/// with the stroke starting with the session (while the start-up levels of detail are built) and once 3 s later, and
/// the settled default push again with the occlusion kept on its sculpting frames (--ao-while-sculpting on) and at the
/// fixed 60 Hz pace (--fixed-pace), the baselines of its defaults; prints, per session, the time from a tool sample to
/// the surface it changed being drawn (report.json meshes.sample_to_drawn_ms: p50, p99, max: the frame done on the
/// device and presented) and submitted, beside the push target (p99 <= 50 ms), and the sculpt step times; and writes
/// latency_bench.json into options.out. Throws tridex::Error on a failed session.
std::vector<LatencyBenchRow> run_latency_bench(const SessionBenchOptions& options);

/// The push target's verdict on a latency row: its p99 against kLatencyTargetMs, not measured when no frame drew a
/// timed change (frames 0, or drawn_clock "none").
Verdict latency_verdict(const LatencyBenchRow& row);

/// Runs `tridex demo` sessions (app::run_demo: workpiece, SessionRuntime, scripted stroke, outputs at a small image
/// size) for every resolution and path, reads each one's report.json, prints a table and writes
/// session_bench.json (a list of rows) into options.out. Throws tridex::Error for bad options or an unwritable
/// folder; a GPU row falls back to the CPU when there is no Vulkan device (its `path` then says "cpu").
std::vector<SessionBenchRow> run_session_bench(const SessionBenchOptions& options);

}  // namespace tridex::bench
