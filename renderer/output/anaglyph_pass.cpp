// renderer/output/anaglyph_pass.cpp - render pass, pipeline and tables of the GPU anaglyph; recording and readback.
#include "renderer/output/anaglyph_pass.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "gpu/barrier.hpp"
#include "gpu/buffer.hpp"
#include "gpu/check.hpp"
#include "gpu/descriptor_sets.hpp"
#include "gpu/graphics_pipeline.hpp"
#include "gpu/image_array.hpp"
#include "gpu/shader_module.hpp"
#include "gpu/unique_handle.hpp"
#include "renderer/output/anaglyph_tables.hpp"
#include "renderer/output/stereo_output.hpp"
#include "renderer/stereo/stereo_pipeline.hpp"
#include "shaders/spirv.hpp"

namespace tridex::renderer {
namespace {

// The anaglyph of two pixels of the renderer's clear colour (compose(), the CPU reference), as a clear value whose
// UNORM8 conversion gives back its codes.
VkClearValue background_clear(AnaglyphMethod method, bool swap_eyes) {
    const std::array<std::uint8_t, 3> c = OffscreenStereoRenderer::clear_codes();
    const Image bg{1, 1, {c[0], c[1], c[2], 255}};
    ComposeOptions co;
    co.anaglyph = method;
    co.swap_eyes = swap_eyes;
    const Image a = compose(StereoOutput::kAnaglyph, bg, bg, co);
    VkClearValue v{};
    for (int i = 0; i < 4; ++i) v.color.float32[i] = i < 3 ? static_cast<float>(a.rgba[i]) / 255.0f : 1.0f;
    return v;
}

using UniqueSampler = gpu::UniqueHandle<VkSampler, vkDestroySampler>;

/// shaders/anaglyph.frag `Tables` (std140: vec4 rows, float tables packed 4 to a vec4).
struct AnaglyphUniform {
    float left_rows[3][4];
    float right_rows[3][4];
    float to_linear[256];
};

/// shaders/anaglyph.frag `Mix`.
struct MixConstants {
    std::int32_t method = 0;  ///< 0 Dubois, 1 colour, 2 gray
    std::int32_t swap_eyes = 0;
};

std::int32_t method_index(AnaglyphMethod m) {
    switch (m) {
    case AnaglyphMethod::kDubois: return 0;
    case AnaglyphMethod::kColour: return 1;
    case AnaglyphMethod::kGray: return 2;
    }
    return 0;
}

AnaglyphUniform make_uniform() {
    AnaglyphUniform u{};
    const AnaglyphMatrices& m = dubois_matrices();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            u.left_rows[r][c] = static_cast<float>(m.left[r][c]);
            u.right_rows[r][c] = static_cast<float>(m.right[r][c]);
        }
    const SrgbCodeTables& t = srgb_code_tables();
    for (int i = 0; i < 256; ++i) u.to_linear[i] = static_cast<float>(t.to_linear[i]);
    return u;
}

gpu::UniqueRenderPass make_render_pass(VkDevice device, VkFormat format) {
    VkAttachmentDescription att{};
    att.format = format;
    att.samples = VK_SAMPLE_COUNT_1_BIT;
    att.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;  // to the anaglyph of the eyes' clear colour; the triangle draws the rest
    att.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att.finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    const VkAttachmentReference colour{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &colour;
    // Before: earlier transfer reads of the image (blits, readback) finish. After: the writes are visible to
    // transfer reads.
    VkSubpassDependency deps[2]{};
    deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    deps[0].dstSubpass = 0;
    deps[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    deps[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    deps[0].srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    deps[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    deps[1].srcSubpass = 0;
    deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    deps[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    deps[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    deps[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    deps[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    VkRenderPassCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
    info.attachmentCount = 1;
    info.pAttachments = &att;
    info.subpassCount = 1;
    info.pSubpasses = &subpass;
    info.dependencyCount = 2;
    info.pDependencies = deps;
    VkRenderPass pass = VK_NULL_HANDLE;
    gpu::check(vkCreateRenderPass(device, &info, nullptr, &pass), "vkCreateRenderPass");
    return gpu::UniqueRenderPass(device, pass);
}

gpu::UniquePipeline make_pipeline(const gpu::Context& context, VkRenderPass pass, VkPipelineLayout layout) {
    const gpu::UniqueShaderModule vs = gpu::create_shader_module(context, shaders::spirv("fullscreen_vert"));
    const gpu::UniqueShaderModule fs = gpu::create_shader_module(context, shaders::spirv("anaglyph_frag"));
    gpu::GraphicsPipelineDesc d;  // a full-screen triangle: no vertex buffers, no depth, no blending
    d.vertex = vs.get();
    d.fragment = fs.get();
    // Viewport and scissor are dynamic: the triangle is cut to the pixels the eyes' frame drew (record()).
    return gpu::create_graphics_pipeline(context.device(), pass, layout, d);
}

}  // namespace

struct AnaglyphPass::Impl {
    gpu::Context* context = nullptr;
    int width = 0, height = 0;
    VkFormat format = kStereoColourFormat;  // of output
    gpu::ImageArray output;
    gpu::Buffer tables;    // AnaglyphUniform
    gpu::Buffer readback;  // width * height * 4 bytes
    UniqueSampler sampler;
    gpu::UniqueDescriptorSetLayout set_layout;
    gpu::UniqueDescriptorPool pool;
    VkDescriptorSet set = VK_NULL_HANDLE;  // freed with the pool
    VkImageView bound_view = VK_NULL_HANDLE;
    std::uint64_t bound_generation = 0;  // the source's target_generation() when bound_view was bound
    gpu::UniquePipelineLayout layout;
    gpu::UniqueRenderPass render_pass;
    gpu::UniqueFramebuffer framebuffer;
    gpu::UniquePipeline pipeline;

    ~Impl() {
        try {
            if (context) context->wait_idle();
        } catch (const Error& e) {
            std::fprintf(stderr, "anaglyph pass: %s\n", e.what());
        }
    }

    void check_source(const OffscreenStereoRenderer& source) const {
        if (source.width() != width || source.height() != height)
            throw Error("anaglyph pass: the renderer's eye images are " + std::to_string(source.width()) + "x" +
                        std::to_string(source.height()) + ", the pass was made for " + std::to_string(width) + "x" +
                        std::to_string(height));
        if (source.frames_rendered() == 0)
            throw Error("anaglyph pass: the renderer has not rendered a frame yet (call render() or draw() first)");
    }

    // The size-dependent parts, for eye images of w x h pixels (render_pass made first).
    void make_sized(int w, int h) {
        const VkDevice device = context->device();
        gpu::ImageArrayInfo info;
        info.width = static_cast<std::uint32_t>(w);
        info.height = static_cast<std::uint32_t>(h);
        info.layers = 1;
        info.format = format;
        info.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        // Made aside and swapped in at the end, so that a failure leaves the pass as it was.
        gpu::ImageArray next_output = gpu::ImageArray::create(*context, info);
        gpu::Buffer next_readback = gpu::Buffer::create(*context, static_cast<VkDeviceSize>(w) * h * 4,
                                                        VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryDomain::kHost);
        const VkImageView view = next_output.layer_view(0);
        VkFramebufferCreateInfo fb{};
        fb.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
        fb.renderPass = render_pass.get();
        fb.attachmentCount = 1;
        fb.pAttachments = &view;
        fb.width = static_cast<std::uint32_t>(w);
        fb.height = static_cast<std::uint32_t>(h);
        fb.layers = 1;
        VkFramebuffer made = VK_NULL_HANDLE;
        gpu::check(vkCreateFramebuffer(device, &fb, nullptr, &made), "vkCreateFramebuffer");
        framebuffer = gpu::UniqueFramebuffer(device, made);  // the old one goes before the image it views
        output = std::move(next_output);
        readback = std::move(next_readback);
        width = w;
        height = h;
    }

    // Binds the source's colour view, unless it is bound already (the same handle of the same target: a resize can
    // give a new view the handle value of a destroyed one).
    void bind_source(VkImageView view, std::uint64_t generation) {
        if (view == bound_view && generation == bound_generation) return;
        VkDescriptorImageInfo image{sampler.get(), view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        VkWriteDescriptorSet w{};
        w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        w.dstSet = set;
        w.dstBinding = 0;
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        w.pImageInfo = &image;
        vkUpdateDescriptorSets(context->device(), 1, &w, 0, nullptr);
        bound_view = view;
        bound_generation = generation;
    }
};

namespace {

// Throws tridex::Error for eye images outside 1..maxImageDimension2D (and the framebuffer limit).
void check_size(const gpu::Context& context, int width, int height) {
    const auto max_dim = static_cast<int>(std::min<std::uint32_t>(context.properties().limits.maxImageDimension2D,
                                                                   context.properties().limits.maxFramebufferWidth));
    if (width < 1 || height < 1 || width > max_dim || height > max_dim)
        throw Error("anaglyph pass: size " + std::to_string(width) + "x" + std::to_string(height) +
                    " must be within 1.." + std::to_string(max_dim));
}

}  // namespace

AnaglyphPass AnaglyphPass::create(gpu::Context& context, int width, int height, VkFormat format) {
    if (format != VK_FORMAT_R8G8B8A8_UNORM && format != VK_FORMAT_B8G8R8A8_UNORM)
        throw Error("anaglyph pass: output format " + std::to_string(static_cast<int>(format)) +
                    " is neither R8G8B8A8_UNORM nor B8G8R8A8_UNORM");
    check_size(context, width, height);
    auto impl = std::make_unique<Impl>();
    Impl& im = *impl;
    im.context = &context;
    im.width = width;
    im.height = height;
    im.format = format;
    const VkDevice device = context.device();

    const AnaglyphUniform u = make_uniform();
    im.tables = gpu::Buffer::create(context, sizeof u, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryDomain::kHost);
    im.tables.write(&u, sizeof u);

    VkSamplerCreateInfo si{};
    si.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO;
    si.magFilter = si.minFilter = VK_FILTER_NEAREST;
    si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler = VK_NULL_HANDLE;
    gpu::check(vkCreateSampler(device, &si, nullptr, &sampler), "vkCreateSampler");
    im.sampler = UniqueSampler(device, sampler);

    VkDescriptorSetLayoutBinding bindings[2]{};
    bindings[0].binding = 0;
    bindings[0].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    bindings[0].descriptorCount = 1;
    bindings[0].stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT;
    bindings[1] = bindings[0];
    bindings[1].binding = 1;
    bindings[1].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    VkDescriptorSetLayoutCreateInfo set_info{};
    set_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    set_info.bindingCount = 2;
    set_info.pBindings = bindings;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    gpu::check(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
    im.set_layout = gpu::UniqueDescriptorSetLayout(device, set_layout);

    im.pool = gpu::allocate_descriptor_sets(
        device, {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1}, {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1}}, set_layout, 1,
        &im.set);
    const VkDescriptorBufferInfo buffer{im.tables.handle(), 0, sizeof(AnaglyphUniform)};
    VkWriteDescriptorSet w{};
    w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    w.dstSet = im.set;
    w.dstBinding = 1;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    w.pBufferInfo = &buffer;
    vkUpdateDescriptorSets(device, 1, &w, 0, nullptr);

    const VkPushConstantRange push{VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(MixConstants)};
    VkPipelineLayoutCreateInfo layout_info{};
    layout_info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout;
    layout_info.pushConstantRangeCount = 1;
    layout_info.pPushConstantRanges = &push;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    gpu::check(vkCreatePipelineLayout(device, &layout_info, nullptr, &layout), "vkCreatePipelineLayout");
    im.layout = gpu::UniquePipelineLayout(device, layout);

    im.render_pass = make_render_pass(device, format);
    im.make_sized(width, height);
    im.pipeline = make_pipeline(context, im.render_pass.get(), layout);
    return AnaglyphPass(std::move(impl));
}

void AnaglyphPass::resize(int width, int height) {
    Impl& im = *impl_;
    check_size(*im.context, width, height);
    if (width == im.width && height == im.height) return;
    im.context->wait_idle();  // no pass in flight writes or reads the old image
    im.make_sized(width, height);
}

AnaglyphPass::AnaglyphPass(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
AnaglyphPass::~AnaglyphPass() = default;
AnaglyphPass::AnaglyphPass(AnaglyphPass&&) noexcept = default;
AnaglyphPass& AnaglyphPass::operator=(AnaglyphPass&&) noexcept = default;

int AnaglyphPass::width() const { return impl_->width; }
int AnaglyphPass::height() const { return impl_->height; }
VkFormat AnaglyphPass::format() const { return impl_->format; }
VkImage AnaglyphPass::image() const { return impl_->output.handle(); }

void AnaglyphPass::record(VkCommandBuffer cmd, const OffscreenStereoRenderer& source, AnaglyphMethod method,
                          bool swap_eyes, bool readback) {
    Impl& im = *impl_;
    im.check_source(source);
    im.bind_source(source.colour_array_view(), source.target_generation());
    const VkImage eyes = source.colour_image();
    gpu::image_barrier(cmd, eyes, 2, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                   VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT,
                   VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                   VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
    VkRenderPassBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
    begin.renderPass = im.render_pass.get();
    begin.framebuffer = im.framebuffer.get();
    begin.renderArea = {{0, 0}, {static_cast<std::uint32_t>(im.width), static_cast<std::uint32_t>(im.height)}};
    // Where the frame drew nothing both eyes hold the clear colour: the pass clears to its anaglyph (the CPU
    // reference's, so it is exact) and runs the shader only over the pixels the frame drew.
    const VkClearValue clear = background_clear(method, swap_eyes);
    begin.clearValueCount = 1;
    begin.pClearValues = &clear;
    vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
    const std::vector<PixelRect>& drawn = source.last_drawn_rects();
    if (!drawn.empty()) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, im.pipeline.get());
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, im.layout.get(), 0, 1, &im.set, 0, nullptr);
        const MixConstants mix{method_index(method), swap_eyes ? 1 : 0};
        vkCmdPushConstants(cmd, im.layout.get(), VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof mix, &mix);
        const VkViewport viewport{0.0f, 0.0f, static_cast<float>(im.width), static_cast<float>(im.height), 0.0f, 1.0f};
        vkCmdSetViewport(cmd, 0, 1, &viewport);
        for (const PixelRect& r : drawn) {  // overlapping rectangles shade a pixel twice, to the same value
            const int x0 = std::clamp(r.x0, 0, im.width), y0 = std::clamp(r.y0, 0, im.height);
            const int x1 = std::clamp(r.x1, x0, im.width), y1 = std::clamp(r.y1, y0, im.height);
            if (x1 == x0 || y1 == y0) continue;
            const VkRect2D scissor{{x0, y0},
                                   {static_cast<std::uint32_t>(x1 - x0), static_cast<std::uint32_t>(y1 - y0)}};
            vkCmdSetScissor(cmd, 0, 1, &scissor);
            vkCmdDraw(cmd, 3, 1, 0, 0);
        }
    }
    vkCmdEndRenderPass(cmd);
    // The renderer's image back to the layout it promises; its next render pass waits for transfer reads,
    // which this barrier's reads chain into.
    gpu::image_barrier(cmd, eyes, 2, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 0,
                   VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    if (!readback) return;
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {static_cast<std::uint32_t>(im.width), static_cast<std::uint32_t>(im.height), 1};
    vkCmdCopyImageToBuffer(cmd, im.output.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, im.readback.handle(), 1,
                           &copy);
    VkMemoryBarrier host{};
    host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &host, 0, nullptr, 0,
                         nullptr);
}

Image AnaglyphPass::compose(const OffscreenStereoRenderer& source, AnaglyphMethod method, bool swap_eyes) {
    impl_->check_source(source);
    impl_->context->submit_and_wait([&](VkCommandBuffer cmd) { record(cmd, source, method, swap_eyes, true); });
    return read();
}

Image AnaglyphPass::read() const {
    const Impl& im = *impl_;
    const std::size_t bytes = static_cast<std::size_t>(im.width) * im.height * 4;
    Image img{im.width, im.height, std::vector<std::uint8_t>(bytes)};
    im.readback.read(img.rgba.data(), bytes);
    if (im.format == VK_FORMAT_B8G8R8A8_UNORM) swap_red_blue(img.rgba);
    return img;
}

}  // namespace tridex::renderer
