// renderer/stereo/ambient_occlusion.cpp - pipelines, descriptors and dispatches of the volumetric obscurance passes.
#include "renderer/stereo/ambient_occlusion.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "gpu/check.hpp"
#include "gpu/compute_pipeline.hpp"
#include "gpu/descriptor_sets.hpp"
#include "gpu/shader_module.hpp"
#include "renderer/stereo/stereo_uniforms.hpp"
#include "shaders/spirv.hpp"

namespace tridex::renderer {
namespace {

constexpr std::uint32_t kGroup = 8;  // local_size_x/y of stereo_ao.comp and stereo_ao_apply.comp
constexpr std::uint32_t kBlock = 2;  // the finest block (pixels per value along x and y): the image's size
constexpr std::uint32_t kBindings = 4;
constexpr VkDescriptorType kTypes[kBindings] = {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                                                VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                                VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};

}  // namespace

AmbientOcclusion AmbientOcclusion::create(const gpu::Context& context, const StereoTarget& target, VkBuffer eyes) {
    const VkDevice device = context.device();
    AmbientOcclusion a;
    a.eyes_ = eyes;
    VkDescriptorSetLayoutBinding bindings[kBindings]{};
    for (std::uint32_t b = 0; b < kBindings; ++b) {
        bindings[b].binding = b;
        bindings[b].descriptorType = kTypes[b];
        bindings[b].descriptorCount = 1;
        bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo set_info{};
    set_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    set_info.bindingCount = kBindings;
    set_info.pBindings = bindings;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    gpu::check(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
    a.set_layout_ = gpu::UniqueDescriptorSetLayout(device, set_layout);

    const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, 4 * sizeof(std::uint32_t)};
    VkPipelineLayoutCreateInfo layout_info{};
    layout_info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout;
    layout_info.pushConstantRangeCount = 1;
    layout_info.pPushConstantRanges = &push;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    gpu::check(vkCreatePipelineLayout(device, &layout_info, nullptr, &layout), "vkCreatePipelineLayout");
    a.layout_ = gpu::UniquePipelineLayout(device, layout);
    const char* const names[2][2] = {{"stereo_ao_comp", "stereo_ao_apply_comp"},
                                     {"stereo_ao4_comp", "stereo_ao4_apply_comp"}};
    for (int r = 0; r < 2; ++r) {
        const gpu::UniqueShaderModule module = gpu::create_shader_module(context, shaders::spirv(names[r][0]));
        a.pipelines_[r] = gpu::create_compute_pipeline(context, module.get(), layout);
        const gpu::UniqueShaderModule apply = gpu::create_shader_module(context, shaders::spirv(names[r][1]));
        a.apply_pipelines_[r] = gpu::create_compute_pipeline(context, apply.get(), layout);
    }

    VkSamplerCreateInfo si{};
    si.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO;
    si.magFilter = si.minFilter = VK_FILTER_NEAREST;
    si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler = VK_NULL_HANDLE;
    gpu::check(vkCreateSampler(device, &si, nullptr, &sampler), "vkCreateSampler");
    a.sampler_ = UniqueSampler(device, sampler);

    a.pool_ =
        gpu::allocate_descriptor_sets(device, {{kTypes[0], 3}, {kTypes[1], 3}, {kTypes[2], 6}}, set_layout, 3, a.sets_);
    a.retarget(context, target);
    return a;
}

void AmbientOcclusion::retarget(const gpu::Context& context, const StereoTarget& target) {
    if (!valid()) throw Error("ambient occlusion: retarget() of one not made by create()");
    const VkDevice device = context.device();
    gpu::ImageArrayInfo half_info;
    half_info.width = (static_cast<std::uint32_t>(target.width()) + kBlock - 1) / kBlock;
    half_info.height = (static_cast<std::uint32_t>(target.height()) + kBlock - 1) / kBlock;
    half_info.layers = 2;
    half_info.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    half_info.usage = VK_IMAGE_USAGE_STORAGE_BIT;
    gpu::ImageArray half = gpu::ImageArray::create(context, half_info);  // a failure leaves the old one bound
    const VkDescriptorBufferInfo buffer{eyes_, 0, sizeof(EyesUniform)};
    for (int k = 0; k < 3; ++k) {
        const VkImageView depth_view = k == 0 ? target.depth_array_view() : target.depth_layer_array_view(k - 1);
        const VkImageView colour_view = k == 0 ? target.colour_array_view() : target.colour_layer_array_view(k - 1);
        const VkDescriptorImageInfo depth{sampler_.get(), depth_view, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL};
        const VkDescriptorImageInfo colour{VK_NULL_HANDLE, colour_view, VK_IMAGE_LAYOUT_GENERAL};
        const VkDescriptorImageInfo half_image{VK_NULL_HANDLE, half.array_view(), VK_IMAGE_LAYOUT_GENERAL};
        VkWriteDescriptorSet writes[kBindings]{};
        for (std::uint32_t b = 0; b < kBindings; ++b) {
            writes[b].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
            writes[b].dstSet = sets_[k];
            writes[b].dstBinding = b;
            writes[b].descriptorCount = 1;
            writes[b].descriptorType = kTypes[b];
        }
        writes[0].pBufferInfo = &buffer;
        writes[1].pImageInfo = &depth;
        writes[2].pImageInfo = &colour;
        writes[3].pImageInfo = &half_image;
        vkUpdateDescriptorSets(device, kBindings, writes, 0, nullptr);
    }
    half_ = std::move(half);
    width_ = target.width();
    height_ = target.height();
}

void AmbientOcclusion::record(VkCommandBuffer cmd, std::uint32_t first_layer, std::uint32_t layer_count,
                              const PixelRect& region, OcclusionResolution resolution) const {
    const PixelRect r = unite(PixelRect{}, PixelRect{std::max(region.x0, 0), std::max(region.y0, 0),
                                                     std::min(region.x1, width_), std::min(region.y1, height_)});
    if (layer_count == 0 || r.empty()) return;
    // One layer: its own views (texel layer 0 of the view); both: the views of both layers.
    const VkDescriptorSet set = layer_count == 1 ? sets_[1 + first_layer] : sets_[0];
    // The region in blocks: [b0, b1) for the colour pass, one block wider on each side (clamped) for the
    // half-resolution pass, whose values the colour pass reads around each block.
    const int quarter = resolution == OcclusionResolution::kQuarter ? 1 : 0;
    const int block = 2 << quarter;  // pixels per value along x and y
    const int blocks_x = (width_ + block - 1) / block;
    const int blocks_y = (height_ + block - 1) / block;
    const int b0x = r.x0 / block, b0y = r.y0 / block, b1x = (r.x1 + block - 1) / block,
              b1y = (r.y1 + block - 1) / block;
    const int h0x = std::max(b0x - 1, 0), h0y = std::max(b0y - 1, 0);
    const int h1x = std::min(b1x + 1, blocks_x), h1y = std::min(b1y + 1, blocks_y);
    const auto groups = [](int blocks) { return (static_cast<std::uint32_t>(blocks) + kGroup - 1) / kGroup; };
    const std::uint32_t eye_texel[2] = {first_layer, layer_count == 1 ? 0u : first_layer};  // of invocation z = 0
    // The half-resolution image (both layers, as the descriptors bind both): earlier dispatches (an earlier frame's
    // or eye's, whose colour scaling is recorded already) are done with it; its contents are discarded (UNDEFINED)
    // and the dispatched layers rewritten whole.
    VkImageMemoryBarrier to_general{};
    to_general.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
    to_general.srcAccessMask = 0;
    to_general.dstAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    to_general.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    to_general.newLayout = VK_IMAGE_LAYOUT_GENERAL;
    to_general.srcQueueFamilyIndex = to_general.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    to_general.image = half_.handle();
    to_general.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 2};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0,
                         nullptr, 0, nullptr, 1, &to_general);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set, 0, nullptr);
    const std::uint32_t half_push[4] = {eye_texel[0], eye_texel[1], static_cast<std::uint32_t>(h0x),
                                        static_cast<std::uint32_t>(h0y)};
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof half_push, half_push);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_[quarter].get());
    vkCmdDispatch(cmd, groups(h1x - h0x), groups(h1y - h0y), layer_count);
    // The half-resolution values -> the upsampling pass.
    VkImageMemoryBarrier written = to_general;
    written.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    written.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
    written.oldLayout = written.newLayout = VK_IMAGE_LAYOUT_GENERAL;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0,
                         nullptr, 0, nullptr, 1, &written);
    const std::uint32_t apply_push[4] = {eye_texel[0], eye_texel[1], static_cast<std::uint32_t>(b0x),
                                         static_cast<std::uint32_t>(b0y)};
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof apply_push, apply_push);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, apply_pipelines_[quarter].get());
    vkCmdDispatch(cmd, groups(b1x - b0x), groups(b1y - b0y), layer_count);
}

}  // namespace tridex::renderer
