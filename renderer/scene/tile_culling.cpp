// renderer/scene/tile_culling.cpp - frustum planes from a clip matrix and the box test.
#include "renderer/scene/tile_culling.hpp"

#include <cmath>

#include "core/error.hpp"

namespace tridex::renderer {

Frustum frustum_from_clip(const Mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) throw Error("frustum_from_clip: clip-from-world matrix is not finite");
    // Row r of the matrix (GLM is column-major: m[column][row]).
    const auto row = [&](int r) { return glm::dvec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
    const glm::dvec4 x = row(0), y = row(1), z = row(2), w = row(3);
    Frustum f;
    f.planes[0] = w + x;  // x >= -w (left)
    f.planes[1] = w - x;  // x <= w (right)
    f.planes[2] = w + y;  // y >= -w (top: y_ndc = -1 is framebuffer row 0)
    f.planes[3] = w - y;  // y <= w (bottom)
    f.planes[4] = z;      // z >= 0 (near)
    f.planes[5] = w - z;  // z <= w (far)
    return f;
}

bool may_be_visible(const Frustum& frustum, const Aabb& box_m) {
    if (box_m.empty()) return false;
    if (!is_finite(box_m.lo) || !is_finite(box_m.hi)) throw Error("may_be_visible: tile bounds_m must be finite");
    for (const glm::dvec4& p : frustum.planes) {
        const Vec3 far_corner(p.x >= 0.0 ? box_m.hi.x : box_m.lo.x, p.y >= 0.0 ? box_m.hi.y : box_m.lo.y,
                              p.z >= 0.0 ? box_m.hi.z : box_m.lo.z);
        if (p.x * far_corner.x + p.y * far_corner.y + p.z * far_corner.z + p.w < 0.0) return false;
    }
    return true;
}

}  // namespace tridex::renderer
