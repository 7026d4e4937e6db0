// app/session/view/run_view.hpp - what the render thread draws each frame: the scene from the haptic loop's newest view and
// the newest mesh, and the camera through the navigated scene.
#pragma once

#include <cstdint>
#include <string>
#include <deque>
#include <utility>

#include "core/aabb.hpp"
#include "core/pose.hpp"
#include "core/tri_mesh.hpp"
#include "haptics/haptic_loop.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/camera/scene_navigation.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

/// The axis-aligned box (world m) that holds a box of half extents `half_m` (m, >= 0) posed by `box`
/// (centre m, orientation): the 8 corners box.apply(+/-half) bounded. An all-zero half extent gives the point box.
Aabb enclosing_box(const Pose& box, const Vec3& half_m);

/// The SceneView of one frame: `mesh` as the workpiece (nullptr = none), the ball tool of `tool_radius_m` at the
/// view's tool position, the workspace box (enclosing_box of the view's box; drawn only while the workspace button
/// is held, view.modelling_paused, as Peng et al. 4.1 show it) and the bubble (when its radius > 0).
/// Before the loop's first tick (view.tick == 0) the tool sits at `fallback_tool_m` and the box is
/// `fallback_box_m`. All positions world m.
renderer::SceneView scene_view_from(const haptics::LoopView& view, const TriMesh* mesh, double tool_radius_m,
                                    const Vec3& fallback_tool_m, const Aabb& fallback_box_m);

/// What the overlay of a run frame says.
struct RunOverlay {
    double haptic_rate_hz = -1.0;  ///< haptic ticks per second over the last second; < 0 = unknown
    double sculpt_rate_hz = -1.0;  ///< sculpt steps per second over the last second; < 0 = unknown
    double frame_time_ms = -1.0;   ///< the previous frame's wall time, ms; < 0 = the renderer's own
    std::string status{};          ///< further overlay lines (what was saved, what is not being saved)
    bool tile_counts = false;      ///< also the tiles drawn and skipped per eye (--overlay-stats)
};

/// Adds the run's scene items to `s`: the proxy (view.proxy_m, a translucent sphere of `proxy_radius_m`, m,
/// the tool's radius: the god-object of the ball tool's centre), the force arrow (view.force_n, N, drawn at
/// `force_m_per_newton` m per N from the tool centre) and the overlay with `o`'s numbers. Before the loop's
/// first tick (view.tick == 0) there is no proxy and no force. Nothing is checked here (the renderer checks
/// finiteness when it draws).
void add_run_items(renderer::SceneView& s, const haptics::LoopView& view, double proxy_radius_m,
                   double force_m_per_newton, const RunOverlay& o);

/// Events per second over a sliding window: fed (time, running count) samples, e.g. (LoopView.t_s,
/// LoopView.tick) for the haptic rate or (wall time, SculptStats steps) for the sculpt rate.
class RateMeter {
public:
    /// window_s: span the rate is measured over, s (> 0; else 1 s is used).
    explicit RateMeter(double window_s = 1.0) : window_s_(window_s > 0.0 ? window_s : 1.0) {}
    /// Adds a sample at t_s (s) with running count `count`. A time before the newest sample's, or a count
    /// below its count (a restart), clears the history first; a sample at the newest time replaces it.
    void add(double t_s, std::uint64_t count);
    /// (newest count - oldest count) / (newest t - oldest t) over the samples of the last window_s (plus the
    /// one just before it), per s; -1 with fewer than two samples or a zero time span.
    double rate_hz() const;

private:
    double window_s_;
    std::deque<std::pair<double, std::uint64_t>> samples_;
};

/// The arguments of OffscreenStereoRenderer::render() for one frame.
struct RunCamera {
    renderer::Screen screen;        ///< screen corners, m (scene frame)
    Pose head;                      ///< head pose, m (scene frame)
    double eye_separation_m = 0.0;  ///< m (scene frame)
    double near_m = 0.05;           ///< m (scene frame)
    double far_m = 20.0;            ///< m (scene frame)
};

/// The camera that shows the scene moved by `nav` (world_from_scene = T R S) on the real screen from the real
/// head: since perspective projection commutes with a similarity, drawing the scene at nav.to_world(p) through
/// (screen, head) gives the same image as drawing p through the screen corners, head pose, eye separation and
/// near/far planes mapped by scene_from_world (positions by to_scene, orientations by R^-1, lengths / scale).
/// The scene (workpiece, tool, workspace) is never transformed on the CPU. The renderer's directional light
/// turns with the scene. Inputs must be finite; off_axis_view checks the rest when the frame is drawn.
RunCamera navigated_camera(const renderer::Screen& screen, const Pose& head, double eye_separation_m,
                           const renderer::SceneNavigation& nav, double near_m = 0.05, double far_m = 20.0);

/// True when the camera can be drawn: the head pose is finite and both eyes (renderer::eye_positions) are in front
/// of the screen's plane by more than a tenth of a millimetre (off_axis_view refuses an eye on or behind it). A
/// tracker glitch (a head reported at or behind the wall, or NaN) makes it false.
bool eyes_see_screen(const RunCamera& camera);

}  // namespace tridex::app
