// haptics/forces/force_clamp.hpp - the last safety stage before a force reaches the device.
#pragma once

#include "core/math.hpp"

namespace tridex::haptics {

/// Limits the magnitude of v to max_norm, keeping its direction: returns v when |v| <= max_norm,
/// v * max_norm / |v| otherwise. Returns zero when v has a NaN or infinite component, or when
/// max_norm is not finite or <= 0, so the result is always finite and bounded (never send an
/// unbounded force). Works for forces (N) and torques (N*m) alike. Allocation-free.
Vec3 clamp_magnitude(const Vec3& v, double max_norm);

/// Clamps a force (N) to a device's continuous force limit max_force_n (N); see clamp_magnitude.
inline Vec3 clamp_force(const Vec3& force_n, double max_force_n) { return clamp_magnitude(force_n, max_force_n); }

}  // namespace tridex::haptics
