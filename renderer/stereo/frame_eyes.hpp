// renderer/stereo/frame_eyes.hpp - the two eyes of one frame: their off-axis views as the shaders read them (uniforms
// with the key light, ambient-occlusion settings and palette), their frusta for culling and their LOD views.
#pragma once

#include <array>

#include "core/math.hpp"
#include "core/pose.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/scene/tile_culling.hpp"
#include "renderer/scene/tile_lod.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "renderer/stereo/stereo_uniforms.hpp"

namespace tridex::renderer {

/// One frame's eyes: the uniforms the shaders read, and per eye its frustum, clip-from-world matrix and LOD view.
struct FrameEyes {
    EyesUniform uniform{};
    std::array<Frustum, 2> frusta;
    std::array<Mat4, 2> clip_from_world{};
    std::array<LodEye, 2> lod{};
};

/// The eyes of a frame of width x height pixels per eye seen from `head` (world m) on `screen` (Kooima's off-axis
/// frustum, off_axis_view; near and far planes m), with the key light (from above, a little to the right and in front
/// of the screen: light from above is how people read shape, a cut's upper wall falls into shade and its lower wall
/// catches light), the ambient-occlusion settings of `scene` and the material palette. Throws tridex::Error on a bad
/// eye separation (eye_positions), SceneView::lod_max_px or view (off_axis_view).
FrameEyes frame_eyes(const SceneView& scene, const Screen& screen, const Pose& head, double eye_separation_m, double near_m,
                     double far_m, int width, int height);

}  // namespace tridex::renderer
