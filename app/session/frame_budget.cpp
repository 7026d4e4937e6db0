// app/session/frame_budget.cpp - the frame-time budget's ladder: occlusion resolution, then render scale.
#include "app/session/frame_budget.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace tridex {
namespace {

using renderer::OcclusionResolution;

// Frames must fit within this share of the target before the budget tries the step above.
constexpr double kReturnShare = 0.9;
// The longest wait, in windows, between two trials that failed.
constexpr int kMaxBackoff = 32;

double median_of(std::vector<double> v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

const char* occlusion_name(OcclusionResolution r) { return r == OcclusionResolution::kQuarter ? "quarter" : "half"; }

}  // namespace

FrameBudget::FrameBudget(double target_ms, double min_scale, int window)
    : target_ms_(target_ms), min_scale_(min_scale) {
    if (!std::isfinite(target_ms) || target_ms < 0.0)
        throw Error("--frame-target-ms: must be a finite number of ms >= 0 (0 = no budget), got " +
                    std::to_string(target_ms));
    if (!(min_scale >= 0.5 && min_scale <= 1.0))
        throw Error("--min-render-scale: must lie in 0.5..1 (1 = never scale), got " + std::to_string(min_scale));
    if (window < 5 || window > 1000)
        throw Error("FrameBudget: window must lie in 5..1000 frames, got " + std::to_string(window));
    window_ = static_cast<std::size_t>(window);
    recent_.reserve(window_);
    ladder_.push_back({OcclusionResolution::kHalf, 1.0});
    ladder_.push_back({OcclusionResolution::kQuarter, 1.0});
    for (int k = 1; 1.0 - k * kScaleStep > min_scale + 1e-9; ++k)
        ladder_.push_back({OcclusionResolution::kQuarter, 1.0 - k * kScaleStep});
    if (min_scale < 1.0) ladder_.push_back({OcclusionResolution::kQuarter, min_scale});
    frames_.assign(ladder_.size(), 0);
}

std::size_t FrameBudget::below(std::size_t level, bool occlusion_on) const {
    for (std::size_t l = level + 1; l < ladder_.size(); ++l)
        if (occlusion_on || ladder_[l].scale != ladder_[level].scale) return l;
    return level;
}

std::size_t FrameBudget::above(std::size_t level, bool occlusion_on) const {
    for (std::size_t l = level; l-- > 0;)
        if (occlusion_on || ladder_[l].scale != ladder_[level].scale) {
            // Without the occlusion, the finest step of that scale (the occlusion's choice does not matter then).
            while (!occlusion_on && l > 0 && ladder_[l - 1].scale == ladder_[l].scale) --l;
            return l;
        }
    return level;
}

void FrameBudget::add(double frame_ms, bool occlusion_on) {
    if (!std::isfinite(frame_ms) || frame_ms < 0.0) return;
    ++frames_[level_];
    if (target_ms_ <= 0.0) return;
    recent_.push_back(frame_ms);
    if (recent_.size() < window_) return;
    const double median = median_of(recent_);
    recent_.clear();
    ++windows_at_level_;
    const bool over = median > target_ms_;
    if (probing_) backoff_ = over ? std::min(backoff_ * 2, kMaxBackoff) : 1;  // the trial failed / held
    probing_ = false;
    std::size_t next = level_;
    if (over) {
        next = below(level_, occlusion_on);
    } else if (median < kReturnShare * target_ms_ && windows_at_level_ >= backoff_) {
        next = above(level_, occlusion_on);
        probing_ = next != level_;
    }
    if (next == level_) return;
    level_ = next;
    windows_at_level_ = 0;
    ++switches_;
}

std::uint64_t FrameBudget::frames_where(bool (*drawn)(const FrameQuality&)) const {
    std::uint64_t n = 0;
    for (std::size_t l = 0; l < ladder_.size(); ++l)
        if (drawn(ladder_[l])) n += frames_[l];
    return n;
}

std::uint64_t FrameBudget::frames_half() const {
    return frames_where([](const FrameQuality& q) { return q.occlusion == OcclusionResolution::kHalf; });
}

std::uint64_t FrameBudget::frames_quarter() const {
    return frames_where([](const FrameQuality& q) { return q.occlusion == OcclusionResolution::kQuarter; });
}

std::uint64_t FrameBudget::frames_scaled() const {
    return frames_where([](const FrameQuality& q) { return q.scale < 1.0; });
}

nlohmann::json FrameBudget::to_json() const {
    nlohmann::json steps = nlohmann::json::array();
    for (std::size_t l = 0; l < ladder_.size(); ++l)
        steps.push_back(
            {{"occlusion", occlusion_name(ladder_[l].occlusion)}, {"scale", ladder_[l].scale}, {"frames", frames_[l]}});
    return nlohmann::json{{"target_ms", target_ms_},
                          {"window", window_},
                          {"min_scale", min_scale_},
                          {"frames_half", frames_half()},
                          {"frames_quarter", frames_quarter()},
                          {"frames_scaled", frames_scaled()},
                          {"switches", switches_},
                          {"ladder", steps},
                          {"now", {{"occlusion", occlusion_name(quality().occlusion)}, {"scale", quality().scale}}}};
}

}  // namespace tridex
