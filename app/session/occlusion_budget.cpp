// app/session/occlusion_budget.cpp - the frame-time budget's choice of ambient-occlusion resolution.
#include "app/session/occlusion_budget.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace tridex {
namespace {

// Frames at 4x4 must fit within this share of the target before the budget tries 2x2 again.
constexpr double kReturnShare = 0.9;
// The longest wait, in windows at 4x4, between two trials of 2x2 that failed.
constexpr int kMaxBackoff = 32;

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
    if (!quarter) {
        const bool over = median > target_ms_;
        if (probing_) backoff_ = over ? std::min(backoff_ * 2, kMaxBackoff) : 1;  // the trial at 2x2 failed / held
        probing_ = false;
        if (over) {
            resolution_ = renderer::OcclusionResolution::kQuarter;
            windows_at_quarter_ = 0;
            ++switches_;
        }
        return;
    }
    ++windows_at_quarter_;
    // Frames well within the target at 4x4 for long enough: try 2x2 again for one window.
    if (median < kReturnShare * target_ms_ && windows_at_quarter_ >= backoff_) {
        resolution_ = renderer::OcclusionResolution::kHalf;
        probing_ = true;
        ++switches_;
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
