// app/session/view/framing.hpp - the part of a wall through which a box is seen from a head: a picture that the box fills
// with the wall's stereo unchanged (the demo's and a film strip's pictures, a desk window with a fixed head).
#pragma once

#include "core/aabb.hpp"
#include "core/math.hpp"
#include "renderer/camera/off_axis.hpp"

namespace tridex::app {

/// The part of `wall` (the same plane) through which the world box `box_m` is seen from head_m (m): the box's corners
/// projected from the head onto the wall's plane, 10% margin on each side, widened about its centre to `aspect`
/// (width / height). Drawing through it keeps every eye ray of the full wall, so the stereo is unchanged, but the
/// box fills the image. Returns `wall` itself when the box is empty or not finite, a corner is not between the head
/// and the wall's far side, or the crop would not be smaller than the wall.
renderer::Screen framing_screen(const renderer::Screen& wall, const Aabb& box_m, const Vec3& head_m, double aspect);

}  // namespace tridex::app
