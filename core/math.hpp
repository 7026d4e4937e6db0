// core/math.hpp - the vector and rotation types of the whole API (GLM, double precision).
#pragma once

#define GLM_FORCE_DEPTH_ZERO_TO_ONE
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace tridex {

/// A point or direction in world space, metres (or N, N*m where documented).
using Vec3 = glm::dvec3;
/// A unit quaternion (rotation), dimensionless.
using Quat = glm::dquat;
/// A 4x4 homogeneous transform, column-major (GLM convention).
using Mat4 = glm::dmat4;

/// True when every component of v is finite (no NaN, no infinity).
inline bool is_finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace tridex
