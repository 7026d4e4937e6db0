// renderer/output/anaglyph_pass.hpp - the anaglyph of a stereo frame composed on the GPU by a fragment pass.
#pragma once

#include <memory>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "renderer/image/image.hpp"
#include "renderer/output/stereo_output.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::renderer {

/// Mixes the two eye layers of an OffscreenStereoRenderer's colour image into one width x height 8-bit
/// anaglyph image (RGBA or BGRA in memory) on the GPU: a full-screen triangle whose fragment shader
/// (shaders/anaglyph.frag) reads both layers of the same pixel and applies the AnaglyphMethod with the arithmetic of the CPU reference compose()
/// (Dubois: the same sRGB code tables and matrices, mixed in 32-bit floats, so a channel may differ from
/// compose() by 1 where a value lies within float rounding of a code boundary; colour and gray: exact).
/// Move-only; the Context must outlive it, and every renderer it reads must outlive its last submission.
class AnaglyphPass {
public:
    /// Builds the pass for eye images of width x height pixels, writing an image of `format`:
    /// VK_FORMAT_R8G8B8A8_UNORM, or VK_FORMAT_B8G8R8A8_UNORM (a window's swapchain format, so that presenting is
    /// a plain copy instead of a converting blit). Throws tridex::Error when a size is outside
    /// 1..maxImageDimension2D, for another format, or on a Vulkan failure.
    static AnaglyphPass create(gpu::Context& context, int width, int height,
                               VkFormat format = VK_FORMAT_R8G8B8A8_UNORM);

    /// For eye images of width x height pixels from now on: a new output image, readback buffer and framebuffer; the
    /// pipeline is kept (building it is most of create()'s cost). When the size changes it waits for the device to be
    /// idle first; the same size changes nothing. Throws as create() for a size (the pass stays as it was then, as on
    /// a Vulkan failure).
    void resize(int width, int height);

    ~AnaglyphPass();
    AnaglyphPass(AnaglyphPass&&) noexcept;
    AnaglyphPass& operator=(AnaglyphPass&&) noexcept;

    int width() const;   ///< pixels
    int height() const;  ///< pixels
    VkFormat format() const;  ///< of image(), as created

    /// Records into `cmd` (recording, outside a render pass) the pass over `source`'s last frame: its colour
    /// image goes to SHADER_READ_ONLY_OPTIMAL for the pass and back to TRANSFER_SRC_OPTIMAL (as the renderer
    /// promises), image() is written and left in TRANSFER_SRC_OPTIMAL for transfer reads in the same or later
    /// submissions; with `readback` also its copy into a host buffer for read(). `swap_eyes` takes the left
    /// eye from layer 1. The shader runs only over source.last_drawn_rects(); the rest of image() is cleared to
    /// the anaglyph of the clear colour (compose() of OffscreenStereoRenderer::clear_codes()), which is what the
    /// shader would give there. Throws tridex::Error when the renderer's size differs from the pass's or it has not
    /// rendered a frame yet.
    void record(VkCommandBuffer cmd, const OffscreenStereoRenderer& source, AnaglyphMethod method, bool swap_eyes,
                bool readback = false);
    /// Records the pass with readback, submits it, waits, and returns the anaglyph (width x height RGBA, alpha
    /// 255, whatever the format). Same errors as record(), plus Vulkan failures.
    Image compose(const OffscreenStereoRenderer& source, AnaglyphMethod method, bool swap_eyes);
    /// The anaglyph as last copied back by a recorded readback (complete once that submission finished), as RGBA.
    Image read() const;
    /// The single-layer anaglyph image, of format(); TRANSFER_SRC_OPTIMAL after a recorded pass.
    VkImage image() const;

    struct Impl;

private:
    explicit AnaglyphPass(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace tridex::renderer
