// core/duration_histogram.cpp - the fixed-bin duration histogram.
#include "core/duration_histogram.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace tridex {

DurationHistogram::DurationHistogram(double bin_width_ms, std::size_t bins, std::size_t coarse_bins,
                                     double coarse_factor)
    : width_(bin_width_ms), fine_(bins), coarse_width_(coarse_factor * bin_width_ms) {
    if (!std::isfinite(bin_width_ms) || bin_width_ms <= 0.0)
        throw Error("DurationHistogram: bin_width_ms must be a finite number > 0");
    if (bins == 0) throw Error("DurationHistogram: bins must be >= 1");
    if (!std::isfinite(coarse_factor) || coarse_factor < 1.0)
        throw Error("DurationHistogram: coarse_factor must be a finite number >= 1");
    bins_.assign(bins + coarse_bins, 0);
}

double DurationHistogram::bin_lower_ms(std::size_t k) const {
    if (k < fine_) return static_cast<double>(k) * width_;
    return static_cast<double>(fine_) * width_ + static_cast<double>(k - fine_) * coarse_width_;
}

void DurationHistogram::add(double ms) {
    if (!std::isfinite(ms) || ms < 0.0) {
        ++rejected_;
        return;
    }
    const double k = std::floor(ms / width_);
    if (k < static_cast<double>(fine_)) {
        ++bins_[static_cast<std::size_t>(k)];
    } else {
        const double j = std::floor((ms - static_cast<double>(fine_) * width_) / coarse_width_);
        if (j < static_cast<double>(bins_.size() - fine_))
            ++bins_[fine_ + static_cast<std::size_t>(std::max(j, 0.0))];
        else
            ++overflow_;
    }
    min_ = count_ == 0 ? ms : std::min(min_, ms);
    max_ = count_ == 0 ? ms : std::max(max_, ms);
    sum_ += ms;
    ++count_;
}

void DurationHistogram::clear() {
    std::fill(bins_.begin(), bins_.end(), 0);
    count_ = overflow_ = rejected_ = 0;
    sum_ = min_ = max_ = 0.0;
}

double DurationHistogram::min_ms() const { return count_ ? min_ : 0.0; }
double DurationHistogram::max_ms() const { return count_ ? max_ : 0.0; }
double DurationHistogram::mean_ms() const { return count_ ? sum_ / static_cast<double>(count_) : 0.0; }

double DurationHistogram::percentile_ms(double p) const {
    if (!(p >= 0.0 && p <= 1.0)) throw Error("DurationHistogram::percentile_ms: p must be in [0, 1]");
    if (count_ == 0) return 0.0;
    const auto rank =
        std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(p * static_cast<double>(count_))));
    std::uint64_t seen = 0;
    for (std::size_t k = 0; k < bins_.size(); ++k) {
        seen += bins_[k];
        if (seen >= rank) return std::min(bin_lower_ms(k + 1), max_);  // the bin's upper edge
    }
    return max_;
}

}  // namespace tridex
