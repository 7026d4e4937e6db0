// app/session/run/run_sculpt.hpp - the sculpting side of a `tridex run` session: the scene's scripted hand on a simulated
// device, and the session's threads (SessionRuntime) running while the render thread draws.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "app/scene/run_scene.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "devices/mouse_device.hpp"

namespace tridex::app {

/// The device -> world gain of a "fit" workspace (RunScene::workspace_fit): 1 when the world box `reach_m` (m)
/// fits 90 % of the profile's workspace on every axis, else the smallest gain that makes it fit (the largest
/// ratio of the box's extent to 90 % of the workspace's over the axes). An empty box gives 1. Throws
/// tridex::Error "workspace.scale: ..." for a profile without a workspace.
double fit_workspace_scale(const Aabb& reach_m, const devices::DeviceProfile& profile);

/// Whether the device driver's hand is the simulated hand (scripted input: the simulated device, and the emulated
/// Falcon whose grip it holds), which plays a scene's scripted path (a stroke, a study's scripted participant).
inline bool scripted_hand_driver(const std::string& driver) {
    return driver_caps(driver).input == devices::InputKind::kScripted;
}

/// The sculpting side of a run: the scene's workpiece scan-converted and contoured, a simulated device (the
/// scene's profile) whose virtual hand follows the scripted stroke (plan_stroke; or holds still in front of the
/// workpiece when the scene has none), and the SessionRuntime of the scene's spec on it, handing the contoured
/// surface to the renderer (throttled to mesh_interval_s). With the scene's device driver "mouse" there is no
/// scripted hand: a MouseDevice (mouse()) rests at the device's home in front of the workpiece until the app
/// sets its hand. The render thread reads runtime().latest_view() and
/// latest_mesh(): newest values, never waiting for either thread, and neither thread ever waits for it.
class SculptBackend {
public:
    /// Prepares everything (loads, scan-converts and contours the workpiece, plans the stroke, checks the loop
    /// configuration) without starting threads. Throws tridex::Error for a bad mesh, an impossible resolution,
    /// a stroke with no material under it or a bad spec. `form`, `booleans` and `render_context`: as
    /// RuntimeOptions (the dirty tiles are contoured on the GPU into the render context's buffers where that is
    /// the default or asked for).
    /// `tool_dtrack`: for the flystick and tracked-body drivers, the DTrack receiver to share (the head's or the
    /// wand's on the same port); null = the driver opens its own on scene.tracked_port.
    explicit SculptBackend(const RunScene& scene, double mesh_interval_s = 1.0 / 60.0,
                           MeshForm form = MeshForm::kTiles, const SculptOptions& booleans = {},
                           gpu::Context* render_context = nullptr,
                           std::shared_ptr<devices::DTrackReceiver> tool_dtrack = nullptr);

    /// The session's threads (start, stop, latest_view, latest_mesh, records, final_mesh, ...).
    SessionRuntime& runtime() { return *runtime_; }
    const SessionRuntime& runtime() const { return *runtime_; }
    /// True once the haptic loop has played the whole stroke (device time; never for a scene without stroke)
    /// or has ended by itself (device lost).
    bool stroke_done() const;
    /// Where the tool is drawn before the loop's first tick, and the device workspace box there (world m).
    Vec3 start_tool_m() const { return start_m_; }
    Aabb start_box_m() const;
    std::size_t stroke_ticks() const { return stroke_ticks_; }  ///< ticks the stroke lasts; 0 without stroke
    /// Steady-clock time (s) at which the workpiece was ready: scan-converted or loaded, before any contour.
    double loaded_s() const { return loaded_s_; }
    /// The mouse device (driver "mouse"), or nullptr; owned by runtime().
    devices::MouseDevice* mouse() const { return mouse_; }

private:
    Vec3 start_m_{0.0};
    std::size_t stroke_ticks_ = 0;
    double loaded_s_ = -1.0;
    devices::MouseDevice* mouse_ = nullptr;
    std::unique_ptr<SessionRuntime> runtime_;
};

}  // namespace tridex::app
