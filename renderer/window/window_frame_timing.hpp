// renderer/window/window_frame_timing.hpp - frame-time histograms with preallocated bins.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

namespace tridex::renderer {

/// A histogram of durations in milliseconds with `bins` equal bins of `bin_width_ms` starting at 0, plus
/// an overflow count for samples >= bins * bin_width_ms. All storage is allocated at construction: add()
/// never allocates, so it may run on a render thread every frame. Not thread-safe (one writer; read it
/// between frames or from the same thread).
class FrameTimeHistogram {
public:
    /// Bins [k * w, (k + 1) * w) ms for k = 0 .. bins - 1. Throws tridex::Error when bin_width_ms is not a
    /// finite number > 0 or bins == 0. Default: 0.25 ms bins up to 100 ms.
    explicit FrameTimeHistogram(double bin_width_ms = 0.25, std::size_t bins = 400);

    /// Records one duration, ms. Negative or non-finite values are not binned; they are counted in rejected().
    void add(double ms);
    /// Forgets every sample (bins keep their storage).
    void clear();

    std::uint64_t count() const { return count_; }        ///< samples binned (including overflow)
    std::uint64_t overflow() const { return overflow_; }  ///< samples >= the histogram's range
    std::uint64_t rejected() const { return rejected_; }  ///< negative or non-finite samples refused
    double bin_width_ms() const { return width_; }        ///< width of one bin, ms
    const std::vector<std::uint64_t>& bins() const { return bins_; }  ///< counts per bin
    double min_ms() const;   ///< smallest sample, ms (0 when empty)
    double max_ms() const;   ///< largest sample, ms (0 when empty)
    double mean_ms() const;  ///< arithmetic mean of the samples, ms (0 when empty)
    /// The upper edge (ms) of the bin holding the sample of rank ceil(p * count) (p in [0, 1]; p = 0 gives the
    /// first sample's bin): an upper bound on the p-quantile, exact to one bin width. Overflowed samples report
    /// max_ms(). Returns 0 when empty; throws tridex::Error when p is outside [0, 1].
    double percentile_ms(double p) const;

    /// {"bin_width_ms", "count", "overflow", "rejected", "min_ms", "max_ms", "mean_ms", "p50_ms", "p95_ms",
    /// "p99_ms", "bins": [[lower_edge_ms, count], ...] for the non-empty bins only}.
    nlohmann::json to_json() const;

private:
    double width_;
    std::vector<std::uint64_t> bins_;
    std::uint64_t count_ = 0, overflow_ = 0, rejected_ = 0;
    double sum_ = 0, min_ = 0, max_ = 0;
};

/// The timings a presenting window collects, one sample per presented frame (each in its own histogram).
struct FrameTimings {
    FrameTimeHistogram render_gpu_ms;  ///< GPU time of the stereo render (OffscreenStereoRenderer::last_gpu_ms)
    FrameTimeHistogram blit_gpu_ms;    ///< GPU time of the present pass (blits/upload into the swapchain image)
    FrameTimeHistogram interval_ms;    ///< CPU time between successive presents (the display period under vsync)

    /// {"render_gpu_ms": ..., "blit_gpu_ms": ..., "interval_ms": ...} (FrameTimeHistogram::to_json each).
    nlohmann::json to_json() const;
};

}  // namespace tridex::renderer
