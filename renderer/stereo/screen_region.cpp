// renderer/stereo/screen_region.cpp - projected bounds of world boxes in pixels.
#include "renderer/stereo/screen_region.hpp"

#include <algorithm>
#include <cmath>

namespace tridex::renderer {

PixelRect unite(const PixelRect& a, const PixelRect& b) {
    if (a.empty()) return b;
    if (b.empty()) return a;
    return PixelRect{std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

PixelRect project_box(const Mat4& clip_from_world, const Aabb& box_m, int width, int height) {
    if (box_m.empty() || width <= 0 || height <= 0) return PixelRect{};
    double lo_x = INFINITY, lo_y = INFINITY, hi_x = -INFINITY, hi_y = -INFINITY;
    for (int c = 0; c < 8; ++c) {
        const Vec3 p((c & 1) ? box_m.hi.x : box_m.lo.x, (c & 2) ? box_m.hi.y : box_m.lo.y,
                     (c & 4) ? box_m.hi.z : box_m.lo.z);
        const glm::dvec4 clip = clip_from_world * glm::dvec4(p, 1.0);
        if (!(clip.w > 0.0) || !std::isfinite(clip.x) || !std::isfinite(clip.y)) return whole_image(width, height);
        // Vulkan viewport transform: framebuffer x = (ndc.x + 1) / 2 * width, y = (ndc.y + 1) / 2 * height.
        const double x = (clip.x / clip.w + 1.0) * 0.5 * width, y = (clip.y / clip.w + 1.0) * 0.5 * height;
        lo_x = std::min(lo_x, x);
        hi_x = std::max(hi_x, x);
        lo_y = std::min(lo_y, y);
        hi_y = std::max(hi_y, y);
    }
    const auto clamp_to = [](double v, int n) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(n))); };
    PixelRect r{clamp_to(std::floor(lo_x) - 1.0, width), clamp_to(std::floor(lo_y) - 1.0, height),
                clamp_to(std::ceil(hi_x) + 1.0, width), clamp_to(std::ceil(hi_y) + 1.0, height)};
    return r.empty() ? PixelRect{} : r;
}

}  // namespace tridex::renderer
