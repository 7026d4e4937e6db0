// renderer/scene/tile_lod.cpp - projected error of a tile's levels per eye.
#include "renderer/scene/tile_lod.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace tridex::renderer {

LodEye lod_eye(const Screen& screen, const Vec3& eye_m, int width_px, int height_px) {
    if (width_px < 1 || height_px < 1)
        throw Error("lod_eye: image size must be at least 1x1, got " + std::to_string(width_px) + "x" +
                    std::to_string(height_px));
    const EyeView v = off_axis_view(screen, eye_m, 0.01, 100.0);
    LodEye e;
    e.view = v.view;
    const glm::dvec4 corner = v.view * glm::dvec4(screen.lower_left, 1.0);
    e.screen_distance_m = -corner.z;
    e.pixels_per_screen_m = std::max(width_px / screen.width(), height_px / screen.height());
    return e;
}

double pixels_per_metre(const LodEye& eye, const Aabb& box_m) {
    if (box_m.empty()) return 0.0;
    if (!is_finite(box_m.lo) || !is_finite(box_m.hi)) throw Error("pixels_per_metre: box must be finite");
    double depth = std::numeric_limits<double>::infinity(), lateral = 0.0;
    for (int c = 0; c < 8; ++c) {
        const Vec3 p((c & 1) ? box_m.hi.x : box_m.lo.x, (c & 2) ? box_m.hi.y : box_m.lo.y,
                     (c & 4) ? box_m.hi.z : box_m.lo.z);
        const glm::dvec4 q = eye.view * glm::dvec4(p, 1.0);
        depth = std::min(depth, -q.z);  // the box is convex: its depths span the corners' range
        lateral = std::max(lateral, std::hypot(q.x, q.y));
    }
    if (!(depth > 0.0)) return std::numeric_limits<double>::infinity();
    const double slope = lateral / depth;
    return eye.pixels_per_screen_m * eye.screen_distance_m / depth * std::sqrt(1.0 + slope * slope);
}

std::size_t choose_level(std::span<const TileMeshLevel> levels, double px_per_m, double max_px) {
    for (std::size_t k = levels.size(); k > 0; --k) {
        const TileMeshLevel& l = levels[k - 1];
        if (!l.mesh || l.mesh->triangles.empty()) continue;
        if (l.error_m * px_per_m <= max_px) return k;
    }
    return 0;
}

}  // namespace tridex::renderer
