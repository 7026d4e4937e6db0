// renderer/camera/stereo_output_mode.hpp - the stereo output modes and anaglyph mixings a display is set to, and
// their names (what the display config names; renderer/output/stereo_output.hpp makes the images).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace tridex::renderer {

/// How the two eye images reach the viewer's eyes. Names (parse_stereo_output / to_string) in brackets.
enum class StereoOutput {
    kQuad,             ///< [quad] one swapchain with 2 image layers (left = layer 0); needs maxImageArrayLayers >= 2
    kFrameSequential,  ///< [frame-sequential] eyes alternate on successive presents; shutter glasses + emitter
    kSideBySide,       ///< [side-by-side] left | right, each at full resolution (width 2w); dual passive projectors
    kSideBySideHalf,   ///< [side-by-side-half] left | right, each squeezed to half width (width w); 3D-TV
    kTopBottom,        ///< [top-bottom] left over right, each at full resolution (height 2h)
    kTopBottomHalf,    ///< [top-bottom-half] left over right, each squeezed to half height (height h); 3D-TV
    kAnaglyph,         ///< [anaglyph] red-cyan glasses: red from the left eye, green + blue from the right
    kMono,             ///< [mono] one view only; the caller renders a single eye
};

/// How an anaglyph is mixed from the left (L) and right (R) eye colours. Each is a 3x3 matrix pair:
/// out = M_L * L + M_R * R, clamped to 0..1.
enum class AnaglyphMethod {
    /// [dubois] Dubois' least-squares red-cyan matrices (E. Dubois, "A projection method to generate
    /// anaglyph stereo images", ICASSP 2001), applied in linear light (sRGB decoded, mixed, re-encoded):
    ///   M_L = [ 0.456  0.500  0.176; -0.040 -0.038 -0.016; -0.015 -0.021 -0.005]
    ///   M_R = [-0.043 -0.088 -0.002;  0.378  0.734 -0.018; -0.072 -0.113  1.226]
    /// The result is clamped to 0..1 and re-encoded with rounding to the nearest 8-bit code. Least ghosting
    /// of the three; colours are shifted.
    kDubois,
    /// [colour] simple colour anaglyph on the stored 8-bit values: out = (L.r, R.g, R.b).
    kColour,
    /// [gray] grey anaglyph on the stored 8-bit values: out = (Y(L), Y(R), Y(R)) with the Rec. 601 luma
    /// Y = 0.299 r + 0.587 g + 0.114 b, rounded to the nearest integer (exact integer arithmetic, halves up).
    /// No colour, least rivalry.
    kGray,
};

/// The name of an output, e.g. "side-by-side-half".
std::string_view to_string(StereoOutput output);
/// The name of an anaglyph method: "dubois", "colour", "gray".
std::string_view to_string(AnaglyphMethod method);
/// Every output, in the order of the enum.
const std::vector<StereoOutput>& all_stereo_outputs();
/// The names of all outputs joined with ", " (for messages and --help).
std::string stereo_output_names();

/// The output called `name` (exact, lower case, as listed in StereoOutput). Throws tridex::Error
/// "unknown stereo output 'x'; valid outputs: quad, frame-sequential, ..." for any other string.
StereoOutput parse_stereo_output(const std::string& name);
/// The anaglyph method called `name` ("dubois", "colour" or "gray"). Throws tridex::Error listing the
/// valid names for any other string.
AnaglyphMethod parse_anaglyph_method(const std::string& name);

}  // namespace tridex::renderer
