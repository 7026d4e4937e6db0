// renderer/stereo_uniforms.hpp - C++ mirrors of the shader interface in shaders/stereo_interface.glsl.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

namespace tridex::renderer {

/// Uniform block `Eyes` (std140), set 0 binding 0: per-eye clip-from-world matrices (float, world m),
/// eye positions (w unused) and the unit direction towards the directional light.
struct EyesUniform {
    glm::mat4 clip_from_world[2];
    glm::vec4 eye_position[2];
    glm::vec4 light_direction;
};
static_assert(offsetof(EyesUniform, eye_position) == 128 && offsetof(EyesUniform, light_direction) == 160);
static_assert(sizeof(EyesUniform) == 176);

/// Push-constant block `Draw` (std430): world-from-model (m), linear RGBA colour, eye index for the
/// pass-per-eye strategy (0 left, 1 right), and lit (1: Blinn-Phong shading; 0: flat colour).
struct DrawConstants {
    glm::mat4 world_from_model{1.0f};
    glm::vec4 colour{1.0f};
    std::uint32_t eye = 0;
    std::uint32_t lit = 1;
};
static_assert(offsetof(DrawConstants, colour) == 64 && offsetof(DrawConstants, eye) == 80 &&
              offsetof(DrawConstants, lit) == 84);
static_assert(sizeof(DrawConstants) == 88);

/// Vertex layout of every stereo mesh draw: position (model m) and unit normal, 32-bit floats.
struct MeshVertex {
    glm::vec3 position;
    glm::vec3 normal;
};
static_assert(sizeof(MeshVertex) == 24);

}  // namespace tridex::renderer
