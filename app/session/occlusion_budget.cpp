// app/session/occlusion_budget.cpp - the frame-time budget's choice of ambient-occlusion resolution.
#include "app/session/occlusion_budget.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace tridex {
namespace {

// Predicted frames at 2x2 must fit within this share of the target before the budget goes back to 2x2.
constexpr double kReturnShare = 0.9;

double median_of(std::vector<double> v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

}  // namespace

OcclusionBudget::OcclusionBudget(double target_ms, int window) : target_ms_(target_ms) {
    if (!std::isfinite(target_ms) || target_ms < 0.0)
        throw Error("--frame-target-ms: must be a finite number of ms >= 0 (0 = no budget), got " +
                    std::to_string(target_ms));
    if (window < 5 || window > 1000)
        throw Error("OcclusionBudget: window must lie in 5..1000 frames, got " + std::to_string(window));
    window_ = static_cast<std::size_t>(window);
    recent_.reserve(window_);
}

void OcclusionBudget::add(double frame_ms) {
    if (!std::isfinite(frame_ms) || frame_ms < 0.0) return;
    const bool quarter = resolution_ == renderer::OcclusionResolution::kQuarter;
    ++frames_[quarter ? 1 : 0];
    if (target_ms_ <= 0.0) return;
    recent_.push_back(frame_ms);
    if (recent_.size() < window_) return;
    const double median = median_of(recent_);
    recent_.clear();
    if (!quarter && median > target_ms_) {
        half_median_ms_ = median;
        extra_ms_ = -1.0;
        resolution_ = renderer::OcclusionResolution::kQuarter;
        ++switches_;
    } else if (quarter) {
        // What 2x2 costs more: the first window at 4x4 against the last one at 2x2, side by side in time (never
        // less than nothing: a busier moment may have hidden it).
        if (extra_ms_ < 0.0) extra_ms_ = std::max(half_median_ms_ - median, 0.0);
        if (median + extra_ms_ < kReturnShare * target_ms_) {
            resolution_ = renderer::OcclusionResolution::kHalf;
            ++switches_;
        }
    }
}

nlohmann::json OcclusionBudget::to_json() const {
    return nlohmann::json{{"target_ms", target_ms_},
                          {"window", window_},
                          {"frames_half", frames_[0]},
                          {"frames_quarter", frames_[1]},
                          {"switches", switches_},
                          {"now", resolution_ == renderer::OcclusionResolution::kQuarter ? "quarter" : "half"}};
}

}  // namespace tridex
