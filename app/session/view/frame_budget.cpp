// app/session/view/frame_budget.cpp - the frame-time budget's ladder: occlusion resolution, levels of detail, render scale.
#include "app/session/view/frame_budget.hpp"

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
// A step down saves about a fifth of a frame's work (a render scale step: about a fifth fewer pixels), so a frame
// this many times over the target is met with one more step at once.
constexpr double kStepGain = 1.25;

// Steps down for frames `median` ms long against `target` ms (median > target): floor(log(median / target) /
// log(kStepGain)), at least one, so that a heavy overload is not drawn for `react` frames per step.
int steps_for(double median, double target) {
    return std::max(1, static_cast<int>(std::floor(std::log(median / target) / std::log(kStepGain))));
}

double median_of(std::vector<double>& v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

const char* occlusion_name(OcclusionResolution r) { return r == OcclusionResolution::kQuarter ? "quarter" : "half"; }

// Whether two steps draw the same picture when the occlusion is off.
bool same_without_occlusion(const FrameQuality& a, const FrameQuality& b) {
    return a.scale == b.scale && a.lod_px == b.lod_px;
}

}  // namespace

FrameBudget::FrameBudget(const FrameBudgetOptions& o) : options_(o) {
    if (!std::isfinite(o.target_ms) || o.target_ms < 0.0)
        throw Error("--frame-target-ms: must be a finite number of ms >= 0 (0 = no budget), got " +
                    std::to_string(o.target_ms));
    if (!(o.min_scale >= 0.5 && o.min_scale <= 1.0))
        throw Error("--min-render-scale: must lie in 0.5..1 (1 = never scale), got " + std::to_string(o.min_scale));
    if (!(o.coarse_lod_px >= 1.0 && o.coarse_lod_px <= 8.0))
        throw Error("--max-lod-px: must lie in 1..8 pixels (1 = never coarser), got " +
                    std::to_string(o.coarse_lod_px));
    if (o.window < 5 || o.window > 1000)
        throw Error("FrameBudget: window must lie in 5..1000 frames, got " + std::to_string(o.window));
    if (o.react < 1 || o.react > o.window)
        throw Error("FrameBudget: react must lie in 1..window frames, got " + std::to_string(o.react));
    window_ = static_cast<std::size_t>(o.window);
    react_ = static_cast<std::size_t>(o.react);
    for (State& st : states_) st.recent.reserve(window_);
    scratch_.reserve(window_);
    const double px = o.coarse_lod_px;
    ladder_.push_back({OcclusionResolution::kHalf, 1.0, 1.0});
    ladder_.push_back({OcclusionResolution::kQuarter, 1.0, 1.0});
    if (px > 1.0) ladder_.push_back({OcclusionResolution::kQuarter, px, 1.0});
    for (int k = 1; 1.0 - k * kScaleStep > o.min_scale + 1e-9; ++k)
        ladder_.push_back({OcclusionResolution::kQuarter, px, 1.0 - k * kScaleStep});
    if (o.min_scale < 1.0) ladder_.push_back({OcclusionResolution::kQuarter, px, o.min_scale});
    frames_.assign(ladder_.size(), 0);
}

std::size_t FrameBudget::below(std::size_t level, bool occlusion_on) const {
    for (std::size_t l = level + 1; l < ladder_.size(); ++l)
        if (occlusion_on || !same_without_occlusion(ladder_[l], ladder_[level])) return l;
    return level;
}

std::size_t FrameBudget::above(std::size_t level, bool occlusion_on) const {
    for (std::size_t l = level; l-- > 0;)
        if (occlusion_on || !same_without_occlusion(ladder_[l], ladder_[level])) {
            // Without the occlusion, the finest step that draws the same (the occlusion's choice does not matter then).
            while (!occlusion_on && l > 0 && same_without_occlusion(ladder_[l - 1], ladder_[l])) --l;
            return l;
        }
    return level;
}

void FrameBudget::change_to(std::size_t next) {
    State& st = states_[active_];
    st.level = next;
    st.windows_at_level = 0;
    st.recent.clear();
    ++switches_;
}

void FrameBudget::set_sculpting(bool on) {
    const int next = on ? kSculpting : kCalm;
    if (next == active_) return;
    State& st = states_[next];
    if (!st.used) st.level = states_[active_].level;  // nothing learnt yet: start where the frames are
    active_ = next;
}

FrameQuality FrameBudget::sculpting_quality() const {
    return ladder_[states_[kSculpting].used ? states_[kSculpting].level : states_[kCalm].level];
}

void FrameBudget::add(double frame_ms, bool occlusion_on) {
    if (!std::isfinite(frame_ms) || frame_ms < 0.0) return;
    State& st = states_[active_];
    st.used = true;
    ++frames_[st.level];
    if (active_ == kSculpting) ++frames_sculpting_;
    if (options_.target_ms <= 0.0) return;
    st.recent.push_back(frame_ms);
    const double target = options_.target_ms;
    if (st.recent.size() % react_ == 0) {  // overload is met after `react` frames, a trial's too
        scratch_.assign(st.recent.end() - static_cast<std::ptrdiff_t>(react_), st.recent.end());
        const double median = median_of(scratch_);
        if (median > target) {
            if (st.probing) st.backoff = std::min(st.backoff * 2, kMaxBackoff);
            st.probing = false;
            std::size_t next = st.level;
            for (int k = steps_for(median, target); k > 0; --k) next = below(next, occlusion_on);
            if (next != st.level) return change_to(next);
        }
    }
    if (st.recent.size() < window_) return;
    scratch_.assign(st.recent.begin(), st.recent.end());
    const double median = median_of(scratch_);
    st.recent.clear();
    ++st.windows_at_level;
    const bool over = median > target;
    if (st.probing) st.backoff = over ? std::min(st.backoff * 2, kMaxBackoff) : 1;  // the trial failed / held
    st.probing = false;
    std::size_t next = st.level;
    if (over) {
        next = below(st.level, occlusion_on);
    } else if (median < kReturnShare * target && st.windows_at_level >= st.backoff) {
        next = above(st.level, occlusion_on);
        st.probing = next != st.level;
    }
    if (next != st.level) change_to(next);
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

std::uint64_t FrameBudget::frames_coarse_lod() const {
    return frames_where([](const FrameQuality& q) { return q.lod_px > 1.0; });
}

std::uint64_t FrameBudget::frames_scaled() const {
    return frames_where([](const FrameQuality& q) { return q.scale < 1.0; });
}

nlohmann::json FrameBudget::to_json() const {
    nlohmann::json steps = nlohmann::json::array();
    for (std::size_t l = 0; l < ladder_.size(); ++l)
        steps.push_back({{"occlusion", occlusion_name(ladder_[l].occlusion)},
                         {"lod_px", ladder_[l].lod_px},
                         {"scale", ladder_[l].scale},
                         {"frames", frames_[l]}});
    const auto step = [](const FrameQuality& q) {
        return nlohmann::json{{"occlusion", occlusion_name(q.occlusion)}, {"lod_px", q.lod_px}, {"scale", q.scale}};
    };
    return nlohmann::json{{"target_ms", options_.target_ms},
                          {"window", window_},
                          {"react", react_},
                          {"min_scale", options_.min_scale},
                          {"coarse_lod_px", options_.coarse_lod_px},
                          {"frames_half", frames_half()},
                          {"frames_quarter", frames_quarter()},
                          {"frames_coarse_lod", frames_coarse_lod()},
                          {"frames_scaled", frames_scaled()},
                          {"frames_sculpting", frames_sculpting_},
                          {"switches", switches_},
                          {"ladder", steps},
                          {"now", step(quality())},
                          {"now_calm", step(calm_quality())},
                          {"now_sculpting", step(sculpting_quality())}};
}

}  // namespace tridex
