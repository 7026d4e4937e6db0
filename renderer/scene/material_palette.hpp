// renderer/scene/material_palette.hpp - the colours of the workpiece materials (painting writes material ids).
#pragma once

#include <array>

#include <glm/glm.hpp>

#include "renderer/scene/mesh_vertex.hpp"

namespace tridex::renderer {

/// The palette the renderer uses for per-material workpiece colours: linear RGBA, alpha 1, indexed by
/// material id 0..kMaterialCount-1. Material 0 is the unpainted clay colour (0.80, 0.62, 0.45), the
/// colour the workpiece always had; 1..7 are paints: red, green, blue, yellow, white, charcoal, purple.
const std::array<glm::vec4, kMaterialCount>& material_palette();

}  // namespace tridex::renderer
