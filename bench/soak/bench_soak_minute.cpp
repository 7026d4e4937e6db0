// bench/soak/bench_soak_minute.cpp - one minute of a soak run read from /proc and from the differences of the session's
// cumulative histograms.
#include "bench/soak/bench_soak_minute.hpp"

#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <utility>
#include <vector>

#include "app/session/runtime/session_runtime.hpp"

namespace tridex::bench {

namespace {

namespace fs = std::filesystem;

constexpr double kMb = 1e6;

// The p-quantile (upper bin edge, ms) of the samples `now` holds and `before` did not (both with the same bins);
// samples beyond the bins read now's largest. 0 when there are none.
double quantile_between(const DurationHistogram& now, const DurationHistogram& before, double p) {
    const std::uint64_t n = now.count() - before.count();
    if (n == 0) return 0.0;
    const auto rank = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(p * static_cast<double>(n))));
    std::uint64_t seen = 0;
    for (std::size_t k = 0; k < now.bins().size(); ++k) {
        seen += now.bins()[k] - before.bins()[k];
        if (seen >= rank) return std::min(now.bin_lower_ms(k + 1), now.max_ms());
    }
    return now.max_ms();
}

// The haptic loop's period histogram of the minute: now's counts less before's.
haptics::Histogram minus(const haptics::Histogram& now, const haptics::Histogram& before) {
    haptics::Histogram d = now;
    for (std::size_t i = 0; i < d.counts.size(); ++i) d.counts[i] -= before.counts[i];
    d.overflow -= before.overflow;
    return d;
}

// The longest period of the minute, s: the largest sample when it came in this minute, else the upper edge of the
// highest bin the minute filled (beyond the bins and not the largest: their lower edge, a lower bound).
double worst_of(const haptics::Histogram& minute, const haptics::Histogram& before, const haptics::Histogram& now) {
    if (now.max_s > before.max_s) return now.max_s;
    if (minute.overflow > 0) return static_cast<double>(haptics::Histogram::kBins) * minute.bin_width_s;
    for (std::size_t i = minute.counts.size(); i-- > 0;)
        if (minute.counts[i] > 0) return std::min(static_cast<double>(i + 1) * minute.bin_width_s, now.max_s);
    return 0.0;
}

}  // namespace

double resident_bytes() {
    std::ifstream in("/proc/self/statm");
    double size = 0.0, resident = 0.0;
    if (!(in >> size >> resident)) return 0.0;
    return resident * static_cast<double>(sysconf(_SC_PAGESIZE));
}

double heap_bytes() {
    const struct mallinfo2 mi = mallinfo2();
    return static_cast<double>(mi.uordblks) + static_cast<double>(mi.hblkhd);
}

int proc_entries(const char* dir) {
    std::error_code ec;
    int n = 0;
    for (fs::directory_iterator it(fs::path("/proc/self") / dir, ec), end; !ec && it != end; it.increment(ec)) ++n;
    return ec ? -1 : n;
}

SoakMonitor::SoakMonitor(std::string journal, std::function<void(const SoakMinute&)> on_minute)
    : journal_(std::move(journal)), on_minute_(std::move(on_minute)) {}

void SoakMonitor::frame(const app::RunFrameProbe& p) {
    const Clock::time_point now = Clock::now();
    if (!started_) {  // the minutes count from the first frame; its own time is the warm-up's
        started_ = true;
        t0_ = now;
        const haptics::LoopStats loop = p.runtime->loop_stats();
        period_before_ = loop.period_histogram;
        ticks_before_ = loop.ticks;
        over_2ms_before_ = loop.periods_over_2ms;
        const app::SculptLive s = p.runtime->sculpt_live();
        step_before_ = s.step_ms;
        steps_before_ = s.steps;
        return;
    }
    frame_ms_.add(p.frame_ms);
    const double into_s = std::chrono::duration<double>(now - t0_).count();
    if (into_s >= 60.0 * (minute_ + 1) - kSoakHeapWindowS &&
        std::chrono::duration<double>(now - heap_read_at_).count() >= kSoakHeapEveryS) {
        const double heap = heap_bytes();  // mallinfo2 walks the arenas: a few reads a second, not one a frame
        if (heap_least_ < 0.0 || heap < heap_least_) heap_least_ = heap;
        heap_read_at_ = now;
    }
    if (into_s >= 60.0 * (minute_ + 1)) end_minute(p);
}

void SoakMonitor::end_minute(const app::RunFrameProbe& p) {
    SoakMinute m;
    m.minute = ++minute_;
    m.t_s = std::chrono::duration<double>(Clock::now() - t0_).count();
    m.frames = frame_ms_.count();
    m.frame_p50_ms = frame_ms_.percentile_ms(0.5);
    m.frame_p99_ms = frame_ms_.percentile_ms(0.99);
    frame_ms_.clear();
    const haptics::LoopStats loop = p.runtime->loop_stats();
    haptics::Histogram period = minus(loop.period_histogram, period_before_);
    m.ticks = loop.ticks - ticks_before_;
    m.period_worst_us = 1e6 * worst_of(period, period_before_, loop.period_histogram);
    // The minute's own longest period (or its lower bound), not an earlier minute's: a quantile that falls beyond the
    // bins is then that bound too, never above the worst.
    period.max_s = 1e-6 * m.period_worst_us;
    m.period_p99_us = 1e6 * period.quantile(0.99);
    m.periods_over_2ms = loop.periods_over_2ms - over_2ms_before_;
    period_before_ = loop.period_histogram;
    ticks_before_ = loop.ticks;
    over_2ms_before_ = loop.periods_over_2ms;
    const app::SculptLive s = p.runtime->sculpt_live();
    m.steps = s.steps - steps_before_;
    m.step_p99_ms = quantile_between(s.step_ms, step_before_, 0.99);
    m.history_mb = static_cast<double>(s.history_bytes) / kMb;
    m.history_budget_mb = static_cast<double>(s.history_budget_bytes) / kMb;
    step_before_ = s.step_ms;
    steps_before_ = s.steps;
    std::error_code ec;
    const std::uintmax_t journal_bytes = journal_.empty() ? 0 : fs::file_size(journal_, ec);
    m.journal_mb = ec ? 0.0 : static_cast<double>(journal_bytes) / kMb;
    m.rss_mb = resident_bytes() / kMb;
    const double heap_now = heap_bytes();
    m.heap_mb = (heap_least_ >= 0.0 ? std::min(heap_least_, heap_now) : heap_now) / kMb;
    heap_least_ = -1.0;
    m.triangles = p.triangles;
    m.fds = proc_entries("fd");
    m.threads = proc_entries("task");
    if (on_minute_) on_minute_(m);
}

}  // namespace tridex::bench
