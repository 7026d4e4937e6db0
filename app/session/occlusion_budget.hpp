// app/session/occlusion_budget.hpp - ambient occlusion on a frame-time budget: half resolution while frames fit.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "renderer/stereo/ambient_occlusion.hpp"

namespace tridex {

/// Chooses, frame by frame, how finely a live session evaluates its ambient occlusion
/// (renderer::OcclusionResolution) so that frames keep to a frame-time target: per 2x2 pixels while they fit, per
/// 4x4 pixels (about a quarter of the obscurance dispatch's work) when the median of the last `window` frames is
/// over the target; back to 2x2 once the frames measured at 4x4, plus what 2x2 cost more (the last window at 2x2
/// against the first at 4x4), would fit within 90 % of the target. Every choice holds for a whole window of frames measured with it, so the
/// picture does not flicker between the two. Single-threaded (the render thread).
class OcclusionBudget {
public:
    /// target_ms: the frame-time target, ms (finite, >= 0; 0 = no budget: always 2x2). window: frames per
    /// decision, 5..1000. Throws tridex::Error naming --frame-target-ms on a bad target, or on a bad window.
    explicit OcclusionBudget(double target_ms, int window = 30);

    /// Adds one frame's wall time, ms (the frame was drawn at resolution()); non-finite or negative values are
    /// ignored. May change resolution() for the next frame.
    void add(double frame_ms);
    /// The resolution the next frame should use.
    renderer::OcclusionResolution resolution() const { return resolution_; }
    /// Frames drawn at 2x2 and at 4x4 so far, and the number of changes.
    std::uint64_t frames_half() const { return frames_[0]; }
    std::uint64_t frames_quarter() const { return frames_[1]; }
    std::uint64_t switches() const { return switches_; }
    /// report.json's render.occlusion_budget: {target_ms, window, frames_half, frames_quarter, switches, now}.
    nlohmann::json to_json() const;

private:
    double target_ms_;
    std::size_t window_;
    renderer::OcclusionResolution resolution_ = renderer::OcclusionResolution::kHalf;
    std::vector<double> recent_;    // this choice's frames, up to a window
    double half_median_ms_ = -1.0;  // the median frame at 2x2 when it was last given up (-1: never)
    double extra_ms_ = -1.0;        // what 2x2 cost more than 4x4 then, ms (-1: not measured yet)
    std::uint64_t frames_[2] = {0, 0};
    std::uint64_t switches_ = 0;
};

}  // namespace tridex
