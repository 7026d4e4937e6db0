// renderer/scene/material_palette.cpp - the material colour table.
#include "renderer/scene/material_palette.hpp"

namespace tridex::renderer {

const std::array<glm::vec4, kMaterialCount>& material_palette() {
    static const std::array<glm::vec4, kMaterialCount> palette = {
        glm::vec4(0.80f, 0.62f, 0.45f, 1.0f),  // 0 clay (unpainted)
        glm::vec4(0.78f, 0.20f, 0.18f, 1.0f),  // 1 red
        glm::vec4(0.25f, 0.62f, 0.30f, 1.0f),  // 2 green
        glm::vec4(0.22f, 0.40f, 0.80f, 1.0f),  // 3 blue
        glm::vec4(0.90f, 0.78f, 0.25f, 1.0f),  // 4 yellow
        glm::vec4(0.92f, 0.92f, 0.90f, 1.0f),  // 5 white
        glm::vec4(0.18f, 0.18f, 0.20f, 1.0f),  // 6 charcoal
        glm::vec4(0.58f, 0.32f, 0.70f, 1.0f),  // 7 purple
    };
    return palette;
}

}  // namespace tridex::renderer
