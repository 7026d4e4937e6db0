// bench/soak/bench_soak_minute.hpp - the soak's per-minute reading: the process's figures from /proc and the minute's share
// of the session's cumulative histograms.
#pragma once

#include <chrono>
#include <functional>
#include <string>

#include "app/session/run/run_options.hpp"
#include "bench/soak/bench_soak.hpp"
#include "core/duration_histogram.hpp"
#include "haptics/telemetry.hpp"

namespace tridex::bench {

/// Resident memory of this process (/proc/self/statm), bytes; 0 when unreadable.
double resident_bytes();
/// Bytes the C heap has in use (mallinfo2 uordblks + hblkhd).
double heap_bytes();
/// Entries of /proc/self/<dir> ("fd": open descriptors, "task": threads); -1 when unreadable.
int proc_entries(const char* dir);

/// Watches a run through RunOptions::frame_probe and makes a SoakMinute each time a minute of wall time since the
/// first frame has passed. Every frame costs one histogram add and a clock read; the minute's reading (copies of the
/// loop's and the sculpt thread's histograms, /proc, the journal's size) happens on the frame that ends it.
/// The heap a minute reports is the least read over its last this many seconds (every kSoakHeapEveryS): three of the
/// scripted sculptor's 5 s cycles, each of which ends with its stroke undone, so a stroke's meshes and buffers in
/// flight at the minute's end do not count as growth, and a leak still raises the least.
inline constexpr double kSoakHeapWindowS = 15.0, kSoakHeapEveryS = 0.5;

class SoakMonitor {
public:
    /// `journal`: the journal file whose size is read; `on_minute` gets each minute's row (on the frame thread).
    SoakMonitor(std::string journal, std::function<void(const SoakMinute&)> on_minute);
    /// The probe: call after every frame.
    void frame(const app::RunFrameProbe& p);

private:
    using Clock = std::chrono::steady_clock;
    void end_minute(const app::RunFrameProbe& p);

    std::string journal_;
    std::function<void(const SoakMinute&)> on_minute_;
    bool started_ = false;
    Clock::time_point t0_{};
    int minute_ = 0;
    DurationHistogram frame_ms_;                // this minute's frames
    haptics::Histogram period_before_{};        // the loop's period histogram at the minute's start
    std::size_t ticks_before_ = 0, over_2ms_before_ = 0;
    DurationHistogram step_before_ = DurationHistogram::fine();  // the sculpt thread's step times at the start
    std::uint64_t steps_before_ = 0;
    double heap_least_ = -1.0;                  // the least heap bytes read in this minute's window; < 0: none yet
    Clock::time_point heap_read_at_{};          // when it was last read
};

}  // namespace tridex::bench
