// renderer/contour_indirect_draw.cpp - render pass, pipeline and the two draw paths (indirect per tile,
// direct reference) of ContourIndirectRenderer.
#include "renderer/contour_indirect_draw.hpp"

#include <cstring>
#include <functional>
#include <string>

#include "core/error.hpp"
#include "gpu/buffer.hpp"
#include "gpu/check.hpp"
#include "gpu/image_array.hpp"
#include "gpu/shader_module.hpp"
#include "gpu/unique_handle.hpp"
#include "shaders/spirv.hpp"

namespace tridex::renderer {

struct ContourIndirectRenderer::Impl {
    const gpu::Context* context = nullptr;
    std::uint32_t width = 0, height = 0;
    gpu::ImageArray colour, depth;
    gpu::UniqueRenderPass pass;
    gpu::UniqueFramebuffer framebuffer;
    gpu::UniquePipelineLayout layout;
    gpu::UniquePipeline pipeline;
    gpu::Buffer readback;

    Image draw(const std::function<void(VkCommandBuffer)>& record, const glm::mat4& clip_from_grid);
};

namespace {

gpu::UniqueRenderPass make_pass(VkDevice dev) {
    VkAttachmentDescription att[2]{};
    att[0].format = VK_FORMAT_R8G8B8A8_UNORM;
    att[0].samples = VK_SAMPLE_COUNT_1_BIT;
    att[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att[0].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    att[1] = att[0];
    att[1].format = VK_FORMAT_D32_SFLOAT;
    att[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    const VkAttachmentReference colour{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    const VkAttachmentReference depth{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &colour;
    sub.pDepthStencilAttachment = &depth;
    VkSubpassDependency dep[2]{};
    // Earlier transfer reads of the colour image and depth writes finish before this pass writes.
    dep[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    dep[0].dstSubpass = 0;
    dep[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    dep[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT;
    dep[0].srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    dep[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                           VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
    // The colour writes are visible to the readback copy after the pass.
    dep[1].srcSubpass = 0;
    dep[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    dep[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dep[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    dep[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dep[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    VkRenderPassCreateInfo ci{};
    ci.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
    ci.attachmentCount = 2;
    ci.pAttachments = att;
    ci.subpassCount = 1;
    ci.pSubpasses = &sub;
    ci.dependencyCount = 2;
    ci.pDependencies = dep;
    VkRenderPass pass = VK_NULL_HANDLE;
    gpu::check(vkCreateRenderPass(dev, &ci, nullptr, &pass), "vkCreateRenderPass");
    return gpu::UniqueRenderPass(dev, pass);
}

gpu::UniquePipeline make_pipeline(const gpu::Context& context, VkRenderPass pass, VkPipelineLayout layout, std::uint32_t w,
                                  std::uint32_t h) {
    const VkDevice dev = context.device();
    const gpu::UniqueShaderModule vs = gpu::create_shader_module(context, shaders::spirv("dexel_contour_draw_vert"));
    const gpu::UniqueShaderModule fs = gpu::create_shader_module(context, shaders::spirv("dexel_contour_draw_frag"));
    VkPipelineShaderStageCreateInfo stages[2]{};
    for (int i = 0; i < 2; ++i) {
        stages[i].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        stages[i].stage = i == 0 ? VK_SHADER_STAGE_VERTEX_BIT : VK_SHADER_STAGE_FRAGMENT_BIT;
        stages[i].module = i == 0 ? vs.get() : fs.get();
        stages[i].pName = "main";
    }
    const VkVertexInputBindingDescription binding{0, sizeof(ContourDrawVertex), VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription attrs[2] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                                                        {1, 0, VK_FORMAT_R32_UINT, 12}};
    VkPipelineVertexInputStateCreateInfo vi{};
    vi.sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO;
    vi.vertexBindingDescriptionCount = 1;
    vi.pVertexBindingDescriptions = &binding;
    vi.vertexAttributeDescriptionCount = 2;
    vi.pVertexAttributeDescriptions = attrs;
    VkPipelineInputAssemblyStateCreateInfo ia{};
    ia.sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO;
    ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    const VkViewport viewport{0.0f, 0.0f, static_cast<float>(w), static_cast<float>(h), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {w, h}};
    VkPipelineViewportStateCreateInfo vp{};
    vp.sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO;
    vp.viewportCount = 1;
    vp.pViewports = &viewport;
    vp.scissorCount = 1;
    vp.pScissors = &scissor;
    VkPipelineRasterizationStateCreateInfo rs{};
    rs.sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO;
    rs.polygonMode = VK_POLYGON_MODE_FILL;
    rs.cullMode = VK_CULL_MODE_NONE;
    rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    rs.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo ms{};
    ms.sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO;
    ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo ds{};
    ds.sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO;
    ds.depthTestEnable = VK_TRUE;
    ds.depthWriteEnable = VK_TRUE;
    ds.depthCompareOp = VK_COMPARE_OP_LESS;
    VkPipelineColorBlendAttachmentState blend{};
    blend.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo cb{};
    cb.sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO;
    cb.attachmentCount = 1;
    cb.pAttachments = &blend;
    VkGraphicsPipelineCreateInfo ci{};
    ci.sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO;
    ci.stageCount = 2;
    ci.pStages = stages;
    ci.pVertexInputState = &vi;
    ci.pInputAssemblyState = &ia;
    ci.pViewportState = &vp;
    ci.pRasterizationState = &rs;
    ci.pMultisampleState = &ms;
    ci.pDepthStencilState = &ds;
    ci.pColorBlendState = &cb;
    ci.layout = layout;
    ci.renderPass = pass;
    VkPipeline pipe = VK_NULL_HANDLE;
    gpu::check(vkCreateGraphicsPipelines(dev, VK_NULL_HANDLE, 1, &ci, nullptr, &pipe), "vkCreateGraphicsPipelines");
    return gpu::UniquePipeline(dev, pipe);
}

}  // namespace

ContourIndirectRenderer ContourIndirectRenderer::create(const gpu::Context& context, int width, int height) {
    if (width < 1 || height < 1 || width > 4096 || height > 4096)
        throw Error("contour renderer: size " + std::to_string(width) + "x" + std::to_string(height) + " outside 1..4096");
    auto impl = std::make_unique<Impl>();
    impl->context = &context;
    impl->width = static_cast<std::uint32_t>(width);
    impl->height = static_cast<std::uint32_t>(height);
    const VkDevice dev = context.device();
    gpu::ImageArrayInfo ci;
    ci.width = impl->width;
    ci.height = impl->height;
    ci.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    impl->colour = gpu::ImageArray::create(context, ci);
    ci.format = VK_FORMAT_D32_SFLOAT;
    ci.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    ci.aspect = VK_IMAGE_ASPECT_DEPTH_BIT;
    impl->depth = gpu::ImageArray::create(context, ci);
    impl->pass = make_pass(dev);
    const VkImageView views[2] = {impl->colour.layer_view(0), impl->depth.layer_view(0)};
    VkFramebufferCreateInfo fi{};
    fi.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
    fi.renderPass = impl->pass.get();
    fi.attachmentCount = 2;
    fi.pAttachments = views;
    fi.width = impl->width;
    fi.height = impl->height;
    fi.layers = 1;
    VkFramebuffer fb = VK_NULL_HANDLE;
    gpu::check(vkCreateFramebuffer(dev, &fi, nullptr, &fb), "vkCreateFramebuffer");
    impl->framebuffer = gpu::UniqueFramebuffer(dev, fb);
    const VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::mat4)};
    VkPipelineLayoutCreateInfo li{};
    li.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    li.pushConstantRangeCount = 1;
    li.pPushConstantRanges = &range;
    VkPipelineLayout pl = VK_NULL_HANDLE;
    gpu::check(vkCreatePipelineLayout(dev, &li, nullptr, &pl), "vkCreatePipelineLayout");
    impl->layout = gpu::UniquePipelineLayout(dev, pl);
    impl->pipeline = make_pipeline(context, impl->pass.get(), pl, impl->width, impl->height);
    impl->readback = gpu::Buffer::create(context, std::size_t{impl->width} * impl->height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                         gpu::MemoryDomain::kHost);
    return ContourIndirectRenderer(std::move(impl));
}

ContourIndirectRenderer::ContourIndirectRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ContourIndirectRenderer::~ContourIndirectRenderer() = default;
ContourIndirectRenderer::ContourIndirectRenderer(ContourIndirectRenderer&&) noexcept = default;
ContourIndirectRenderer& ContourIndirectRenderer::operator=(ContourIndirectRenderer&&) noexcept = default;

Image ContourIndirectRenderer::Impl::draw(const std::function<void(VkCommandBuffer)>& record, const glm::mat4& clip_from_grid) {
    context->submit_and_wait([&](VkCommandBuffer cmd) {
        VkClearValue clear[2]{};
        clear[0].color = {{0.05f, 0.05f, 0.08f, 1.0f}};
        clear[1].depthStencil = {1.0f, 0};
        VkRenderPassBeginInfo bi{};
        bi.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
        bi.renderPass = pass.get();
        bi.framebuffer = framebuffer.get();
        bi.renderArea = {{0, 0}, {width, height}};
        bi.clearValueCount = 2;
        bi.pClearValues = clear;
        vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.get());
        vkCmdPushConstants(cmd, layout.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::mat4), &clip_from_grid);
        record(cmd);
        vkCmdEndRenderPass(cmd);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.imageExtent = {width, height, 1};
        vkCmdCopyImageToBuffer(cmd, colour.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.handle(), 1, &copy);
        VkMemoryBarrier barrier{};
        barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
        barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
    });
    Image out = Image::filled(static_cast<int>(width), static_cast<int>(height), 0, 0, 0);
    std::memcpy(out.rgba.data(), readback.mapped(), out.rgba.size());
    return out;
}

Image ContourIndirectRenderer::render_indirect(const IndirectSurface& s, const glm::mat4& clip_from_grid) {
    if (s.draw_count > 0 && (s.vertices == VK_NULL_HANDLE || s.indices == VK_NULL_HANDLE || s.commands == VK_NULL_HANDLE))
        throw Error("contour renderer: an indirect surface with " + std::to_string(s.draw_count) + " draws lacks a buffer");
    return impl_->draw([&](VkCommandBuffer cmd) {
        if (s.draw_count == 0) return;
        const VkDeviceSize zero = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &s.vertices, &zero);
        vkCmdBindIndexBuffer(cmd, s.indices, 0, VK_INDEX_TYPE_UINT32);
        for (std::uint32_t i = 0; i < s.draw_count; ++i)
            vkCmdDrawIndexedIndirect(cmd, s.commands, VkDeviceSize{i} * 20, 1, 20);
    }, clip_from_grid);
}

Image ContourIndirectRenderer::render_direct(std::span<const ContourDrawVertex> vertices, std::span<const std::uint32_t> indices,
                                             const glm::mat4& clip_from_grid) {
    if (indices.size() % 3 != 0) throw Error("contour renderer: index count " + std::to_string(indices.size()) + " is not a multiple of 3");
    for (std::size_t i = 0; i < indices.size(); ++i)
        if (indices[i] >= vertices.size())
            throw Error("contour renderer: index " + std::to_string(i) + " = " + std::to_string(indices[i]) + " is out of range");
    if (indices.empty()) return impl_->draw([](VkCommandBuffer) {}, clip_from_grid);
    const gpu::Buffer vb = gpu::Buffer::create(*impl_->context, vertices.size_bytes(), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, gpu::MemoryDomain::kHost);
    const gpu::Buffer ib = gpu::Buffer::create(*impl_->context, indices.size_bytes(), VK_BUFFER_USAGE_INDEX_BUFFER_BIT, gpu::MemoryDomain::kHost);
    std::memcpy(vb.mapped(), vertices.data(), vertices.size_bytes());
    std::memcpy(ib.mapped(), indices.data(), indices.size_bytes());
    return impl_->draw([&](VkCommandBuffer cmd) {
        const VkDeviceSize zero = 0;
        const VkBuffer v = vb.handle();
        vkCmdBindVertexBuffers(cmd, 0, 1, &v, &zero);
        vkCmdBindIndexBuffer(cmd, ib.handle(), 0, VK_INDEX_TYPE_UINT32);
        vkCmdDrawIndexed(cmd, static_cast<std::uint32_t>(indices.size()), 1, 0, 0, 0);
    }, clip_from_grid);
}

}  // namespace tridex::renderer
