// compute/model/interval_ops.hpp - one ray's Boolean updates: subtract, union and paint a span [t0, t1].
#pragma once

#include <cstdint>
#include <vector>

#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// Subtracts [t0, t1] (grid units) from one ray's sorted, disjoint, non-touching intervals; an
/// interval may shrink, vanish, or split in two. Pieces of zero length are dropped, so the result
/// keeps the invariants. The ends the cut creates get material `cut_material` (the material of the
/// freshly exposed surface); surviving ends keep theirs. Nothing happens when t0 >= t1 or either bound
/// is NaN. Returns true when the ray changed. O(intervals).
/// Source: Peng et al., tri-dexel Boolean subtraction, per ray. The GPU kernel (shaders/dexel_sweep.comp)
/// performs the same steps in the same order.
bool subtract_interval_changed(std::vector<Interval>& ray, float t0, float t1, std::uint8_t cut_material = 0);

/// Same as subtract_interval_changed, without the result.
void subtract_interval(std::vector<Interval>& ray, float t0, float t1);

/// Adds [t0, t1] (grid units) as material: every interval that overlaps or touches it is merged with it
/// into one interval, so the ray stays sorted, disjoint and non-touching. An end that the added span
/// extends (strictly beyond the old end) gets `material`; the others keep theirs. Nothing happens when
/// t0 >= t1 or either bound is NaN. Returns true when the ray changed. O(intervals).
/// Source: Peng et al., tri-dexel Boolean union, per ray.
bool union_interval_changed(std::vector<Interval>& ray, float t0, float t1, std::uint8_t material);

/// Paints the surface inside [t0, t1]: every interval end (a surface point) with t0 <= depth <= t1 gets
/// `material`. Depths do not change. Nothing happens when t0 > t1 or either bound is NaN. Returns true
/// when a material id changed. O(log intervals + painted ends).
bool paint_interval_changed(std::vector<Interval>& ray, float t0, float t1, std::uint8_t material);

}  // namespace tridex::compute
