// core/pose.hpp - a rigid pose (position in metres, orientation as a unit quaternion).
#pragma once

#include <cmath>

#include "core/aabb.hpp"
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
    /// The inverse transform (parent -> body): inverse().apply(apply(p)) == p up to rounding. Needs a unit
    /// orientation (the conjugate is its inverse).
    Pose inverse() const {
        const Quat q = glm::conjugate(orientation);
        return Pose{q * -position, q};
    }
    /// Whether this is exactly the identity (no move, no turn).
    bool is_identity() const { return position == Vec3(0.0) && orientation == Quat(1.0, 0.0, 0.0, 0.0); }
};

/// Tolerance on |q| - 1 for a quaternion to count as a unit one (is_unit).
inline constexpr double kUnitQuatTolerance = 1e-6;

/// Whether `q` is a unit quaternion: |q| within kUnitQuatTolerance of 1 (false for NaN or infinite components).
inline bool is_unit(const Quat& q) {
    const double n = glm::length(q);
    return std::isfinite(n) && std::abs(n - 1.0) <= kUnitQuatTolerance;
}

/// Whether `p` is a rigid pose: a finite position and a unit orientation (is_unit).
inline bool is_rigid(const Pose& p) { return is_finite(p.position) && is_unit(p.orientation); }

/// Composition: (a * b).apply(p) == a.apply(b.apply(p)) (b maps body -> middle frame, a middle -> parent); the
/// orientation is renormalised so chains of poses stay unit.
inline Pose operator*(const Pose& a, const Pose& b) {
    return Pose{a.orientation * b.position + a.position, glm::normalize(a.orientation * b.orientation)};
}

/// The axis-aligned box (m) holding `box` (in the pose's body frame) once placed by `pose`: the box of its eight
/// corners mapped into the parent frame. An empty box stays empty.
inline Aabb placed(const Aabb& box, const Pose& pose) {
    if (box.empty()) return box;
    Aabb out;
    for (int k = 0; k < 8; ++k)
        out.add(pose.apply(Vec3(k & 1 ? box.hi.x : box.lo.x, k & 2 ? box.hi.y : box.lo.y, k & 4 ? box.hi.z : box.lo.z)));
    return out;
}

}  // namespace tridex
