// renderer/scene/force_arrow.cpp - force arrow placement.
#include "renderer/scene/force_arrow.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace tridex::renderer {
namespace {

// World from a model whose +z axis goes along unit `dir`, scaled by (radius, radius, length), at `base`.
Mat4 along(const Vec3& base, const Vec3& dir, double radius, double length) {
    // Any unit vector perpendicular to dir: cross with the world axis least aligned with it.
    const Vec3 a = std::abs(dir.x) < 0.9 ? Vec3(1.0, 0.0, 0.0) : Vec3(0.0, 1.0, 0.0);
    const Vec3 u = glm::normalize(glm::cross(a, dir));
    const Vec3 v = glm::cross(dir, u);  // u x v = dir: right-handed
    Mat4 m(1.0);
    m[0] = glm::dvec4(u * radius, 0.0);
    m[1] = glm::dvec4(v * radius, 0.0);
    m[2] = glm::dvec4(dir * length, 0.0);
    m[3] = glm::dvec4(base, 1.0);
    return m;
}

}  // namespace

ForceArrowTransforms force_arrow(const Vec3& origin_m, const Vec3& force_N, double m_per_newton,
                                 const ForceArrowStyle& style) {
    if (!is_finite(origin_m) || !is_finite(force_N))
        throw Error("force_arrow: SceneView.tool_centre_m / force_N must be finite");
    if (!std::isfinite(m_per_newton) || m_per_newton < 0.0)
        throw Error("force_arrow: SceneView.force_m_per_newton must be finite and >= 0");
    if (!(style.shaft_radius_m > 0.0) || !(style.head_radius_m > 0.0) || !(style.head_length_m > 0.0) ||
        !std::isfinite(style.shaft_radius_m + style.head_radius_m + style.head_length_m))
        throw Error("force_arrow: ForceArrowStyle sizes must be finite and > 0");
    ForceArrowTransforms t;
    const double magnitude = glm::length(force_N);
    t.length_m = m_per_newton * magnitude;
    if (!(t.length_m >= 1e-6) || !std::isfinite(t.length_m)) return t;
    t.visible = true;
    const Vec3 dir = force_N / magnitude;
    const double head = std::min(style.head_length_m, 0.5 * t.length_m);
    const double shaft = t.length_m - head;
    t.shaft = along(origin_m, dir, style.shaft_radius_m, shaft);
    t.head = along(origin_m + dir * shaft, dir, style.head_radius_m, head);
    return t;
}

}  // namespace tridex::renderer
