// renderer/stereo/ambient_occlusion.cpp - pipeline, descriptors and dispatch of the volumetric obscurance pass.
#include "renderer/stereo/ambient_occlusion.hpp"

#include "gpu/check.hpp"
#include "gpu/compute_pipeline.hpp"
#include "gpu/shader_module.hpp"
#include "renderer/stereo/stereo_uniforms.hpp"
#include "shaders/spirv.hpp"

namespace tridex::renderer {
namespace {

constexpr std::uint32_t kGroup = 8;  // local_size_x/y of stereo_ao.comp
constexpr std::uint32_t kBlock = 2;  // pixels per invocation along x and y (2x2 blocks)

}  // namespace

AmbientOcclusion AmbientOcclusion::create(const gpu::Context& context, const StereoTarget& target, VkBuffer eyes) {
    const VkDevice device = context.device();
    AmbientOcclusion a;
    a.width_ = target.width();
    a.height_ = target.height();

    VkDescriptorSetLayoutBinding bindings[3]{};
    const VkDescriptorType types[3] = {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                       VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
    for (std::uint32_t b = 0; b < 3; ++b) {
        bindings[b].binding = b;
        bindings[b].descriptorType = types[b];
        bindings[b].descriptorCount = 1;
        bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo set_info{};
    set_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    set_info.bindingCount = 3;
    set_info.pBindings = bindings;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    gpu::check(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
    a.set_layout_ = gpu::UniqueDescriptorSetLayout(device, set_layout);

    const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, 2 * sizeof(std::uint32_t)};
    VkPipelineLayoutCreateInfo layout_info{};
    layout_info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout;
    layout_info.pushConstantRangeCount = 1;
    layout_info.pPushConstantRanges = &push;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    gpu::check(vkCreatePipelineLayout(device, &layout_info, nullptr, &layout), "vkCreatePipelineLayout");
    a.layout_ = gpu::UniquePipelineLayout(device, layout);
    const gpu::UniqueShaderModule module = gpu::create_shader_module(context, shaders::spirv("stereo_ao_comp"));
    a.pipeline_ = gpu::create_compute_pipeline(context, module.get(), layout);

    VkSamplerCreateInfo si{};
    si.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO;
    si.magFilter = si.minFilter = VK_FILTER_NEAREST;
    si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler = VK_NULL_HANDLE;
    gpu::check(vkCreateSampler(device, &si, nullptr, &sampler), "vkCreateSampler");
    a.sampler_ = UniqueSampler(device, sampler);

    const VkDescriptorPoolSize sizes[3] = {{types[0], 3}, {types[1], 3}, {types[2], 3}};
    VkDescriptorPoolCreateInfo pool_info{};
    pool_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    pool_info.maxSets = 3;
    pool_info.poolSizeCount = 3;
    pool_info.pPoolSizes = sizes;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    gpu::check(vkCreateDescriptorPool(device, &pool_info, nullptr, &pool), "vkCreateDescriptorPool");
    a.pool_ = gpu::UniqueDescriptorPool(device, pool);
    const VkDescriptorSetLayout layouts[3] = {set_layout, set_layout, set_layout};
    VkDescriptorSetAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 3;
    alloc.pSetLayouts = layouts;
    gpu::check(vkAllocateDescriptorSets(device, &alloc, a.sets_), "vkAllocateDescriptorSets");

    const VkDescriptorBufferInfo buffer{eyes, 0, sizeof(EyesUniform)};
    for (int k = 0; k < 3; ++k) {
        const VkImageView depth_view = k == 0 ? target.depth_array_view() : target.depth_layer_array_view(k - 1);
        const VkImageView colour_view = k == 0 ? target.colour_array_view() : target.colour_layer_array_view(k - 1);
        const VkDescriptorImageInfo depth{a.sampler_.get(), depth_view, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL};
        const VkDescriptorImageInfo colour{VK_NULL_HANDLE, colour_view, VK_IMAGE_LAYOUT_GENERAL};
        VkWriteDescriptorSet writes[3]{};
        for (std::uint32_t b = 0; b < 3; ++b) {
            writes[b].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
            writes[b].dstSet = a.sets_[k];
            writes[b].dstBinding = b;
            writes[b].descriptorCount = 1;
            writes[b].descriptorType = types[b];
        }
        writes[0].pBufferInfo = &buffer;
        writes[1].pImageInfo = &depth;
        writes[2].pImageInfo = &colour;
        vkUpdateDescriptorSets(device, 3, writes, 0, nullptr);
    }
    return a;
}

void AmbientOcclusion::record(VkCommandBuffer cmd, std::uint32_t first_layer, std::uint32_t layer_count) const {
    if (layer_count == 0) return;
    // One layer: its own views (texel layer 0 of the view); both: the views of both layers.
    const VkDescriptorSet set = layer_count == 1 ? sets_[1 + first_layer] : sets_[0];
    const std::uint32_t push[2] = {first_layer, layer_count == 1 ? 0u : first_layer};  // eye, texel layer of z = 0
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, push);
    const std::uint32_t blocks_x = (static_cast<std::uint32_t>(width_) + kBlock - 1) / kBlock;
    const std::uint32_t blocks_y = (static_cast<std::uint32_t>(height_) + kBlock - 1) / kBlock;
    vkCmdDispatch(cmd, (blocks_x + kGroup - 1) / kGroup, (blocks_y + kGroup - 1) / kGroup, layer_count);
}

}  // namespace tridex::renderer
