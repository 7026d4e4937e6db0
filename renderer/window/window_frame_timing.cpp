// renderer/window/window_frame_timing.cpp - the fixed-bin frame-time histogram.
#include "renderer/window/window_frame_timing.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace tridex::renderer {

FrameTimeHistogram::FrameTimeHistogram(double bin_width_ms, std::size_t bins, std::size_t coarse_bins,
                                       double coarse_factor)
    : width_(bin_width_ms), fine_(bins), coarse_width_(coarse_factor * bin_width_ms) {
    if (!std::isfinite(bin_width_ms) || bin_width_ms <= 0.0)
        throw Error("FrameTimeHistogram: bin_width_ms must be a finite number > 0");
    if (bins == 0) throw Error("FrameTimeHistogram: bins must be >= 1");
    if (!std::isfinite(coarse_factor) || coarse_factor < 1.0)
        throw Error("FrameTimeHistogram: coarse_factor must be a finite number >= 1");
    bins_.assign(bins + coarse_bins, 0);
}

double FrameTimeHistogram::bin_lower_ms(std::size_t k) const {
    if (k < fine_) return static_cast<double>(k) * width_;
    return static_cast<double>(fine_) * width_ + static_cast<double>(k - fine_) * coarse_width_;
}

void FrameTimeHistogram::add(double ms) {
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

void FrameTimeHistogram::clear() {
    std::fill(bins_.begin(), bins_.end(), 0);
    count_ = overflow_ = rejected_ = 0;
    sum_ = min_ = max_ = 0.0;
}

double FrameTimeHistogram::min_ms() const { return count_ ? min_ : 0.0; }
double FrameTimeHistogram::max_ms() const { return count_ ? max_ : 0.0; }
double FrameTimeHistogram::mean_ms() const { return count_ ? sum_ / static_cast<double>(count_) : 0.0; }

double FrameTimeHistogram::percentile_ms(double p) const {
    if (!(p >= 0.0 && p <= 1.0)) throw Error("FrameTimeHistogram::percentile_ms: p must be in [0, 1]");
    if (count_ == 0) return 0.0;
    const auto rank = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(p * static_cast<double>(count_))));
    std::uint64_t seen = 0;
    for (std::size_t k = 0; k < bins_.size(); ++k) {
        seen += bins_[k];
        if (seen >= rank) return bin_lower_ms(k + 1);  // the bin's upper edge
    }
    return max_;
}

nlohmann::json FrameTimeHistogram::to_json() const {
    nlohmann::json bins = nlohmann::json::array();
    for (std::size_t k = 0; k < bins_.size(); ++k)
        if (bins_[k]) bins.push_back({bin_lower_ms(k), bins_[k]});
    return {{"bin_width_ms", width_}, {"count", count_},          {"overflow", overflow_},
            {"rejected", rejected_},  {"min_ms", min_ms()},       {"max_ms", max_ms()},
            {"mean_ms", mean_ms()},   {"p50_ms", percentile_ms(0.5)}, {"p95_ms", percentile_ms(0.95)},
            {"p99_ms", percentile_ms(0.99)}, {"bins", bins}};
}

nlohmann::json FrameTimings::to_json() const {
    return {{"render_gpu_ms", render_gpu_ms.to_json()},
            {"blit_gpu_ms", blit_gpu_ms.to_json()},
            {"interval_ms", interval_ms.to_json()}};
}

}  // namespace tridex::renderer
