// app/session/frame_budget.hpp - a live session's picture on a frame-time budget: occlusion resolution, render scale.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "renderer/stereo/ambient_occlusion.hpp"

namespace tridex {

/// One step of FrameBudget's ladder: how finely the ambient occlusion is evaluated and the render scale (the eye
/// images' size as a share of the window's, per axis; the present blit scales them up with a linear filter).
struct FrameQuality {
    renderer::OcclusionResolution occlusion = renderer::OcclusionResolution::kHalf;
    double scale = 1.0;
};

/// Chooses, frame by frame, how much a live session draws so that frames keep to a frame-time target. The choices
/// form a ladder from the finest to the cheapest: the occlusion per 2x2 pixels at full scale, per 4x4 pixels (about
/// a quarter of the obscurance dispatch's work) at full scale, then the render scale lowered in steps of
/// kScaleStep down to min_scale (each step about a fifth fewer pixels to rasterise, shade and occlude; the
/// dynamic resolution of game engines and VR runtimes). When the median of a window of frames is over the target
/// the budget takes one step down; once a window is within 90 % of the target it tries the step above for a
/// window; a trial that goes over the target doubles the windows to wait before the next one (up to 32), one that
/// fits resets it. Every choice holds for a whole window of frames measured with it, so the picture does not
/// flicker. Steps that differ only in the occlusion are skipped while the occlusion is off. Single-threaded (the
/// render thread).
class FrameBudget {
public:
    /// The render scale's step between two rungs of the ladder.
    static constexpr double kScaleStep = 0.125;

    /// target_ms: the frame-time target, ms (finite, >= 0; 0 = no budget: always the finest step). min_scale: the
    /// lowest render scale, 0.5..1 (1 = never scale: only the occlusion is budgeted; offscreen and fullscreen
    /// sessions pass 1). window: frames per decision, 5..1000. Throws tridex::Error naming --frame-target-ms or
    /// --min-render-scale on a bad value, or on a bad window.
    explicit FrameBudget(double target_ms, double min_scale = 1.0, int window = 30);

    /// Adds one frame's wall time, ms (the frame was drawn at quality()); `occlusion_on`: whether the frame drew
    /// the ambient occlusion. Non-finite or negative times are ignored. May change quality() for the next frame.
    void add(double frame_ms, bool occlusion_on = true);
    /// What the next frame should draw.
    FrameQuality quality() const { return ladder_[level_]; }
    /// The ladder, finest first (at least two steps).
    const std::vector<FrameQuality>& ladder() const { return ladder_; }
    /// Frames drawn at each step of ladder() so far.
    const std::vector<std::uint64_t>& frames() const { return frames_; }
    /// Frames drawn with the occlusion at 2x2 and at 4x4, with the render scale below 1, and the number of changes.
    std::uint64_t frames_half() const;
    std::uint64_t frames_quarter() const;
    std::uint64_t frames_scaled() const;
    std::uint64_t switches() const { return switches_; }
    /// report.json's render.frame_budget: {target_ms, window, min_scale, frames_half, frames_quarter,
    /// frames_scaled, switches, ladder: [{occlusion, scale, frames}], now: {occlusion, scale}}.
    nlohmann::json to_json() const;

private:
    /// The step below / above `level` that changes what is drawn (the scale alone while the occlusion is off);
    /// `level` itself when there is none.
    std::size_t below(std::size_t level, bool occlusion_on) const;
    std::size_t above(std::size_t level, bool occlusion_on) const;
    /// Frames drawn at the steps for which `drawn` is true.
    std::uint64_t frames_where(bool (*drawn)(const FrameQuality&)) const;

    double target_ms_;
    double min_scale_;
    std::size_t window_;
    std::vector<FrameQuality> ladder_;
    std::size_t level_ = 0;
    std::vector<double> recent_;  // this choice's frames, up to a window
    bool probing_ = false;        // this window is a trial of the step above the one before
    int backoff_ = 1;             // windows to wait before the next trial
    int windows_at_level_ = 0;    // since the last change
    std::vector<std::uint64_t> frames_;
    std::uint64_t switches_ = 0;
};

}  // namespace tridex
