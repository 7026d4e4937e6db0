// renderer/window/window_presenter.hpp - stereo frames into a window's swapchain: GPU blits per output, vsync, timing.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "renderer/output/frame_sequencer.hpp"
#include "renderer/image/image.hpp"
#include "renderer/output/stereo_output.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "renderer/window/window_frame_timing.hpp"
#include "renderer/window/window_glfw.hpp"

namespace tridex::renderer {

/// How a WindowPresenter shows frames.
struct PresenterOptions {
    StereoOutput output = StereoOutput::kSideBySide;
    /// FIFO presentation (one image per display refresh, no tearing). false: mailbox/immediate if offered.
    bool vsync = true;
    /// Exchange the eyes in every output (for frame-sequential: the image shown for each shutter).
    bool swap_eyes = false;
    /// The display's refresh rate in Hz, for the frame-sequential sequencer's timing figures (120 on the wall).
    double refresh_hz = 60.0;
    /// Copy every presented swapchain image back to the host (last_capture()); for tests and screenshots.
    /// Needs TRANSFER_SRC swapchain usage and a B8G8R8A8/R8G8B8A8 UNORM swapchain format.
    bool capture = false;
};

/// Presents stereo frames of an OffscreenStereoRenderer in a Window through a vsync'd swapchain, with GPU
/// blits from the renderer's 2-layer colour image (no CPU round trip) laid out by plan_blits():
/// quad = a 2-layer swapchain (only when the surface reports maxImageArrayLayers >= 2), frame-sequential =
/// the two eyes on two successive presents (FrameSequencer: hook naming the shutter, swap-eyes switch),
/// side-by-side / top-bottom (full or half) = two blits into halves (scaled with a linear filter when the
/// sizes differ), mono = the left layer. Anaglyph mixes pixels: an AnaglyphPass recorded into the present
/// (present_image() with record_first) composes it on the GPU; a CPU-composed image goes through
/// present_composed(), which uploads and blits it.
/// The swapchain is recreated when the window's framebuffer size changes or presentation reports it
/// out of date; nothing is presented while the window is minimised (size 0).
/// Each present is one command buffer (timestamped: blit_gpu_ms) submitted after the image is acquired; two
/// presents are in flight (each with its own command buffer, fence, acquire semaphore and queries): a present
/// waits only for the one two before it (and, with capture, for itself), so the renderer records the next frame
/// while the GPU still draws and blits this one (one queue keeps them in order). With
/// vsync, acquiring blocks while every swapchain image is queued for display: that is where the display's
/// rate paces the caller. Move-only; the Context and the Window must outlive it and the Window must not be
/// moved while it exists. Main thread only (GLFW windows).
class WindowPresenter {
public:
    /// Creates surface and swapchain for `window` (size = its framebuffer size). Throws tridex::Error when
    /// the Context was not made with window_context_options(), the output is kQuad and the surface reports
    /// maxImageArrayLayers < 2 (check_output_support's message, listing the outputs that will work), capture
    /// is asked for but unsupported, the window is minimised, or on a Vulkan failure.
    static WindowPresenter create(gpu::Context& context, Window& window, const PresenterOptions& options);

    ~WindowPresenter();
    WindowPresenter(WindowPresenter&&) noexcept;
    WindowPresenter& operator=(WindowPresenter&&) noexcept;

    /// Presents the renderer's last frame (render() or draw()) for the output: 2 presents for frame-sequential
    /// (the sequencer's eye order), 1 otherwise. Returns the number of images presented (0 while minimised).
    /// Throws tridex::Error when the output is kAnaglyph (use present_composed), the renderer has not rendered a
    /// frame yet, or on a Vulkan failure.
    int present(const OffscreenStereoRenderer& renderer);
    /// Uploads a CPU-composed image (e.g. compose(kAnaglyph, ...)) and blits it over the whole swapchain image
    /// (every layer; scaled with a linear filter when the sizes differ). Returns 1, or 0 while minimised.
    /// Throws tridex::Error for an empty or inconsistent image or on a Vulkan failure.
    int present_composed(const Image& image);
    /// Puts `image` (single layer, width x height, `format` R8G8B8A8_UNORM or B8G8R8A8_UNORM, TRANSFER_SRC usage)
    /// over the whole swapchain image, every layer: copied when its format and size are the swapchain's, else
    /// blitted (linear filter when the sizes differ). `record_first`, when set, is recorded into the present's
    /// command buffer before that (outside a render pass) and must leave `image` written and in
    /// TRANSFER_SRC_OPTIMAL (e.g. AnaglyphPass::record); without it `image` must already be so from a finished
    /// submission. Returns 1, or 0 while minimised. Throws tridex::Error for a null image, a size < 1 or another
    /// format, or on a Vulkan failure (and whatever record_first throws).
    int present_image(VkImage image, VkFormat format, int width, int height,
                      const std::function<void(VkCommandBuffer)>& record_first = {});

    StereoOutput output() const;            ///< the output shown
    FrameSequencer& sequencer();            ///< frame-sequential eye order, emitter hook (on_eye) and swap switch
    const FrameSequencer& sequencer() const;  ///< the same, read-only (missed refreshes, shown shutters)
    /// Exchanges the eyes from the next present on (same switch as sequencer().set_swap_eyes()).
    void set_swap_eyes(bool swap);
    bool swap_eyes() const;                 ///< true when the eyes are exchanged
    VkExtent2D extent() const;              ///< current swapchain size, pixels
    VkFormat format() const;                ///< swapchain image format
    const char* present_mode() const;       ///< "fifo" with vsync
    std::uint32_t max_image_array_layers() const;  ///< what the surface reports (>= 2 allows quad)
    std::uint64_t presents() const;         ///< images presented so far
    std::uint64_t recreations() const;      ///< swapchain recreations so far (resizes, out-of-date)
    int last_eye() const;                   ///< eye of the last single-eye present (0/1); -1 when both eyes were shown
    /// Render / present-pass GPU times and present intervals, ms. render_gpu_ms holds the renderer's latest
    /// finished frame at each present (none while no frame has finished); a present pass's blit_gpu_ms is added
    /// once it is seen finished (finish() waits for those in flight).
    const FrameTimings& timings() const;
    /// Waits for the presents in flight and records their present-pass GPU times. Throws tridex::Error when the
    /// GPU takes over 10 s.
    void finish();
    /// The last presented image read back (RGBA, swapchain size) for swapchain layer `layer`; empty unless
    /// PresenterOptions::capture. Throws tridex::Error for a layer outside the swapchain's layers.
    const Image& last_capture(int layer = 0) const;

    struct Impl;

private:
    explicit WindowPresenter(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace tridex::renderer
