// app/menu/pie_menu_mesh.cpp - slices, labels and status text of the open pie menu.
#include "app/menu/pie_menu_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "renderer/scene/overlay_text.hpp"
#include "renderer/scene/plane_marks.hpp"

namespace tridex::app {

namespace {

constexpr int kSegmentsPerSlice = 10;   // arc segments of one slice
constexpr double kGapRad = 0.035;       // half the angular gap between slices, rad
constexpr double kMarkOffM = 0.001;     // the lit slice towards the head
constexpr double kTextOffM = 0.002;     // text towards the head

// Appends the annular sector between radii r0 and r1 from angle a0 to a1 (clockwise from up), two-sided.
void add_sector(TriMesh& m, const renderer::PlaneFrame& f, double r0, double r1, double a0, double a1, double off) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (int i = 0; i <= kSegmentsPerSlice; ++i) {
        const double a = a0 + (a1 - a0) * i / kSegmentsPerSlice;
        const double u = std::sin(a), v = std::cos(a);
        m.positions.push_back(f.at(r0 * u, r0 * v, off));
        m.positions.push_back(f.at(r1 * u, r1 * v, off));
    }
    for (std::uint32_t i = 0; i < kSegmentsPerSlice; ++i) {
        const std::uint32_t a = base + 2 * i;
        renderer::add_two_sided(m, a, a + 1, a + 3);
        renderer::add_two_sided(m, a, a + 3, a + 2);
    }
}

}  // namespace

std::vector<MenuPiece> pie_menu_pieces(const RingView& ring, const std::string& status) {
    if (!ring.node || ring.node->children.empty()) return {};
    renderer::PlaneFrame f;
    f.o = ring.centre_m;
    f.ex = ring.right;
    f.ey = ring.up;
    f.n = ring.normal;
    std::vector<MenuPiece> out(3);
    out[0].colour = glm::vec4(0.10f, 0.12f, 0.16f, 1.0f);
    out[1].colour = glm::vec4(1.00f, 0.50f, 0.08f, 1.0f);
    out[2].colour = glm::vec4(0.95f, 0.95f, 0.95f, 1.0f);
    const int n = static_cast<int>(ring.node->children.size());
    const double w = 2.0 * std::numbers::pi / n;
    const double r0 = 1.4 * ring.dead_radius_m, r1 = ring.radius_m;
    const double text_h = std::max(0.16 * r1, 0.002);  // letter height, m
    for (int k = 0; k < n; ++k) {
        const MenuItem& item = ring.node->children[static_cast<std::size_t>(k)];
        const double c = k * w;
        const bool lit = k == ring.highlighted;
        add_sector(lit ? out[1].mesh : out[0].mesh, f, r0, r1, c - 0.5 * w + kGapRad, c + 0.5 * w - kGapRad,
                   lit ? kMarkOffM : 0.0);
        const double du = std::sin(c), dv = std::cos(c);
        // The glyph inside the slice, centred.
        const double rg = 0.5 * (r0 + r1);
        if (!item.glyph.empty())
            renderer::add_plane_text(out[2].mesh, f, item.glyph, rg * du, rg * dv + 0.5 * text_h, text_h, 0.5, kTextOffM);
        // The label just outside the ring on a dark backing, anchored away from the centre.
        const std::string& label = item.label;
        const renderer::TextExtent e = renderer::overlay_text_extent(label, 1.0);
        if (e.height_px <= 0.0) continue;
        const double s = text_h / e.height_px * 1.0;
        const double lw = s * e.width_px;
        const double anchor = std::abs(du) < 0.2 ? 0.5 : du > 0.0 ? 0.0 : 1.0;
        const double rl = r1 + 0.25 * text_h;
        const double u = rl * du, v = rl * dv + (dv > 0.2 ? text_h : dv < -0.2 ? 0.0 : 0.5 * text_h);
        const double u0 = u - anchor * lw, pad = 0.2 * text_h;
        renderer::add_plane_rect(lit ? out[1].mesh : out[0].mesh, f, u0 - pad, v - text_h - pad, u0 + lw + pad, v + pad,
                                 lit ? kMarkOffM : 0.0);
        renderer::add_plane_text(out[2].mesh, f, label, u, v, text_h, anchor, kTextOffM);
    }
    if (!status.empty()) {  // the overlay's status beside the hand: below the ring, centred
        const double sh = 0.6 * text_h;
        const int lines = 1 + static_cast<int>(std::count(status.begin(), status.end(), '\n'));
        renderer::add_plane_text(out[2].mesh, f, status, 0.0, -r1 - 2.0 * text_h, sh * lines, 0.5, kTextOffM);
    }
    return out;
}

}  // namespace tridex::app
