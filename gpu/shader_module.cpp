// gpu/shader_module.cpp - shader module creation with a basic SPIR-V header check.
#include "gpu/shader_module.hpp"

#include "core/error.hpp"
#include "gpu/check.hpp"

namespace tridex::gpu {

UniqueShaderModule create_shader_module(const Context& context, std::span<const std::uint32_t> spirv) {
    constexpr std::uint32_t kSpirvMagic = 0x07230203u;
    if (spirv.size() < 5 || spirv[0] != kSpirvMagic)
        throw Error("gpu: shader module code is not SPIR-V (empty or wrong magic number)");
    VkShaderModuleCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
    info.codeSize = spirv.size_bytes();
    info.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    check(vkCreateShaderModule(context.device(), &info, nullptr, &module), "vkCreateShaderModule");
    return UniqueShaderModule(context.device(), module);
}

}  // namespace tridex::gpu
