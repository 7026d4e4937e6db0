// renderer/stereo/stereo_uniforms.hpp - C++ mirrors of the shader interface in shaders/stereo_interface.glsl (the
// vertex layout and material count, which what is drawn shares, are in renderer/scene/mesh_vertex.hpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

#include "renderer/scene/mesh_vertex.hpp"

namespace tridex::renderer {

/// Uniform block `Eyes` (std140), set 0 binding 0: per-eye clip-from-world matrices (float, world m),
/// eye positions (w unused), the unit direction towards the directional key light, the material palette
/// (linear RGBA per material id, used by draws with DrawConstants::palette = 1), and for the ambient-occlusion
/// pass (renderer/stereo/ambient_occlusion.hpp): per-eye view-from-clip matrices (inverse projections; eye
/// space in m, the eye looking along -z), per-eye pixels per metre at 1 m from the eye (x, y; z, w unused) and
/// `occlusion` = (sphere radius m, strength, unused, unused).
struct EyesUniform {
    glm::mat4 clip_from_world[2];
    glm::vec4 eye_position[2];
    glm::vec4 light_direction;
    glm::vec4 palette[kMaterialCount];
    glm::mat4 view_from_clip[2];
    glm::vec4 pixels_per_metre[2];
    glm::vec4 occlusion;
};
static_assert(offsetof(EyesUniform, eye_position) == 128 && offsetof(EyesUniform, light_direction) == 160 &&
              offsetof(EyesUniform, palette) == 176);
static_assert(offsetof(EyesUniform, view_from_clip) == 176 + 16 * kMaterialCount &&
              offsetof(EyesUniform, pixels_per_metre) == 304 + 128 && offsetof(EyesUniform, occlusion) == 464);
static_assert(sizeof(EyesUniform) == 480);

/// Push-constant block `Draw` (std430): world-from-model (m), linear RGBA colour, eye index for the
/// pass-per-eye strategy (0 left, 1 right), lit (1: Blinn-Phong shading; 0: flat colour), palette
/// (1: the base colour is EyesUniform::palette[vertex material] instead of `colour`) and screen_space
/// (1: world_from_model maps the vertex straight to clip space, the same for both eyes - overlays on the
/// screen plane; 0: world_from_model then the eye's clip_from_world) and eye_mask (bit 0 left, bit 1 right: the
/// fragment shader discards the eyes not in it, so a one-eye draw stays in its eye under every strategy, multiview
/// included).
struct DrawConstants {
    glm::mat4 world_from_model{1.0f};
    glm::vec4 colour{1.0f};
    std::uint32_t eye = 0;
    std::uint32_t lit = 1;
    std::uint32_t palette = 0;
    std::uint32_t screen_space = 0;
    std::uint32_t eye_mask = 0b11;
};
static_assert(offsetof(DrawConstants, colour) == 64 && offsetof(DrawConstants, eye) == 80 &&
              offsetof(DrawConstants, lit) == 84 && offsetof(DrawConstants, palette) == 88 &&
              offsetof(DrawConstants, screen_space) == 92 && offsetof(DrawConstants, eye_mask) == 96);
static_assert(sizeof(DrawConstants) == 100);

}  // namespace tridex::renderer
