// renderer/stereo/stereo_target.cpp - stereo attachments, framebuffers per strategy, readback.
#include "renderer/stereo/stereo_target.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"
#include "gpu/check.hpp"

namespace tridex::renderer {
namespace {

gpu::UniqueFramebuffer make_framebuffer(VkDevice device, VkRenderPass pass, VkImageView colour, VkImageView depth,
                                        int width, int height, std::uint32_t layers) {
    const VkImageView views[2] = {colour, depth};
    VkFramebufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
    info.renderPass = pass;
    info.attachmentCount = 2;
    info.pAttachments = views;
    info.width = static_cast<std::uint32_t>(width);
    info.height = static_cast<std::uint32_t>(height);
    info.layers = layers;
    VkFramebuffer fb = VK_NULL_HANDLE;
    gpu::check(vkCreateFramebuffer(device, &info, nullptr, &fb), "vkCreateFramebuffer");
    return gpu::UniqueFramebuffer(device, fb);
}

gpu::UniqueImageView layer_array_view(VkDevice device, const gpu::ImageArray& image, std::uint32_t layer) {
    VkImageViewCreateInfo v{};
    v.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
    v.image = image.handle();
    v.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    v.format = image.info().format;
    v.subresourceRange = {image.info().aspect, 0, 1, layer, 1};
    VkImageView view = VK_NULL_HANDLE;
    gpu::check(vkCreateImageView(device, &v, nullptr, &view), "vkCreateImageView");
    return gpu::UniqueImageView(device, view);
}

}  // namespace

StereoTarget StereoTarget::create(const gpu::Context& context, const StereoPipeline& pipeline, int width, int height) {
    const auto max_dim = static_cast<int>(std::min<std::uint32_t>(context.properties().limits.maxImageDimension2D,
                                                                   context.properties().limits.maxFramebufferWidth));
    if (width < 1 || height < 1 || width > max_dim || height > max_dim)
        throw Error("renderer: stereo target size " + std::to_string(width) + "x" + std::to_string(height) +
                    " must be within 1.." + std::to_string(max_dim));
    StereoTarget t;
    t.width_ = width;
    t.height_ = height;
    gpu::ImageArrayInfo info;
    info.width = static_cast<std::uint32_t>(width);
    info.height = static_cast<std::uint32_t>(height);
    info.layers = 2;
    info.format = kStereoColourFormat;
    info.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                 VK_IMAGE_USAGE_STORAGE_BIT;
    info.aspect = VK_IMAGE_ASPECT_COLOR_BIT;
    t.colour_ = gpu::ImageArray::create(context, info);
    info.format = kStereoDepthFormat;
    info.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    info.aspect = VK_IMAGE_ASPECT_DEPTH_BIT;
    t.depth_ = gpu::ImageArray::create(context, info);

    const VkDevice device = context.device();
    for (std::uint32_t layer = 0; layer < 2; ++layer) {
        t.colour_layer_views_.push_back(layer_array_view(device, t.colour_, layer));
        t.depth_layer_views_.push_back(layer_array_view(device, t.depth_, layer));
    }
    const VkRenderPass pass = pipeline.render_pass();
    switch (pipeline.strategy()) {
        case EyeStrategy::kPassPerEye:
            for (std::uint32_t eye = 0; eye < 2; ++eye)
                t.framebuffers_.push_back(make_framebuffer(device, pass, t.colour_.layer_view(eye),
                                                           t.depth_.layer_view(eye), width, height, 1));
            break;
        case EyeStrategy::kMultiview:  // the view mask selects the layers; framebuffer layers must be 1
            t.framebuffers_.push_back(
                make_framebuffer(device, pass, t.colour_.array_view(), t.depth_.array_view(), width, height, 1));
            break;
        case EyeStrategy::kInstancedLayer:
            t.framebuffers_.push_back(
                make_framebuffer(device, pass, t.colour_.array_view(), t.depth_.array_view(), width, height, 2));
            break;
    }
    t.readback_ = gpu::Buffer::create(context, static_cast<VkDeviceSize>(width) * height * 4 * 2,
                                      VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryDomain::kHost);
    return t;
}

Image StereoTarget::read_layer(int layer) const {
    if (layer < 0 || layer > 1) throw Error("StereoTarget::read_layer: layer must be 0 or 1");
    const std::size_t bytes = static_cast<std::size_t>(width_) * height_ * 4;
    Image img{width_, height_, std::vector<std::uint8_t>(bytes)};
    readback_.read(img.rgba.data(), bytes, bytes * static_cast<std::size_t>(layer));
    return img;
}

}  // namespace tridex::renderer
