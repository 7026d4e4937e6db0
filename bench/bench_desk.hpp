// bench/bench_desk.hpp - frames at the desk: live mouse sessions in a window, per stereo output, beside the targets.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_verdict.hpp"

namespace tridex::bench {

/// What `tridex bench --desk` runs: one live session per stereo output, the default scene's workpiece and head in a
/// desk window, the mouse as the stylus driven by a scripted cursor (press, drag a groove, release, every 1.6 s).
struct DeskBenchOptions {
    double seconds = 12.0;                             ///< session length per output, s (4..600)
    int width = 960, height = 540;                     ///< window size, px (64..7680 x 64..4320)
    std::vector<std::string> stereo{"mono", "anaglyph"};  ///< outputs timed: mono, anaglyph, side-by-side
    /// "window" (needs an X display, e.g. Xvfb), "offscreen" (paced at the refresh rate), or "" = window when
    /// DISPLAY is set, else offscreen.
    std::string display;
    std::string lod = "on";                            ///< levels of detail: on | off
    std::string stroke_contour = "coarse";             ///< a stroke's tiles: coarse | full (--stroke-contour)
    /// Workpiece resolutions N (cells along the bunny's longest side, 16..4096) timed in turn; empty: the default
    /// scene's own. The first is the baseline the others' frame times are divided by, per output and scale.
    std::vector<int> resolutions;
    /// The lowest render scales (--min-render-scale) each output is timed at, in turn (0.5..1). 1 is the baseline:
    /// the eyes always at the window's size and the levels always within 1 pixel (--max-lod-px 1), the budget trading
    /// only the occlusion.
    std::vector<double> min_scales{1.0, 0.75};
    /// The coarsest levels of detail (--max-lod-px, 1..8) the budget may draw in the rows whose scale is below 1.
    double lod_px = 2.0;
    /// Runs of every row, 1..20: the rows are run in turn, then again, so that a busy moment of a shared machine
    /// falls on one run of each, and the median over the runs is printed (and written) per row.
    int repeats = 1;
    /// Seconds the cursor hovers before the first groove (0..300), after which the row still carves for `seconds`:
    /// the frames after start-up's work, as a session an hour long has them. The row's frame count, median and p99
    /// are then those of the frames after the lead-in (the report's cover the whole session).
    double lead_in_s = 0.0;
    std::string out = "out/bench";                     ///< output folder: desk/ per session, desk_bench.json
};

/// One session's figures, all from its report.json.
struct DeskBenchRow {
    std::string stereo, display;
    int resolution = 0;      ///< the workpiece's N (report.json workpiece.resolution)
    int repeat = 1;          ///< which run (1..DeskBenchOptions::repeats); 0: the median over the runs
    double min_scale = 1.0;  ///< the session's --min-render-scale
    double max_lod_px = 1.0;  ///< the session's --max-lod-px
    std::uint64_t frames = 0;
    double frame_median_ms = 0, frame_p99_ms = 0;  ///< one frame's wall time: pick, draw, present
    double interval_median_ms = 0;                 ///< between the starts of successive frames
    double lag_median_ms = 0, lag_p99_ms = 0;      ///< cursor event to the frame that draws the tool there
    double lag_frames = 0;                         ///< lag_median_ms over the frame interval (or time)
    /// The frame's wait for the loop to take the cursor's target (report.json mouse.hand_wait_ms), median and p99
    double hand_wait_median_ms = 0, hand_wait_p99_ms = 0;
    std::uint64_t targets = 0, same_frame = 0;  ///< cursor targets; those drawn by the frame whose input set them
    /// Cursor targets whose lag was timed (report.json mouse.latency_ms count): those the tool reached before the next
    /// target came; the lag's median and p99 rest on these alone.
    std::uint64_t lag_timed = 0;
    nlohmann::json passes = nlohmann::json::object();  ///< pass name (".left" / ".right") -> median GPU ms
    nlohmann::json present;                        ///< the window's present timings (null offscreen)
    nlohmann::json frame_budget;                   ///< report.json render.frame_budget (occlusion, levels, scale)
    double triangles_per_frame = 0;                ///< workpiece triangles drawn per frame, left eye (render.lod)
    /// frame_median_ms over the same output and scale's row at the first resolution (NaN for the first, or when
    /// either is not measured).
    double frame_ratio = 0;
    /// Median <= 25 ms, p99 <= 40 ms and lag <= 2 frames: met, over, or not measured (no frame or cursor target timed).
    Verdict verdict = Verdict::kNotMeasured;
    bool target_met = false;  ///< verdict is kMet
};

/// Runs the sessions, prints a table beside the targets and writes OUT/desk_bench.json (every run's row; with
/// repeats > 1 also a median row per output and scale, `repeat` 0: each figure the median over the runs, the
/// verdict from those medians). Returns the rows as written. Throws tridex::Error naming the option for a value out
/// of range, an unknown output or display, or an unwritable folder.
std::vector<DeskBenchRow> run_desk_bench(const DeskBenchOptions& options);

}  // namespace tridex::bench
