// renderer/window/window_blit_layout.hpp - where each eye's image goes in a swapchain image, per stereo output.
#pragma once

#include <array>
#include <cstdint>
#include <utility>

#include "renderer/output/stereo_output.hpp"

namespace tridex::renderer {

/// One blit of an eye's whole image (layer `eye` of the stereo colour image) into the pixel rectangle
/// [x0, x1) x [y0, y1) of layer `dst_layer` of the swapchain image.
struct EyeBlit {
    int eye = 0;        ///< source layer: 0 = left eye, 1 = right eye
    int dst_layer = 0;  ///< destination array layer (1 only for quad's right slot)
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< destination rectangle, pixels (rows from the top)
};

/// The blits of one present: 1 or 2 of them.
struct BlitPlan {
    int count = 0;
    std::array<EyeBlit, 2> blits{};
};

/// The blits that make one present of `output` in a width x height swapchain image:
/// - kSideBySide / kSideBySideHalf: left eye into columns [0, floor(w/2)), right into [floor(w/2), w) (the same
///   split as compose()). Full and half differ only in the window size the app chooses (output_size):
///   full = twice the eye width, so each blit is 1:1; half = the eye width, so each eye is squeezed 2:1;
/// - kTopBottom / kTopBottomHalf: left eye into rows [0, floor(h/2)), right into [floor(h/2), h);
/// - kQuad: left into layer 0, right into layer 1, each the whole image;
/// - kFrameSequential: eye `frame_eye` (FrameSequencer::eye_for_present) over the whole image;
/// - kMono: the left eye (the one rendered view) over the whole image.
/// With swap_eyes the two eyes exchange places (not for kMono, and not for kFrameSequential, whose
/// frame_eye already includes the swap). kAnaglyph has no blit plan (per-pixel mixing: an AnaglyphPass
/// with WindowPresenter::present_image, or compose() on the CPU with present_composed). Throws tridex::Error for kAnaglyph, a size < 1 (or < 2 in
/// the split direction), or frame_eye not 0 or 1.
BlitPlan plan_blits(StereoOutput output, int width, int height, bool swap_eyes = false, int frame_eye = 0);

/// The eye image size (width, height) that makes every blit of plan_blits(output, width, height) 1:1
/// (nearest filter, exact pixels) in a width x height swapchain: side-by-side (full or half)
/// (floor(w/2), h), top-bottom (full or half) (w, floor(h/2)), every other output (w, h). For the half
/// variants this renders each eye directly at the squeezed size; the off-axis frustum maps the whole screen
/// onto the eye image whatever its pixel count, so the result is the anamorphic half-resolution image a 3D TV
/// expects, without a 2:1 filter. Use it to size the OffscreenStereoRenderer for a fullscreen window.
/// Throws tridex::Error when a size is < 1 (or < 2 in the split direction).
std::pair<int, int> eye_size_for(StereoOutput output, int width, int height);

/// The swapchain image array layers `output` needs: 2 for kQuad, 1 otherwise.
std::uint32_t swapchain_layers(StereoOutput output);

}  // namespace tridex::renderer
