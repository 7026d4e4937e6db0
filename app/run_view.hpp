// app/run_view.hpp - what the render thread draws each frame: the scene from the haptic loop's newest view and
// the newest mesh, and the camera through the navigated scene.
#pragma once

#include "core/aabb.hpp"
#include "core/pose.hpp"
#include "core/tri_mesh.hpp"
#include "haptics/haptic_loop.hpp"
#include "renderer/off_axis.hpp"
#include "renderer/scene_navigation.hpp"
#include "renderer/stereo_renderer.hpp"

namespace tridex::app {

/// The axis-aligned box (world m) that holds a box of half extents `half_m` (m, >= 0) posed by `box`
/// (centre m, orientation): the 8 corners box.apply(+/-half) bounded. An all-zero half extent gives the point box.
Aabb enclosing_box(const Pose& box, const Vec3& half_m);

/// The SceneView of one frame: `mesh` as the workpiece (nullptr = none), the ball tool of `tool_radius_m` at the
/// view's tool position, the workspace box (enclosing_box of the view's box) and the bubble (when its radius > 0).
/// Before the loop's first tick (view.tick == 0) the tool sits at `fallback_tool_m` and the box is
/// `fallback_box_m`. All positions world m.
renderer::SceneView scene_view_from(const haptics::LoopView& view, const TriMesh* mesh, double tool_radius_m,
                                    const Vec3& fallback_tool_m, const Aabb& fallback_box_m);

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

}  // namespace tridex::app
