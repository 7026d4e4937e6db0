// devices/rotation_vector.hpp - unit quaternion <-> rotation vector (axis * angle), for the simulated wrist.
#pragma once

#include "core/math.hpp"

namespace tridex::devices {

/// The rotation vector of a unit quaternion: axis * angle (rad), angle in [0, pi], i.e. the shortest
/// rotation (q and -q give the same vector). Accurate near the identity (uses atan2 of the vector part's
/// length and w). A non-unit q is treated as q / |q|; a zero or non-finite q gives a non-finite result.
Vec3 rotation_vector(const Quat& q);

/// The unit quaternion of a rotation vector v (axis * angle, rad): exp(v / 2). v = 0 gives exactly the
/// identity (1, 0, 0, 0). Non-finite v gives a non-finite quaternion.
Quat quat_from_rotation_vector(const Vec3& v);

}  // namespace tridex::devices
