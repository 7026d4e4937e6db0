// renderer/scene/overlay_text.cpp - stb_easy_font quads -> TriMesh in pixels.
#include "renderer/scene/overlay_text.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace tridex::renderer {
namespace {

void check_scale(double scale) {
    if (!std::isfinite(scale) || scale <= 0.0) throw Error("overlay text: scale must be finite and > 0");
}

// stb_easy_font wants a mutable, NUL-terminated string of '\n' and ASCII 32..126 (it indexes its glyph
// table with c - 32 unchecked), so every other character becomes a space.
std::vector<char> c_string(std::string_view text) {
    std::vector<char> s;
    s.reserve(text.size() + 1);
    for (char c : text) s.push_back(c == '\n' || (c >= 32 && c <= 126) ? c : ' ');
    s.push_back('\0');
    return s;
}

}  // namespace

double overlay_scale_for(int image_height_px, int shown_height_px) {
    if (image_height_px < 1 || shown_height_px < 1)
        throw Error("overlay text: image and shown heights must be >= 1 pixel, got " + std::to_string(image_height_px) +
                    " and " + std::to_string(shown_height_px));
    const double shown_scale = std::floor(shown_height_px / 360.0);
    return std::max(1.0, shown_scale * image_height_px / shown_height_px);
}

TextExtent overlay_text_extent(std::string_view text, double scale) {
    check_scale(scale);
    std::vector<char> s = c_string(text);
    if (text.empty()) return {};
    return TextExtent{stb_easy_font_width(s.data()) * scale, stb_easy_font_height(s.data()) * scale};
}

TriMesh overlay_text_mesh(std::string_view text, double x_px, double y_px, double scale) {
    check_scale(scale);
    if (!std::isfinite(x_px) || !std::isfinite(y_px)) throw Error("overlay text: position must be finite");
    std::vector<char> s = c_string(text);
    // stb_easy_font vertices: x, y, z (float) + 4 colour bytes = 16 bytes; about 270 bytes per character.
    struct FontVertex {
        float x, y, z;
        unsigned char rgba[4];
    };
    static_assert(sizeof(FontVertex) == 16);
    std::vector<FontVertex> buffer(text.size() * 64 + 64);
    const int quads = stb_easy_font_print(0.0f, 0.0f, s.data(), nullptr, buffer.data(),
                                          static_cast<int>(buffer.size() * sizeof(FontVertex)));
    TriMesh m;
    m.positions.reserve(static_cast<std::size_t>(quads) * 4);
    for (int q = 0; q < quads; ++q) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (int k = 0; k < 4; ++k) {
            const FontVertex& v = buffer[static_cast<std::size_t>(q) * 4 + k];
            m.positions.push_back(Vec3(x_px + scale * v.x, y_px + scale * v.y, 0.0));
        }
        m.triangles.push_back({base, base + 1, base + 2});
        m.triangles.push_back({base, base + 2, base + 3});
    }
    return m;
}

TriMesh overlay_rectangle(double x0_px, double y0_px, double x1_px, double y1_px) {
    if (!std::isfinite(x0_px) || !std::isfinite(y0_px) || !std::isfinite(x1_px) || !std::isfinite(y1_px))
        throw Error("overlay rectangle: corners must be finite");
    TriMesh m;
    m.positions = {Vec3(x0_px, y0_px, 0.0), Vec3(x1_px, y0_px, 0.0), Vec3(x1_px, y1_px, 0.0), Vec3(x0_px, y1_px, 0.0)};
    m.triangles = {{0u, 1u, 2u}, {0u, 2u, 3u}};
    return m;
}

}  // namespace tridex::renderer
