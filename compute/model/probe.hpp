// compute/model/probe.hpp - reading the surface height under a point from one ray set.
#pragma once

#include "compute/model/tridexel.hpp"
#include "core/math.hpp"

namespace tridex::compute {

/// The highest surface point (largest coordinate along `axis`) on the ray of set `axis` nearest to
/// the world point p_m (m): p_m is projected onto that ray set's lattice plane and rounded to the
/// nearest node (clamped to the lattice). Writes the world point (m) of the last interval's exit to
/// surface_m and returns true; returns false (surface_m untouched) if that ray is empty.
/// Throws tridex::Error when axis is not 0, 1 or 2 or p_m is not finite.
bool probe_top(const TriDexel& model, int axis, const Vec3& p_m, Vec3& surface_m);

}  // namespace tridex::compute
