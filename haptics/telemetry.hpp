// haptics/telemetry.hpp - fixed-bin histograms of the haptic loop's period and compute time.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace tridex::haptics {

/// A histogram of durations (s) with kBins equal bins [i*w, (i+1)*w), w = bin_width_s, plus an
/// overflow count for values >= kBins*w. A plain value: copy it freely (LoopStats holds copies).
struct Histogram {
    static constexpr std::size_t kBins = 200;  ///< number of regular bins

    double bin_width_s = 0.0;                   ///< width w of each bin, s (> 0 once set up)
    std::array<std::uint32_t, kBins> counts{};  ///< samples per bin
    std::uint32_t overflow = 0;                 ///< samples >= kBins * w
    double max_s = 0.0;                         ///< largest sample seen, s (0 when empty)

    /// Number of samples (regular bins plus overflow).
    std::uint64_t total() const;
    /// Upper edge (s) of the bin holding the q-quantile (q in [0, 1], clamped), or max_s when that is
    /// smaller: a bound the q-quantile does not exceed, exact to one bin width, and never above the largest
    /// sample. Returns max_s when that sample lies in the overflow, 0 when the histogram is empty.
    double quantile(double q) const;
};

/// The loop-side histogram: one writer thread adds samples with add() (allocation-free, lock-free,
/// no read-modify-write atomics: relaxed load + store, valid because there is a single writer), any
/// thread may take a snapshot() at any time (each count is read atomically; the set is not one instant).
class AtomicHistogram {
public:
    /// bin_width_s: width of each bin, s. A non-positive or non-finite width makes add() count
    /// everything as overflow (no exception: the loop validates its configuration before).
    explicit AtomicHistogram(double bin_width_s = 1e-5);

    /// Adds one duration x_s (s). Negative or NaN values count in bin 0 (a clock going backwards
    /// must not crash the loop); +inf counts as overflow.
    void add(double x_s);
    /// Zeroes every count (call while no thread is adding).
    void clear();
    /// A copy of the counts.
    Histogram snapshot() const;
    /// The bin width, s.
    double bin_width_s() const { return width_; }

private:
    double width_;
    std::array<std::atomic<std::uint32_t>, Histogram::kBins> counts_{};
    std::atomic<std::uint32_t> overflow_{0};
    std::atomic<double> max_{0.0};
};

}  // namespace tridex::haptics
