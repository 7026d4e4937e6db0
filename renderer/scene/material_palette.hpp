// renderer/scene/material_palette.hpp - the colours of the workpiece materials (painting writes material ids).
#pragma once

#include <array>

#include <glm/glm.hpp>

#include "core/material_palette.hpp"
#include "renderer/scene/mesh_vertex.hpp"

namespace tridex::renderer {

static_assert(kMaterialCount == kPaletteSize, "the shader's palette holds one colour per material id");

/// The shader's palette of `palette` (core/material_palette.hpp): its colours (PaletteEntry::rgb, which the shader
/// lights as they are and writes unencoded) as RGBA, alpha 1, indexed by
/// material id 0..kMaterialCount-1.
std::array<glm::vec4, kMaterialCount> palette_colours(const MaterialPalette& palette);

/// palette_colours(*palette), or the default palette's colours when `palette` is null.
std::array<glm::vec4, kMaterialCount> palette_colours(const MaterialPalette* palette);

/// The default palette's colours (palette_colours(default_material_palette())): material 0 is the unpainted clay
/// colour (0.80, 0.62, 0.45), the colour the workpiece always had; 1..7 are paints: red, green, blue, yellow,
/// white, charcoal, purple.
const std::array<glm::vec4, kMaterialCount>& material_palette();

}  // namespace tridex::renderer
