// renderer/scene/force_arrow.hpp - where the force arrow's shaft and head go for a force in newtons.
#pragma once

#include "core/math.hpp"

namespace tridex::renderer {

/// Look of the force arrow, metres. The arrow's LENGTH is not here: it is m_per_newton * |F|.
struct ForceArrowStyle {
    double shaft_radius_m = 0.0025;  ///< radius of the shaft cylinder
    double head_radius_m = 0.006;    ///< base radius of the head cone
    double head_length_m = 0.015;    ///< head cone length; shortened to half the arrow on short arrows
};

/// The two model matrices (unit_cylinder -> shaft, unit_cone -> head) of an arrow from `origin_m` along
/// the force, and its length. visible is false (and the matrices identity) when the length is below 1e-6 m.
struct ForceArrowTransforms {
    bool visible = false;
    double length_m = 0.0;  ///< m_per_newton * |force_N|, m
    Mat4 shaft{1.0};        ///< world from unit_cylinder: radius shaft_radius_m, from origin to the head's base
    Mat4 head{1.0};         ///< world from unit_cone: base radius head_radius_m, apex (tip) at origin + length * dir
};

/// Places the arrow: tip = origin_m + m_per_newton * force_N (m; force in N, scale in m/N), head length
/// min(style.head_length_m, length / 2), shaft from origin_m to the head's base. The unit +z axis of the
/// meshes is rotated onto the force direction by a proper rotation (det +1, so winding stays outward).
/// Throws tridex::Error when an input is not finite, m_per_newton < 0, or a style size is <= 0.
ForceArrowTransforms force_arrow(const Vec3& origin_m, const Vec3& force_N, double m_per_newton,
                                 const ForceArrowStyle& style = {});

}  // namespace tridex::renderer
