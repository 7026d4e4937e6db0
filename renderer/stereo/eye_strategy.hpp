// renderer/stereo/eye_strategy.hpp - how the two eyes of a stereo frame reach their own image layer.
#pragma once

#include <string_view>

#include "gpu/context.hpp"

namespace tridex::renderer {

/// How the left and right eye are drawn into layers 0 and 1 of one 2-layer colour (+ depth) image.
enum class EyeStrategy {
    kPassPerEye,      ///< two render pass instances, one per layer; eye index in a push constant. Works everywhere.
    kMultiview,       ///< one multiview render pass, view mask 0b11; eye = gl_ViewIndex (needs multiview)
    kInstancedLayer,  ///< one layered pass; every draw has 2 instances, eye = instance, gl_Layer = eye
                      ///< (needs the Vulkan 1.2 shaderOutputLayer feature)
};

/// "pass-per-eye", "multiview" or "instanced-layer".
std::string_view to_string(EyeStrategy strategy);

/// True when the context enabled the device feature the strategy needs (always true for kPassPerEye).
/// Support is necessary, not sufficient: the renderer still self-tests the strategy (Mesa 22.3 lavapipe
/// advertises multiview but draws view 1's clipped triangles into layer 0; see eye_self_test.hpp).
bool supported(const gpu::Context& context, EyeStrategy strategy);

}  // namespace tridex::renderer
