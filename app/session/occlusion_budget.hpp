// app/session/occlusion_budget.hpp - ambient occlusion on a frame-time budget: half resolution while frames fit.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "renderer/stereo/ambient_occlusion.hpp"

namespace tridex {

/// Chooses, frame by frame, how finely a live session evaluates its ambient occlusion
/// (renderer::OcclusionResolution) so that frames keep to a frame-time target: per 2x2 pixels while they fit, per
/// 4x4 pixels (about a quarter of the obscurance dispatch's work) when the median of a window of frames is over
/// the target. Once a window at 4x4 is within 90 % of the target it tries 2x2 again for a window; a trial that goes
/// over the target doubles the windows to wait at 4x4 before the next one (up to 32), one that fits resets it. Every
/// choice holds for a whole window of frames measured with it, so the picture does not flicker between the two.
/// Single-threaded (the render thread).
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
    bool probing_ = false;          // this window at 2x2 is a trial after windows at 4x4
    int backoff_ = 1;               // windows at 4x4 before the next trial of 2x2
    int windows_at_quarter_ = 0;    // since the last change to 4x4
    std::uint64_t frames_[2] = {0, 0};
    std::uint64_t switches_ = 0;
};

}  // namespace tridex
