// renderer/scene/mesh_vertex.hpp - the vertex layout of every stereo mesh draw and the material count: the part of the
// shader interface (shaders/stereo_interface.glsl) that what is drawn shares with the stereo frame
// (renderer/stereo/stereo_uniforms.hpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

namespace tridex::renderer {

/// Number of entries of the material palette (renderer/scene/material_palette.hpp); material ids are
/// 0..kMaterialCount-1.
constexpr int kMaterialCount = 8;

/// Vertex layout of every stereo mesh draw: position (model m) and unit normal, 32-bit floats, and the
/// material id (0..kMaterialCount-1; 0 for meshes without materials).
struct MeshVertex {
    glm::vec3 position;
    glm::vec3 normal;
    std::uint32_t material = 0;
};
static_assert(sizeof(MeshVertex) == 28 && offsetof(MeshVertex, material) == 24);

}  // namespace tridex::renderer
