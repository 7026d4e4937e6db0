// renderer/scene/overlay_text.hpp - text as screen-space quads for the 2D overlay (stb_easy_font).
#pragma once

#include <string>
#include <string_view>

#include "core/tri_mesh.hpp"

namespace tridex::renderer {

/// Width and height of a block of text, pixels.
struct TextExtent {
    double width_px = 0.0;
    double height_px = 0.0;
};

/// Size of `text` (ASCII, '\n' starts a new line) at `scale` pixels per font unit, pixels: the font
/// is about 6 x 12 units per character cell (stb_easy_font_width / _height times scale); {0, 0} for "".
/// Characters other than '\n' and ASCII 32..126 count as spaces.
/// Throws tridex::Error when scale is not finite and > 0.
TextExtent overlay_text_extent(std::string_view text, double scale);

/// The glyphs of `text` as triangles in pixel coordinates (x right, y down, z 0; "positions" in pixels,
/// NOT metres - for screen-space draws only): stb_easy_font's quads (Sean Barrett, public domain; each
/// quad two triangles), scaled by `scale` about the text origin and moved so the text's top left is at
/// (x_px, y_px). Characters other than '\n' and ASCII 32..126 are drawn (and measured) as spaces. Throws tridex::Error when scale is not
/// finite and > 0, or x_px / y_px are not finite.
TriMesh overlay_text_mesh(std::string_view text, double x_px, double y_px, double scale);

/// The overlay's pixels per font unit in an image image_height_px tall that is shown shown_height_px tall (a scaled
/// image: the present scales it by shown / image): one font unit per 360 shown rows, whole units only, kept in the
/// image at 1 pixel or more so that no stroke drops out. Equal heights give max(1, floor(height / 360)).
/// Throws tridex::Error when a height is < 1.
double overlay_scale_for(int image_height_px, int shown_height_px);

/// An axis-aligned rectangle [x0, x1] x [y0, y1] in pixels as two triangles (z 0), for the overlay panel.
/// Throws tridex::Error when a coordinate is not finite.
TriMesh overlay_rectangle(double x0_px, double y0_px, double x1_px, double y1_px);

}  // namespace tridex::renderer
