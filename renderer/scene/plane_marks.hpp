// renderer/scene/plane_marks.hpp - flat marks and text on a plane in world space (the wall's test pattern, the
// in-scene menu): two-sided triangles, so they are seen from either side.
#pragma once

#include <cstdint>
#include <string_view>

#include "core/math.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::renderer {

/// A plane's frame: origin, unit right (ex), up (ey) and towards the viewer (n), world m.
struct PlaneFrame {
    Vec3 o{0.0}, ex{1.0, 0.0, 0.0}, ey{0.0, 1.0, 0.0}, n{0.0, 0.0, 1.0};
    /// The point u m right, v m up and `off` m towards the viewer of the origin.
    Vec3 at(double u, double v, double off = 0.0) const { return o + u * ex + v * ey + off * n; }
};

/// Appends the triangle (a, b, c) of existing vertices both ways round.
void add_two_sided(TriMesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c);

/// Appends the rectangle [u0, u1] x [v0, v1] of plane `f`, `off` m towards the viewer, two-sided.
void add_plane_rect(TriMesh& m, const PlaneFrame& f, double u0, double v0, double u1, double v1, double off);

/// Appends `text` (the overlay font, renderer/scene/overlay_text.hpp) on plane `f`, `off` m towards the viewer, its
/// lines `height` m tall in all, the top of its box at v and the point `anchor` of the way along its width (0 left,
/// 0.5 centre, 1 right) at u; two-sided. Empty text appends nothing. Throws tridex::Error as overlay_text_mesh does
/// for non-finite coordinates.
void add_plane_text(TriMesh& m, const PlaneFrame& f, std::string_view text, double u, double v, double height,
                    double anchor, double off);

}  // namespace tridex::renderer
