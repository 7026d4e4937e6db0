// bench/soak/bench_soak.hpp - `tridex bench --soak MINUTES`: a scripted sculptor works through the full `run` session (haptic
// loop, sculpt thread, renderer; offscreen) for MINUTES minutes, and every minute the process's memory, files and threads,
// the journal's and the undo history's bytes and the minute's frame, haptic and sculpt times are read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bench/bench_verdict.hpp"

namespace tridex::bench {

/// The bound on resident memory growth after the first minute, MB per minute (MB = 1e6 bytes), for a sculptor whose
/// strokes are undone (SoakOptions::keep false: the model, its meshes and its undo images stay the same size). The
/// session's memory is then allocated up front or bounded (histograms of fixed bins, the undo history's budget, the
/// tile meshes of one model); what may still grow is counted per event (the sculpt thread's per-undo timings and
/// stroke marks, tens of bytes each) plus the allocator's and the Vulkan driver's pages settling. 3 MB/min is
/// 180 MB over a lab's three-hour afternoon, about twice the growth measured in such runs, and a leaked tile mesh
/// per sculpt step or the undo images of every stroke exceed it.
inline constexpr double kSoakGrowthBoundMbPerMin = 3.0;

/// One minute of a soak run: process figures at its end, and the times of what ran during it.
struct SoakMinute {
    int minute = 0;                     ///< 1, 2, ... (the minute that ended)
    double t_s = 0.0;                   ///< wall time since the session's first frame, s
    double rss_mb = 0.0;                ///< resident memory (/proc/self/statm), MB (1e6 bytes)
    /// The C heap's bytes in use (mallinfo2: arena chunks in use plus mmapped chunks), MB, the least read over the
    /// minute's last kSoakHeapWindowS (bench_soak_minute.hpp): RSS growth that this does not follow is not malloc's
    /// (a driver's mappings, fragmentation returned to the system late).
    double heap_mb = 0.0;
    std::size_t triangles = 0;          ///< triangles of the workpiece's mesh drawn last (the model's surface)
    double journal_mb = 0.0;            ///< the journal file's size, MB
    double history_mb = 0.0;            ///< the undo history's bytes held (SculptLive::history_bytes), MB
    double history_budget_mb = 0.0;     ///< its budget, MB
    std::uint64_t frames = 0;           ///< frames drawn in the minute
    double frame_p50_ms = 0.0, frame_p99_ms = 0.0;       ///< the minute's frame time, draw + readback, ms
    std::uint64_t ticks = 0;                             ///< haptic ticks in the minute
    double period_p99_us = 0.0, period_worst_us = 0.0;   ///< the minute's haptic period: p99 and longest, us
    std::uint64_t periods_over_2ms = 0;                  ///< haptic periods over 2 ms in the minute
    std::uint64_t steps = 0;                             ///< sculpt steps that changed the model in the minute
    double step_p99_ms = 0.0;                            ///< the minute's sculpt step (Booleans, publish, contour), ms
    int fds = 0;                        ///< open file descriptors (/proc/self/fd)
    int threads = 0;                    ///< threads of the process (/proc/self/task)
};

/// What a soak run found, with its verdict.
struct SoakResult {
    std::vector<SoakMinute> minutes;    ///< one per minute, in order
    /// Resident memory growth after the first minute, MB/min: the least-squares slope of rss_mb over minutes 1..end
    /// (minute 1 is the warm-up: the model, meshes, levels of detail and driver pools being made). 0 with fewer than
    /// two minutes.
    double growth_mb_per_min = 0.0;
    std::size_t growth_minutes = 0;     ///< minutes the slope was fitted to (0 or 1: not measured)
    /// The same slope of rss_mb - history_mb, MB/min: what grows besides the undo history, which is bounded by its
    /// budget but fills at the sculptor's pace (not judged; for telling the two apart).
    double growth_less_history_mb_per_min = 0.0;
    Verdict verdict = Verdict::kNotMeasured;  ///< growth against kSoakGrowthBoundMbPerMin
    int fds_first = 0, fds_last = 0;    ///< open descriptors at minute 1 and at the end
    int threads_first = 0, threads_last = 0;  ///< threads at minute 1 and at the end
    double journal_mb = 0.0;            ///< the journal at the end, MB
    double journal_mb_per_hour = 0.0;   ///< its growth after minute 1, extrapolated to an hour, MB/h
    double recover_s = -1.0;            ///< `tridex recover` of the journal at the end, wall time, s (-1: not run)
    std::string recovered_from;         ///< what recovery started from (its report's "recovered_from", if any)
    std::string journal;                ///< the journal's path
    std::string ended;                  ///< how the session ended (its first note)
};

/// What to run.
struct SoakOptions {
    double minutes = 10.0;              ///< the session's length, min (> 0)
    std::string out = "out/bench";      ///< folder: soak/ (the session's outputs), soak.jsonl, soak.json, soak.svg
    int resolution = 128;               ///< workpiece lattice cells along its longest side
    bool recover = true;                ///< time `tridex recover` on the journal at the end
    bool keep = false;                  ///< keep half the strokes (write_soak_scene), the model growing; else undo all
    bool print = true;                  ///< print the table while it runs
};

/// Writes the soak's scene into `dir` (created beforehand) and returns its path: the default scene's bunny at
/// `resolution`, the mouse as the stylus driven by a scripted cursor for `seconds` (s) of device time, a scripted head
/// that moves back and forth, and keys: every operation in turn (subtract, union, paint, push, smooth, pull), the
/// tool larger and smaller, undo and redo of strokes, and Ctrl+S. `keep` false: every stroke is undone before the
/// next, so the model is the same at every cycle's end and what grows is the process's, not the model's; true: half
/// the strokes are kept, and the model's surface (its meshes, levels of detail, undo images) grows as a sculptor's
/// does. Throws tridex::Error when it cannot be written.
std::string write_soak_scene(const std::string& dir, double seconds, int resolution, bool keep);

/// The growth slope, its verdict and the first / last process figures of `r.minutes` (fills those fields of r).
void judge_soak(SoakResult& r);

/// Runs the soak: one `tridex run` session offscreen (mono, paced at 60 Hz) on write_soak_scene's scene for
/// options.minutes, with its journal and checkpoints on; prints a row per minute (when options.print), appends each
/// row to <out>/soak.jsonl as it ends, then judges the growth (judge_soak), times run_recover on the journal, writes
/// <out>/soak.json (the summary and the rows) and <out>/soak.svg (memory and frame time per minute). Throws
/// tridex::Error for bad options, an unwritable folder or a failed session.
SoakResult run_soak_bench(const SoakOptions& options);

/// Writes an SVG plot of the rows to `path`: resident memory (MB) and the frame time's median and p99 (ms) against
/// the minute, two panels. Throws tridex::Error when the file cannot be written.
void write_soak_plot(const std::vector<SoakMinute>& rows, const std::string& path);

}  // namespace tridex::bench
