// app/input/wand_navigation.hpp - the paper's Wand: grab-and-move, joystick scaling and reset of the scene from a
// tracked wand (a DTrack Flystick) with buttons.
#pragma once

#include <cstdint>

#include "core/pose.hpp"
#include "renderer/camera/scene_navigation.hpp"

namespace tridex::app {

/// One frame's wand as the navigation sees it.
struct WandSample {
    bool fresh = false;         ///< a tracked, recent pose this frame; false: lost or stale (navigation stops)
    Pose pose;                  ///< wand pose in wall (world) coordinates, m
    std::uint64_t buttons = 0;  ///< bit i set: button i held
    double joystick_y = 0.0;    ///< joystick's y in [-1, 1] (push forward > 0)
};

/// How the wand's buttons and joystick navigate.
struct WandNavigationSettings {
    int grab_button = 0;                   ///< held: the scene follows the wand rigidly (the Flystick's trigger); -1 none
    int reset_button = 1;                  ///< pressed: back to the start pose and scale; -1 none
    bool joystick_scales = true;           ///< the joystick's y scales the scene (false: it drives something else)
    double scale_rate_per_s = 0.6931471805599453;  ///< ln(scale factor per s) at full joystick (ln 2: doubles in 1 s)
    double dead_zone = 0.1;                ///< |joystick_y| below this does nothing
    double max_dt_s = 0.1;                 ///< a frame's time step is clamped to [0, max_dt_s] s (no scale jumps)
    Vec3 pivot_m{0.0};                     ///< the point joystick scaling keeps fixed, world m
};

/// The Wand of Peng et al., "Haptic Interface Technique in Large-Scale Virtual Environment" (navigation of the
/// scene in front of the PowerWall): while the grab button is held, the scene is carried by the wand -
/// world_from_scene <- (wand_now * wand_at_press^-1) * world_from_scene_at_press, applied frame by frame with
/// SceneNavigation::wand_drag; the joystick's y scales the scene about the pivot at an exponential rate,
/// exp(scale_rate_per_s * y * dt), clamped by SceneNavigation's scale limits; the reset button's press restores
/// the start. A sample that is not fresh (lost, untracked, stale, non-finite) ends the grab and moves nothing: the
/// scene never jumps; a grab resumes from the wand's pose when it is tracked again with the button held.
/// One thread; not thread-safe.
class WandNavigator {
public:
    /// Throws tridex::Error for button indices outside -1..63 or equal (but -1), a negative or non-finite rate, a dead zone
    /// outside [0, 1), a non-finite or negative max_dt_s, or a non-finite pivot.
    explicit WandNavigator(const WandNavigationSettings& settings = {});
    /// Applies one frame's sample to `nav`; dt_s: time since the previous frame, s (clamped to [0, max_dt_s];
    /// non-finite counts as 0). Never throws.
    void update(const WandSample& sample, double dt_s, renderer::SceneNavigation& nav);

    bool grabbing() const { return grabbing_; }                       ///< the scene is held right now
    std::uint64_t grabs() const { return grabs_; }                    ///< grabs started (trigger presses while tracked)
    std::uint64_t resets() const { return resets_; }                  ///< reset presses applied
    std::uint64_t frames_tracked() const { return frames_tracked_; }  ///< update() calls with a fresh sample
    std::uint64_t frames_lost() const { return frames_lost_; }        ///< update() calls without one
    std::uint64_t grabs_dropped() const { return grabs_dropped_; }    ///< grabs ended by a lost or stale wand
    double scaled_by() const { return scaled_by_; }                   ///< product of the joystick's applied factors

private:
    WandNavigationSettings settings_;
    bool grabbing_ = false;
    Pose anchor_;                    // the wand pose the last drag step started from (world m)
    std::uint64_t prev_buttons_ = 0;  // buttons of the last fresh sample
    std::uint64_t grabs_ = 0, resets_ = 0, frames_tracked_ = 0, frames_lost_ = 0, grabs_dropped_ = 0;
    double scaled_by_ = 1.0;
};

}  // namespace tridex::app
