// gpu/compute_pipeline.cpp - storage/uniform-buffer descriptor layouts and compute pipelines.
#include "gpu/compute_pipeline.hpp"

#include <vector>

#include "gpu/check.hpp"

namespace tridex::gpu {

ComputeLayout create_compute_layout(const Context& context, std::uint32_t storage_buffers, std::uint32_t push_bytes,
                                    std::uint32_t uniform_bindings, std::uint32_t array_bindings,
                                    std::uint32_t array_size) {
    const VkDevice dev = context.device();
    std::vector<VkDescriptorSetLayoutBinding> b(storage_buffers);
    for (std::uint32_t i = 0; i < storage_buffers; ++i) {
        b[i].binding = i;
        b[i].descriptorType = (uniform_bindings >> i) & 1u ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        b[i].descriptorCount = (array_bindings >> i) & 1u ? array_size : 1u;
        b[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo li{};
    li.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    li.bindingCount = storage_buffers;
    li.pBindings = b.data();
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    check(vkCreateDescriptorSetLayout(dev, &li, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
    ComputeLayout out;
    out.set_layout = UniqueDescriptorSetLayout(dev, set_layout);

    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
    VkPipelineLayoutCreateInfo pli{};
    pli.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    pli.setLayoutCount = 1;
    pli.pSetLayouts = &set_layout;
    pli.pushConstantRangeCount = push_bytes > 0 ? 1u : 0u;
    pli.pPushConstantRanges = push_bytes > 0 ? &range : nullptr;
    VkPipelineLayout pl = VK_NULL_HANDLE;
    check(vkCreatePipelineLayout(dev, &pli, nullptr, &pl), "vkCreatePipelineLayout");
    out.pipeline_layout = UniquePipelineLayout(dev, pl);
    return out;
}

UniquePipeline create_compute_pipeline(const Context& context, VkShaderModule module, VkPipelineLayout layout,
                                       const VkSpecializationInfo* spec) {
    VkComputePipelineCreateInfo ci{};
    ci.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
    ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    ci.stage.module = module;
    ci.stage.pName = "main";
    ci.stage.pSpecializationInfo = spec;
    ci.layout = layout;
    VkPipeline pipe = VK_NULL_HANDLE;
    check(vkCreateComputePipelines(context.device(), VK_NULL_HANDLE, 1, &ci, nullptr, &pipe), "vkCreateComputePipelines");
    return UniquePipeline(context.device(), pipe);
}

}  // namespace tridex::gpu
