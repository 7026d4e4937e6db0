// renderer/stereo/eye_strategy.cpp - names and feature requirements of the eye strategies.
#include "renderer/stereo/eye_strategy.hpp"

namespace tridex::renderer {

std::string_view to_string(EyeStrategy strategy) {
    switch (strategy) {
        case EyeStrategy::kPassPerEye: return "pass-per-eye";
        case EyeStrategy::kMultiview: return "multiview";
        case EyeStrategy::kInstancedLayer: return "instanced-layer";
    }
    return "unknown";
}

bool supported(const gpu::Context& context, EyeStrategy strategy) {
    switch (strategy) {
        case EyeStrategy::kPassPerEye: return true;
        case EyeStrategy::kMultiview: return context.features().multiview;
        case EyeStrategy::kInstancedLayer: return context.features().shader_output_layer;
    }
    return false;
}

}  // namespace tridex::renderer
