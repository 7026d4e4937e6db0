// renderer/stereo/frame_eyes.cpp - the eyes of one frame: off-axis views, uniforms, frusta and LOD views.
#include "renderer/stereo/frame_eyes.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "renderer/scene/material_palette.hpp"

namespace tridex::renderer {

namespace {
const glm::vec3 kTowardsLight = glm::normalize(glm::vec3(0.25f, 1.0f, 0.6f));
}  // namespace

FrameEyes frame_eyes(const SceneView& scene, const Screen& screen, const Pose& head, double eye_separation_m, double near_m,
                     double far_m, int width, int height) {
    const std::array<Vec3, 2> eyes = eye_positions(head, eye_separation_m);
    FrameEyes fe;
    EyesUniform& u = fe.uniform;
    if (scene.lod && !(std::isfinite(scene.lod_max_px) && scene.lod_max_px > 0.0))
        throw Error("renderer: SceneView.lod_max_px must be finite and > 0, got " + std::to_string(scene.lod_max_px));
    for (int e = 0; e < 2; ++e) {
        const EyeView v = off_axis_view(screen, eyes[e], near_m, far_m);
        const Mat4 clip_from_world = v.projection * v.view;
        u.clip_from_world[e] = glm::mat4(clip_from_world);
        u.eye_position[e] = glm::vec4(glm::vec3(eyes[e]), 1.0f);
        u.view_from_clip[e] = glm::mat4(glm::inverse(v.projection));
        u.pixels_per_metre[e] = glm::vec4(static_cast<float>(std::abs(v.projection[0][0]) * 0.5 * width),
                                          static_cast<float>(std::abs(v.projection[1][1]) * 0.5 * height), 0.0f,
                                          0.0f);
        fe.frusta[e] = frustum_from_clip(clip_from_world);
        fe.clip_from_world[e] = clip_from_world;
        fe.lod[e] = lod_eye(screen, eyes[e], width, height);
    }
    u.light_direction = glm::vec4(kTowardsLight, 0.0f);
    u.occlusion = glm::vec4(static_cast<float>(scene.occlusion_radius_m), static_cast<float>(scene.occlusion_strength),
                            0.0f, 0.0f);
    const auto palette = palette_colours(scene.palette);
    for (int m = 0; m < kMaterialCount; ++m) u.palette[m] = palette[m];
    return fe;
}

}  // namespace tridex::renderer
