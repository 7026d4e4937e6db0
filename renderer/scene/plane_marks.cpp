// renderer/scene/plane_marks.cpp - two-sided rectangles and text on a plane.
#include "renderer/scene/plane_marks.hpp"

#include "renderer/scene/overlay_text.hpp"

namespace tridex::renderer {

void add_two_sided(TriMesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, b});
}

void add_plane_rect(TriMesh& m, const PlaneFrame& f, double u0, double v0, double u1, double v1, double off) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(f.at(u0, v0, off));
    m.positions.push_back(f.at(u1, v0, off));
    m.positions.push_back(f.at(u1, v1, off));
    m.positions.push_back(f.at(u0, v1, off));
    add_two_sided(m, base, base + 1, base + 2);
    add_two_sided(m, base, base + 2, base + 3);
}

void add_plane_text(TriMesh& m, const PlaneFrame& f, std::string_view text, double u, double v, double height,
                    double anchor, double off) {
    const TextExtent unit = overlay_text_extent(text, 1.0);
    if (unit.height_px <= 0.0) return;
    const double s = height / unit.height_px;  // m per font pixel
    const double u0 = u - anchor * s * unit.width_px;
    const TriMesh glyphs = overlay_text_mesh(text, 0.0, 0.0, 1.0);
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    // The font's pixel units (x right, y down) become metres along ex and -ey.
    for (const Vec3& p : glyphs.positions) m.positions.push_back(f.at(u0 + s * p.x, v - s * p.y, off));
    for (const auto& t : glyphs.triangles) add_two_sided(m, base + t[0], base + t[1], base + t[2]);
}

}  // namespace tridex::renderer
