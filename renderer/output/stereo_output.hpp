// renderer/output/stereo_output.hpp - stereo output modes: what a display shows made from the two eye images (the
// modes and their names: renderer/camera/stereo_output_mode.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "renderer/camera/stereo_output_mode.hpp"
#include "renderer/image/image.hpp"

namespace tridex::renderer {

/// Options of compose().
struct ComposeOptions {
    /// Swap the eyes: the left eye's image goes where the right one would and vice versa (every output but
    /// mono). Fixes glasses or projectors that are wired the wrong way round.
    bool swap_eyes = false;
    /// The anaglyph mixing (kAnaglyph only).
    AnaglyphMethod anaglyph = AnaglyphMethod::kDubois;
    /// The display's eye slot produced (kQuad: the swapchain layer; kFrameSequential: the shutter that is open
    /// for this present, FrameSequencer::shutter_for_present): 0 = left, 1 = right. Ignored by other outputs.
    int eye_slot = 0;
};

/// False only for kMono: the caller renders one view (e.g. the head centre with eye separation 0) and
/// skips the second eye's work.
bool needs_both_eyes(StereoOutput output);

/// Size (width, height) in pixels of one composed image for eye images of eye_width x eye_height:
/// side-by-side (2w, h), top-bottom (w, 2h), the half-resolution variants, anaglyph, mono, quad (per layer)
/// and frame-sequential (per present) (w, h). Throws tridex::Error when a size is < 1.
std::pair<int, int> output_size(StereoOutput output, int eye_width, int eye_height);
/// The inverse of output_size: the size of each eye's image that fills an output image of output_width x
/// output_height pixels (side by side: half the width; top-bottom: half the height; otherwise the same), at least
/// 1x1. Throws tridex::Error for an output smaller than 1x1.
std::pair<int, int> eye_size_for_output(StereoOutput output, int output_width, int output_height);

/// Whether a presentation surface can show `output`.
struct OutputSupport {
    bool supported = true;
    std::string message;  ///< empty when supported; otherwise one line naming what is missing and the alternatives
};

/// The outputs a surface whose VkSurfaceCapabilitiesKHR reports `max_image_array_layers` can show: all of
/// them when it is >= 2, all but kQuad otherwise.
std::vector<StereoOutput> supported_outputs(std::uint32_t max_image_array_layers);
/// Whether `output` works with `max_image_array_layers` (only kQuad needs >= 2 layers). When not, the
/// message says "stereo output 'quad' needs a swapchain with 2 image layers but the surface reports
/// maxImageArrayLayers = 1; outputs that will work: frame-sequential, ...".
OutputSupport check_output_support(StereoOutput output, std::uint32_t max_image_array_layers);

/// Resamples `image` to new_width x new_height with a box (area-average) filter on the stored 8-bit values,
/// each output pixel the coverage-weighted mean of the source pixels under it, rounded to nearest (a 2:1
/// squeeze averages pixel pairs: (a + b + 1) / 2 in integers). Used for the half-resolution outputs.
/// Throws tridex::Error when the image is empty/inconsistent or a new size is < 1.
Image resample_box(const Image& image, int new_width, int new_height);

/// What the display shows for one frame of `output`, built from the two eye images (same size w x h):
/// - kSideBySide / kTopBottom: the eyes next to / above each other at full size (left first, unless swapped);
/// - kSideBySideHalf / kTopBottomHalf: each eye squeezed to half width / height (resample_box; for odd sizes
///   the first half gets floor(w / 2) and the second the rest), total size w x h;
/// - kAnaglyph: per pixel options.anaglyph (see AnaglyphMethod), alpha 255;
/// - kQuad / kFrameSequential: the image for display slot options.eye_slot (left for slot 0, right for
///   slot 1; the other way round when swap_eyes);
/// - kMono: `left` (the one rendered view); `right` is ignored and may be empty.
/// Throws tridex::Error when an image that is used is empty or inconsistent, the sizes differ, or
/// eye_slot is not 0 or 1.
Image compose(StereoOutput output, const Image& left, const Image& right, const ComposeOptions& options = {});

}  // namespace tridex::renderer
