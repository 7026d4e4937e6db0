// renderer/stereo/screen_region.hpp - the pixel rectangle a world box can cover in one eye's image.
#pragma once

#include "core/aabb.hpp"
#include "core/math.hpp"

namespace tridex::renderer {

/// Pixels [x0, x1) x [y0, y1) of an image (x right, y down, as Vulkan's framebuffer). Empty when x1 <= x0 or
/// y1 <= y0.
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
};

/// The smallest rectangle holding both (an empty one is ignored).
PixelRect unite(const PixelRect& a, const PixelRect& b);

/// The whole width x height image.
inline PixelRect whole_image(int width, int height) { return PixelRect{0, 0, width, height}; }

/// A rectangle of the width x height image (pixels) holding every pixel that `box_m` (world m) can cover when
/// drawn with `clip_from_world` (a perspective projection times a view, Vulkan clip space: x, y in [-w, w]): the
/// bounds of its 8 projected corners, widened by one pixel and clamped to the image. The whole image when a
/// corner lies on or behind the eye's plane (clip w <= 0) or is not finite; empty for an empty box or one wholly
/// outside the image.
PixelRect project_box(const Mat4& clip_from_world, const Aabb& box_m, int width, int height);

}  // namespace tridex::renderer
