// renderer/stereo/stereo_target.hpp - the 2-layer colour + depth image a stereo frame is drawn into.
#pragma once

#include <vector>

#include "gpu/buffer.hpp"
#include "gpu/context.hpp"
#include "gpu/image_array.hpp"
#include "gpu/unique_handle.hpp"
#include "renderer/image/image.hpp"
#include "renderer/stereo/stereo_pipeline.hpp"

namespace tridex::renderer {

/// Colour (RGBA8, layer 0 = left eye, layer 1 = right eye; attachment, transfer source, sampled and storage) and
/// depth (D32; attachment and sampled, for the ambient-occlusion pass) 2-layer images of
/// width x height pixels, the framebuffers `pipeline`'s strategy needs (pass-per-eye: one per layer over
/// single-layer views; multiview: one over the array views with 1 layer; instanced-layer: one over the
/// array views with 2 layers), and a host buffer the colour layers are copied into for readback.
/// Move-only; the Context and the StereoPipeline's render pass must outlive it.
class StereoTarget {
public:
    /// Throws tridex::Error when width or height is not in 1..maxImageDimension2D, or on a Vulkan failure.
    static StereoTarget create(const gpu::Context& context, const StereoPipeline& pipeline, int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    /// Framebuffers, in the order of the render pass instances of one frame (1 or 2).
    const std::vector<gpu::UniqueFramebuffer>& framebuffers() const { return framebuffers_; }
    VkImage colour_image() const { return colour_.handle(); }
    /// A 2D_ARRAY view of both colour layers (for sampling the eyes, e.g. the anaglyph pass).
    VkImageView colour_array_view() const { return colour_.array_view(); }
    /// A 2D_ARRAY view (depth aspect) of both depth layers, for sampling.
    VkImageView depth_array_view() const { return depth_.array_view(); }
    /// 2D_ARRAY views of one layer (0 or 1) of the colour / depth image: for passes that touch one eye's layer
    /// while the other is in another layout (pass per eye).
    VkImageView colour_layer_array_view(int layer) const { return colour_layer_views_.at(static_cast<std::size_t>(layer)).get(); }
    VkImageView depth_layer_array_view(int layer) const { return depth_layer_views_.at(static_cast<std::size_t>(layer)).get(); }
    VkBuffer readback_buffer() const { return readback_.handle(); }
    /// Layer `layer` (0 or 1) of the last frame copied to readback_buffer(), as an Image.
    /// Valid after the frame's submission has completed.
    Image read_layer(int layer) const;

private:
    int width_ = 0, height_ = 0;
    gpu::ImageArray colour_, depth_;
    std::vector<gpu::UniqueImageView> colour_layer_views_, depth_layer_views_;
    std::vector<gpu::UniqueFramebuffer> framebuffers_;
    gpu::Buffer readback_;
};

}  // namespace tridex::renderer
