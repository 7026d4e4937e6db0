// renderer/scene/material_palette.cpp - the shader's material colours from a core palette.
#include "renderer/scene/material_palette.hpp"

namespace tridex::renderer {

std::array<glm::vec4, kMaterialCount> palette_colours(const MaterialPalette& palette) {
    std::array<glm::vec4, kMaterialCount> out{};
    for (int m = 0; m < kMaterialCount; ++m) {
        const auto& c = palette.entries[m].rgb;
        out[m] = glm::vec4(c[0], c[1], c[2], 1.0f);
    }
    return out;
}

std::array<glm::vec4, kMaterialCount> palette_colours(const MaterialPalette* palette) {
    return palette ? palette_colours(*palette) : material_palette();
}

const std::array<glm::vec4, kMaterialCount>& material_palette() {
    static const std::array<glm::vec4, kMaterialCount> palette = palette_colours(default_material_palette());
    return palette;
}

}  // namespace tridex::renderer
