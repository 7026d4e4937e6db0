// shaders/spirv.hpp - the SPIR-V modules compiled from shaders/*.vert|frag|comp at build time.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace tridex::shaders {

/// The embedded SPIR-V words of the shader registered as `name` in shaders/CMakeLists.txt
/// (for example "stereo_mesh_frag"). The span points into static storage (valid for the whole run).
/// Throws tridex::Error naming the shader when no shader of that name was compiled in.
std::span<const std::uint32_t> spirv(std::string_view name);

/// Names of all embedded shaders, in registration order.
std::vector<std::string_view> names();

}  // namespace tridex::shaders
