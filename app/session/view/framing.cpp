// app/session/view/framing.cpp - a wall cropped to the part through which a box is seen from a head.
#include "app/session/view/framing.hpp"

#include <algorithm>

namespace tridex::app {

renderer::Screen framing_screen(const renderer::Screen& wall, const Aabb& box_m, const Vec3& head_m, double aspect) {
    const Vec3 o = wall.lower_left;
    const Vec3 ex = glm::normalize(wall.lower_right - wall.lower_left);
    const Vec3 ey = glm::normalize(wall.upper_left - wall.lower_left);
    const Vec3 n = glm::normalize(glm::cross(ex, ey));
    const double head_d = glm::dot(head_m - o, n);
    if (box_m.empty() || !is_finite(box_m.lo) || !is_finite(box_m.hi) || !(head_d > 0.0) || !(aspect > 0.0)) return wall;
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
    for (int k = 0; k < 8; ++k) {
        const Vec3 c((k & 1) ? box_m.hi.x : box_m.lo.x, (k & 2) ? box_m.hi.y : box_m.lo.y, (k & 4) ? box_m.hi.z : box_m.lo.z);
        const double cd = glm::dot(c - o, n);
        if (!(cd < head_d)) return wall;  // a corner at or behind the head: no sensible crop
        const Vec3 p = head_m + (c - head_m) * (head_d / (head_d - cd));  // the corner seen on the wall plane
        u0 = std::min(u0, glm::dot(p - o, ex)), u1 = std::max(u1, glm::dot(p - o, ex));
        v0 = std::min(v0, glm::dot(p - o, ey)), v1 = std::max(v1, glm::dot(p - o, ey));
    }
    // A margin of 10% on each side, widened to the image's aspect about the centre.
    const double cu = 0.5 * (u0 + u1), cv = 0.5 * (v0 + v1);
    double w = 1.2 * (u1 - u0), h = 1.2 * (v1 - v0);
    if (w < h * aspect) w = h * aspect;
    else h = w / aspect;
    if (w >= wall.width() || h >= wall.height()) return wall;
    renderer::Screen s;
    s.lower_left = o + ex * (cu - 0.5 * w) + ey * (cv - 0.5 * h);
    s.lower_right = s.lower_left + ex * w;
    s.upper_left = s.lower_left + ey * h;
    return s;
}

}  // namespace tridex::app
