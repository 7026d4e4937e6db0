// renderer/scene/tile_culling.hpp - which workpiece tiles an eye's off-axis frustum can see.
#pragma once

#include <array>

#include "core/aabb.hpp"
#include "core/math.hpp"

namespace tridex::renderer {

/// The six planes of a view frustum in world space (m): a point p is inside plane i when
/// dot(planes[i].xyz, p) + planes[i].w >= 0. Order: left, right, top, bottom (framebuffer rows: y_ndc = -1
/// is the top row), near, far. Planes are not normalised (only signs are used).
struct Frustum {
    std::array<glm::dvec4, 6> planes{};
};

/// The frustum of a Vulkan clip-from-world matrix (e.g. EyeView::projection * EyeView::view of an off-axis
/// eye): the points with -w <= x <= w, -w <= y <= w, 0 <= z <= w in clip space (Gribb & Hartmann plane
/// extraction, adapted to Vulkan's 0..1 depth). Throws tridex::Error when the matrix is not finite.
Frustum frustum_from_clip(const Mat4& clip_from_world);

/// Conservative box-vs-frustum test: false only when `box_m` lies entirely on the outside of one of the
/// six planes (tested with the box corner furthest along the plane normal), so a box that is visible is
/// never rejected; a box outside near a frustum edge may still be kept. An empty box is never visible.
/// Throws tridex::Error when a non-empty box is not finite.
bool may_be_visible(const Frustum& frustum, const Aabb& box_m);

}  // namespace tridex::renderer
