// core/duration_histogram.hpp - a fixed-bin histogram of durations: bounded memory however many samples.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tridex {

/// A histogram of durations in milliseconds (frame times, latencies, waits): `bins` fine bins of `bin_width_ms`
/// from 0, then `coarse_bins` bins `coarse_factor` times as wide (slow frames, such as a CPU Vulkan
/// implementation's, still get percentiles), plus an overflow count for samples beyond both. All storage is
/// allocated at construction: add() never allocates, so it may run on a render thread every frame, and a session of
/// any length keeps the same memory. Not thread-safe (one writer; read it between frames or from the same thread).
class DurationHistogram {
public:
    /// Bins [k * w, (k + 1) * w) ms for k = 0 .. bins - 1, then [F + j * c, F + (j + 1) * c) for j = 0 ..
    /// coarse_bins - 1 (F = bins * w, c = coarse_factor * w). Throws tridex::Error when bin_width_ms is not a
    /// finite number > 0, bins == 0, or coarse_factor is not a finite number >= 1. Default: 0.25 ms bins up to
    /// 100 ms, then 5 ms bins up to 2.1 s.
    explicit DurationHistogram(double bin_width_ms = 0.25, std::size_t bins = 400, std::size_t coarse_bins = 400,
                               double coarse_factor = 20.0);
    /// For latencies that may reach a few hundred ms (input to photon, tool sample to surface drawn): 0.25 ms bins
    /// up to 400 ms, then 5 ms bins up to 2.4 s.
    static DurationHistogram latency() { return DurationHistogram(0.25, 1600, 400, 20.0); }
    /// For short per-frame or per-step times (render passes, sculpt steps, waits): 0.01 ms bins up to 40 ms, then
    /// 0.25 ms bins up to 240 ms.
    static DurationHistogram fine() { return DurationHistogram(0.01, 4000, 800, 25.0); }

    /// Records one duration, ms. Negative or non-finite values are not binned; they are counted in rejected().
    void add(double ms);
    /// Forgets every sample (bins keep their storage).
    void clear();

    std::uint64_t count() const { return count_; }        ///< samples binned (including overflow)
    std::uint64_t overflow() const { return overflow_; }  ///< samples beyond the histogram's range (fine and coarse)
    std::uint64_t rejected() const { return rejected_; }  ///< negative or non-finite samples refused
    double bin_width_ms() const { return width_; }        ///< width of one fine bin, ms
    /// Counts per bin: the fine bins, then the coarse ones.
    const std::vector<std::uint64_t>& bins() const { return bins_; }
    /// The lower edge of bin k (an index into bins()), ms.
    double bin_lower_ms(std::size_t k) const;
    double min_ms() const;                  ///< smallest sample, ms (0 when empty)
    double max_ms() const;                  ///< largest sample, ms (0 when empty)
    double mean_ms() const;                 ///< arithmetic mean of the samples, ms (0 when empty)
    double sum_ms() const { return sum_; }  ///< sum of the samples, ms
    /// The upper edge (ms) of the bin holding the sample of rank ceil(p * count) (p in [0, 1]; p = 0 gives the
    /// first sample's bin), or max_ms() when that is smaller: an upper bound on the p-quantile, exact to one bin's
    /// width. Overflowed samples report max_ms(). Returns 0 when empty; throws tridex::Error when p is outside
    /// [0, 1].
    double percentile_ms(double p) const;

private:
    double width_;
    std::size_t fine_;     // fine bins: the first fine_ entries of bins_
    double coarse_width_;  // width of a coarse bin, ms
    std::vector<std::uint64_t> bins_;
    std::uint64_t count_ = 0, overflow_ = 0, rejected_ = 0;
    double sum_ = 0, min_ = 0, max_ = 0;
};

}  // namespace tridex
