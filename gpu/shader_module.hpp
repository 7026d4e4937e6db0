// gpu/shader_module.hpp - a VkShaderModule from embedded SPIR-V words.
#pragma once

#include <cstdint>
#include <span>

#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"

namespace tridex::gpu {

/// Creates a shader module from SPIR-V words (for example tridex::shaders::spirv("stereo_mesh_frag")).
/// Throws tridex::Error when the span is shorter than the 5-word SPIR-V header, does not start with the
/// SPIR-V magic number 0x07230203, or the driver rejects it.
UniqueShaderModule create_shader_module(const Context& context, std::span<const std::uint32_t> spirv);

}  // namespace tridex::gpu
