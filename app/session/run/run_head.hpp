// app/session/run/run_head.hpp - the head-pose provider of a run: fixed, keyboard and mouse, scripted, a tracker or DTrack.
#pragma once

#include <memory>

#include "app/input/dtrack_head.hpp"
#include "app/scene/run_scene.hpp"
#include "renderer/camera/head_pose.hpp"

namespace tridex::app {

/// The head provider of the scene `s` (s.head): DTrack (a DTrackHead on the scene's port and body, tracker space
/// mapped to the wall by the display config, the scene's head pose as the fallback while untracked), scripted
/// (the scene's head waypoints), a tracker fed by the caller, or fixed at the scene's head pose; a fixed head in an
/// `interactive` session (a window) becomes a keyboard-and-mouse head with the same home pose. `km`, `tracker` and
/// `dtrack` (non-null) are set to the provider when it is of that kind, else to nullptr; they stay valid as long as
/// the returned provider. Throws tridex::Error when the DTrack port cannot be opened.
std::unique_ptr<renderer::HeadPoseProvider> make_run_head(const RunScene& s, bool interactive,
                                                         renderer::KeyboardMouseHead** km,
                                                         renderer::TrackerHead** tracker, DTrackHead** dtrack);

}  // namespace tridex::app
