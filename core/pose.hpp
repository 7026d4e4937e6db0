// core/pose.hpp - a rigid pose (position in metres, orientation as a unit quaternion).
#pragma once

#include "core/math.hpp"

namespace tridex {

/// Rigid transform from a body frame to its parent frame: p_parent = orientation * p_body + position.
struct Pose {
    Vec3 position{0.0};                  ///< Origin of the body frame in the parent frame, m.
    Quat orientation{1.0, 0.0, 0.0, 0.0};  ///< Rotation body -> parent (w, x, y, z), unit length.

    /// Maps a point given in the body frame (m) into the parent frame (m).
    Vec3 apply(const Vec3& p_body) const { return orientation * p_body + position; }
    /// Maps a direction (no translation) from the body frame into the parent frame.
    Vec3 rotate(const Vec3& d_body) const { return orientation * d_body; }
    /// The 4x4 matrix of this pose.
    Mat4 matrix() const {
        Mat4 m = glm::mat4_cast(orientation);
        m[3] = glm::dvec4(position, 1.0);
        return m;
    }
};

}  // namespace tridex
