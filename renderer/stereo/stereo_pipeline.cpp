// renderer/stereo/stereo_pipeline.cpp - render pass and pipeline creation per eye strategy.
#include "renderer/stereo/stereo_pipeline.hpp"

#include <string>

#include "core/error.hpp"
#include "gpu/check.hpp"
#include "gpu/graphics_pipeline.hpp"
#include "gpu/shader_module.hpp"
#include "renderer/stereo/stereo_uniforms.hpp"
#include "shaders/spirv.hpp"

namespace tridex::renderer {
namespace {

// The frame's two render passes, compatible with each other (same attachments and subpass), so the pipelines
// and framebuffers made for the first serve both.
// kOpaquePhase: colour and depth cleared and stored; colour left in GENERAL and depth in
// DEPTH_STENCIL_READ_ONLY_OPTIMAL for the ambient-occlusion compute pass.
// kResumePhase: both loaded (after the compute pass's colour writes), colour left in TRANSFER_SRC_OPTIMAL for
// readback and blits.
// Before either: earlier readback copies, sampling and compute use of the images and earlier attachment writes
// finish first. After either: the attachment writes are visible to the compute pass, the next render pass and
// transfer reads.
enum class PassPhase { kOpaque, kResume };

gpu::UniqueRenderPass make_render_pass(VkDevice device, EyeStrategy strategy, PassPhase phase) {
    const bool opaque = phase == PassPhase::kOpaque;
    VkAttachmentDescription att[2]{};
    att[0].format = kStereoColourFormat;
    att[0].samples = VK_SAMPLE_COUNT_1_BIT;
    att[0].loadOp = opaque ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
    att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[0].initialLayout = opaque ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_GENERAL;
    att[0].finalLayout = opaque ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    att[1] = att[0];
    att[1].format = kStereoDepthFormat;
    att[1].storeOp = opaque ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[1].initialLayout = opaque ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    att[1].finalLayout = opaque ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL
                                : VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;

    const VkAttachmentReference colour{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    const VkAttachmentReference depth{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &colour;
    subpass.pDepthStencilAttachment = &depth;

    constexpr VkPipelineStageFlags kAttachmentStages = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                                       VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                                       VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    constexpr VkAccessFlags kAttachmentAccess =
        VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
        VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    // The same dependencies in both passes (render pass compatibility, as the validation layer checks it).
    VkSubpassDependency deps[2]{};
    deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    deps[0].dstSubpass = 0;
    deps[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | kAttachmentStages;
    deps[0].srcAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                            VK_ACCESS_SHADER_WRITE_BIT;
    deps[0].dstStageMask = kAttachmentStages;
    deps[0].dstAccessMask = kAttachmentAccess;
    deps[1].srcSubpass = 0;
    deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    deps[1].srcStageMask = kAttachmentStages;
    deps[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    deps[1].dstStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT | kAttachmentStages;
    deps[1].dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                            kAttachmentAccess;

    VkRenderPassCreateInfo info{};

    info.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
    info.attachmentCount = 2;
    info.pAttachments = att;
    info.subpassCount = 1;
    info.pSubpasses = &subpass;
    info.dependencyCount = 2;
    info.pDependencies = deps;

    // Multiview: both views (left = 0, right = 1) in the one subpass; they see the same geometry.
    const std::uint32_t view_mask = 0b11, correlation = 0b11;
    VkRenderPassMultiviewCreateInfo multiview{};
    multiview.sType = VK_STRUCTURE_TYPE_RENDER_PASS_MULTIVIEW_CREATE_INFO;
    multiview.subpassCount = 1;
    multiview.pViewMasks = &view_mask;
    multiview.correlationMaskCount = 1;
    multiview.pCorrelationMasks = &correlation;
    if (strategy == EyeStrategy::kMultiview) info.pNext = &multiview;

    VkRenderPass pass = VK_NULL_HANDLE;
    gpu::check(vkCreateRenderPass(device, &info, nullptr, &pass), "vkCreateRenderPass");
    return gpu::UniqueRenderPass(device, pass);
}

const char* vertex_shader_name(EyeStrategy strategy, bool contour) {
    switch (strategy) {
        case EyeStrategy::kPassPerEye: return contour ? "stereo_contour_pass_vert" : "stereo_mesh_pass_vert";
        case EyeStrategy::kMultiview: return contour ? "stereo_contour_multiview_vert" : "stereo_mesh_multiview_vert";
        case EyeStrategy::kInstancedLayer: return contour ? "stereo_contour_layer_vert" : "stereo_mesh_layer_vert";
    }
    return "";
}

// The GPU contour's vertex (compute/gpu/gpu_contourer.hpp GpuContourVertex): float grid[3], uint material.
constexpr std::uint32_t kContourVertexBytes = 16;

gpu::UniquePipeline make_pipeline(VkDevice device, VkRenderPass pass, VkPipelineLayout layout, VkShaderModule vs,
                                  VkShaderModule fs, PipelineKind kind) {
    const bool contour = kind == PipelineKind::kContour;
    const VkVertexInputBindingDescription binding{0, contour ? kContourVertexBytes : static_cast<std::uint32_t>(sizeof(MeshVertex)),
                                                  VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription attributes[3] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(MeshVertex, position)},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(MeshVertex, normal)},
        {2, 0, VK_FORMAT_R32_UINT, offsetof(MeshVertex, material)},
    };
    const VkVertexInputAttributeDescription contour_attributes[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
        {2, 0, VK_FORMAT_R32_UINT, 12},
    };
    const bool opaque = kind == PipelineKind::kOpaque || contour;
    const bool overlay = kind == PipelineKind::kOverlay;
    gpu::GraphicsPipelineDesc d;
    d.vertex = vs;
    d.fragment = fs;
    d.bindings = std::span(&binding, 1);
    d.attributes = contour ? std::span<const VkVertexInputAttributeDescription>(contour_attributes)
                           : std::span<const VkVertexInputAttributeDescription>(attributes);
    // Meshes are counter-clockwise seen from outside; the projection flips y so the image is upright,
    // which keeps the on-screen winding counter-clockwise in Vulkan's framebuffer convention.
    d.cull = overlay                                  ? VK_CULL_MODE_NONE
             : kind == PipelineKind::kTranslucentBack ? VK_CULL_MODE_FRONT_BIT
                                                      : VK_CULL_MODE_BACK_BIT;
    d.depth = true;
    d.depth_test = !overlay;
    d.depth_write = opaque;
    d.alpha_blend = !opaque;
    return gpu::create_graphics_pipeline(device, pass, layout, d);  // viewport and scissor set per eye
}

}  // namespace

StereoPipeline StereoPipeline::create(const gpu::Context& context, EyeStrategy strategy) {
    if (!supported(context, strategy))
        throw Error("renderer: eye strategy " + std::string(to_string(strategy)) +
                    " is not supported by device " + context.device_name());
    const VkDevice device = context.device();
    StereoPipeline p;
    p.strategy_ = strategy;
    p.render_pass_ = make_render_pass(device, strategy, PassPhase::kOpaque);
    p.resume_pass_ = make_render_pass(device, strategy, PassPhase::kResume);

    VkDescriptorSetLayoutBinding binding{};
    binding.binding = 0;
    binding.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    binding.descriptorCount = 1;
    binding.stageFlags = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    VkDescriptorSetLayoutCreateInfo set_info{};
    set_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    set_info.bindingCount = 1;
    set_info.pBindings = &binding;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    gpu::check(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
    p.set_layout_ = gpu::UniqueDescriptorSetLayout(device, set_layout);

    const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                   sizeof(DrawConstants)};
    VkPipelineLayoutCreateInfo layout_info{};
    layout_info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout;
    layout_info.pushConstantRangeCount = 1;
    layout_info.pPushConstantRanges = &push;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    gpu::check(vkCreatePipelineLayout(device, &layout_info, nullptr, &layout), "vkCreatePipelineLayout");
    p.layout_ = gpu::UniquePipelineLayout(device, layout);

    const gpu::UniqueShaderModule vs =
        gpu::create_shader_module(context, shaders::spirv(vertex_shader_name(strategy, false)));
    const gpu::UniqueShaderModule fs = gpu::create_shader_module(context, shaders::spirv("stereo_mesh_frag"));
    for (PipelineKind kind : {PipelineKind::kOpaque, PipelineKind::kTranslucentBack, PipelineKind::kTranslucentFront,
                              PipelineKind::kOverlay})
        p.pipelines_[static_cast<int>(kind)] =
            make_pipeline(device, p.render_pass_.get(), p.layout_.get(), vs.get(), fs.get(), kind);
    const gpu::UniqueShaderModule contour_vs =
        gpu::create_shader_module(context, shaders::spirv(vertex_shader_name(strategy, true)));
    const gpu::UniqueShaderModule contour_fs =
        gpu::create_shader_module(context, shaders::spirv("stereo_contour_frag"));
    p.pipelines_[static_cast<int>(PipelineKind::kContour)] = make_pipeline(
        device, p.render_pass_.get(), p.layout_.get(), contour_vs.get(), contour_fs.get(), PipelineKind::kContour);
    return p;
}

}  // namespace tridex::renderer
