// haptics/telemetry.cpp - histogram bookkeeping and quantiles.
#include "haptics/telemetry.hpp"

#include <algorithm>
#include <cmath>

namespace tridex::haptics {

std::uint64_t Histogram::total() const {
    std::uint64_t n = overflow;
    for (std::uint32_t c : counts) n += c;
    return n;
}

double Histogram::quantile(double q) const {
    const std::uint64_t n = total();
    if (n == 0) return 0.0;
    q = std::clamp(std::isfinite(q) ? q : 0.0, 0.0, 1.0);
    // Rank of the q-quantile among the sorted samples, 1-based: ceil(q * n), at least 1.
    const auto rank = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(n))));
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < kBins; ++i) {
        seen += counts[i];
        // No sample exceeds max_s, so neither does the quantile: a bin's edge above it would report a quantile
        // larger than the largest sample.
        if (seen >= rank) return std::min(static_cast<double>(i + 1) * bin_width_s, std::max(max_s, 0.0));
    }
    return max_s;
}

AtomicHistogram::AtomicHistogram(double bin_width_s) : width_(bin_width_s) {}

void AtomicHistogram::add(double x_s) {
    std::size_t bin = 0;
    bool over = false;
    if (!(std::isfinite(width_) && width_ > 0.0)) {
        over = true;
    } else if (x_s > 0.0) {  // NaN and negative values stay in bin 0
        const double b = std::floor(x_s / width_);
        if (b >= static_cast<double>(Histogram::kBins)) over = true;  // also +inf
        else bin = static_cast<std::size_t>(b);
    }
    if (over) overflow_.store(overflow_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    else counts_[bin].store(counts_[bin].load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    if (x_s > max_.load(std::memory_order_relaxed)) max_.store(x_s, std::memory_order_relaxed);
}

void AtomicHistogram::clear() {
    for (auto& c : counts_) c.store(0, std::memory_order_relaxed);
    overflow_.store(0, std::memory_order_relaxed);
    max_.store(0.0, std::memory_order_relaxed);
}

Histogram AtomicHistogram::snapshot() const {
    Histogram h;
    h.bin_width_s = width_;
    for (std::size_t i = 0; i < Histogram::kBins; ++i) h.counts[i] = counts_[i].load(std::memory_order_relaxed);
    h.overflow = overflow_.load(std::memory_order_relaxed);
    h.max_s = max_.load(std::memory_order_relaxed);
    return h;
}

}  // namespace tridex::haptics
