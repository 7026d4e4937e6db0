// app/session/view/frame_budget.hpp - a live session's picture on a frame-time budget: occlusion, levels, render scale.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "renderer/stereo/ambient_occlusion.hpp"

namespace tridex {

/// One step of FrameBudget's ladder: how finely the ambient occlusion is evaluated, the largest error of the levels
/// of detail drawn (renderer::SceneView::lod_max_px) and the render scale (the eye images' size as a share of the
/// window's, per axis; the present blit scales them up with a linear filter).
struct FrameQuality {
    renderer::OcclusionResolution occlusion = renderer::OcclusionResolution::kHalf;
    double lod_px = 1.0;  ///< pixels of the eye image
    double scale = 1.0;
};

/// What FrameBudget may trade and how fast it reacts.
struct FrameBudgetOptions {
    /// The frame-time target, ms (finite, >= 0; 0 = no budget: always the finest step).
    double target_ms = 25.0;
    /// The lowest render scale, 0.5..1 (1 = never scale; offscreen and fullscreen sessions pass 1).
    double min_scale = 1.0;
    /// The coarsest levels of detail, as their largest error on screen, pixels, 1..8 (1 = never coarser than the
    /// finest step's 1 pixel; sessions without levels, offscreen and fullscreen sessions pass 1).
    double coarse_lod_px = 1.0;
    /// Frames per decision to go up a step, 5..1000: a window's median must fit within 90 % of the target.
    int window = 30;
    /// Frames per decision to go down a step, 1..window: the median of the newest `react` frames over the target.
    int react = 10;
};

/// Chooses, frame by frame, how much a live session draws so that frames keep to a frame-time target. The choices
/// form a ladder from the finest to the cheapest: the occlusion per 2x2 pixels at full scale, per 4x4 pixels (about
/// a quarter of the obscurance dispatch's work), the levels of detail at up to coarse_lod_px pixels of error instead
/// of 1 (fewer triangles to transform and set up per eye), then the render scale lowered in steps of kScaleStep down
/// to min_scale (each step about a fifth fewer pixels to rasterise, shade and occlude; the dynamic resolution of
/// game engines and VR runtimes). Overload is met fast and relief trusted slowly: whenever `react` frames have been
/// drawn at a step and the median of the newest `react` is over the target, the budget steps down: one step below
/// 1.25^2 times the target, k steps from 1.25^k times (each step saves about a fifth of the work); once a
/// whole window at a step is within 90 % of the target it tries the step above. A trial that goes over the target
/// (within its first `react` frames or over its window) returns at once and doubles the windows to wait before the
/// next trial (up to 32); one that holds for a window resets the wait. Steps that differ only in the occlusion are
/// skipped while the occlusion is off. Frames drawn while the workpiece is being sculpted cost more (the sculpt
/// thread and the level-of-detail worker share the cores with the renderer), so they have a step of their own,
/// learnt from their own frames as above (set_sculpting): a stroke starts at the step the strokes before needed,
/// not at the one the calm frames between them allow (the way CAD viewers degrade while the view moves).
/// Single-threaded (the render thread).
class FrameBudget {
public:
    /// The render scale's step between two rungs of the ladder.
    static constexpr double kScaleStep = 0.125;

    /// Throws tridex::Error naming --frame-target-ms, --min-render-scale or --max-lod-px on a bad value, or on a
    /// bad window or react.
    explicit FrameBudget(const FrameBudgetOptions& options);

    /// Adds one frame's wall time, ms (the frame was drawn at quality()); `occlusion_on`: whether the frame drew
    /// the ambient occlusion. Non-finite or negative times are ignored. May change quality() for the next frame.
    void add(double frame_ms, bool occlusion_on = true);
    /// Whether the frames from now on are drawn while the workpiece is being sculpted: quality() and add() then
    /// use the sculpting frames' own step (the first time: the calm step it starts from), else the calm one.
    void set_sculpting(bool on);
    /// True after set_sculpting(true).
    bool sculpting() const { return active_ == kSculpting; }
    /// What the next frame should draw.
    FrameQuality quality() const { return ladder_[states_[active_].level]; }
    /// The calm frames' step and the sculpting frames' step (the calm one before any sculpting frame).
    FrameQuality calm_quality() const { return ladder_[states_[kCalm].level]; }
    FrameQuality sculpting_quality() const;
    /// Frames drawn while sculpting.
    std::uint64_t frames_sculpting() const { return frames_sculpting_; }
    /// The ladder, finest first (at least two steps).
    const std::vector<FrameQuality>& ladder() const { return ladder_; }
    /// Frames drawn at each step of ladder() so far.
    const std::vector<std::uint64_t>& frames() const { return frames_; }
    /// Frames drawn with the occlusion at 2x2 and at 4x4, with coarser levels than 1 pixel, with the render scale
    /// below 1, and the number of changes.
    std::uint64_t frames_half() const;
    std::uint64_t frames_quarter() const;
    std::uint64_t frames_coarse_lod() const;
    std::uint64_t frames_scaled() const;
    std::uint64_t switches() const { return switches_; }
    /// report.json's render.frame_budget: {target_ms, window, react, min_scale, coarse_lod_px, frames_half,
    /// frames_quarter, frames_coarse_lod, frames_scaled, frames_sculpting, switches, ladder: [{occlusion, lod_px,
    /// scale, frames}], now: {occlusion, lod_px, scale} (quality()), now_calm and now_sculpting: the same for
    /// the calm and the sculpting frames}.
    nlohmann::json to_json() const;

private:
    /// The step below / above `level` that changes what is drawn (not the occlusion alone while it is off);
    /// `level` itself when there is none.
    std::size_t below(std::size_t level, bool occlusion_on) const;
    std::size_t above(std::size_t level, bool occlusion_on) const;
    /// Frames drawn at the steps for which `drawn` is true.
    std::uint64_t frames_where(bool (*drawn)(const FrameQuality&)) const;

    /// One kind of frame's choice on the ladder and what it is learnt from.
    struct State {
        std::size_t level = 0;
        std::vector<double> recent;  // this choice's frames, up to a window
        bool probing = false;        // this window is a trial of the step above the one before
        int backoff = 1;             // windows to wait before the next trial
        int windows_at_level = 0;    // since the last change
        bool used = false;           // a frame was drawn in this state
    };
    static constexpr int kCalm = 0;
    static constexpr int kSculpting = 1;

    /// Ends the active state's current choice: `next` for the frames to come.
    void change_to(std::size_t next);

    FrameBudgetOptions options_;
    std::size_t window_;
    std::size_t react_;
    std::vector<FrameQuality> ladder_;
    State states_[2];
    int active_ = kCalm;
    std::vector<double> scratch_;  // the median's copy
    std::vector<std::uint64_t> frames_;
    std::uint64_t frames_sculpting_ = 0;
    std::uint64_t switches_ = 0;
};

}  // namespace tridex
