// compute/boolean.hpp - CPU reference tri-dexel Booleans with the ball tool's swept volume.
#pragma once

#include <cstddef>
#include <vector>

#include "compute/tridexel.hpp"
#include "core/segment.hpp"

namespace tridex::compute {

/// What a Boolean did: rays whose line passes within the tool's bounding box, and rays whose
/// intervals actually changed.
struct BooleanStats {
    std::size_t rays_visited = 0;
    std::size_t rays_changed = 0;
};

/// Subtracts [t0, t1] (grid units) from one ray's sorted, disjoint, non-touching intervals; an
/// interval may shrink, vanish, or split in two. Pieces of zero length are dropped, so the result
/// keeps the invariants. Nothing happens when t0 >= t1 or either bound is NaN. O(intervals).
/// Source: Peng et al., tri-dexel Boolean subtraction, per ray.
void subtract_interval(std::vector<Interval>& ray, float t0, float t1);

/// Same as subtract_interval; returns true when the ray changed.
bool subtract_interval_changed(std::vector<Interval>& ray, float t0, float t1);

/// Subtracts the swept volume of a ball of radius radius_m moved along seg_m (world metres; a capsule)
/// from every ray of all three sets whose line passes within the capsule's bounding box, and from no
/// other ray; marks dirty the tiles around the capsule's box (TriDexel::mark_dirty) when a ray changed.
/// Each chord is computed by capsule_chord in float, in grid units relative to the segment's start:
/// for the ray of set a at node (u, v) the line is o + t*e_a with o = node - A, o[a] = 0, where
/// A = grid(seg_m.a); the removed depths are float(A[a]) + t0 .. float(A[a]) + t1. A zero-length
/// segment is a ball. Cost: O(rays in the box's footprint x intervals per ray).
/// Throws tridex::Error (model unchanged) on non-finite input or radius_m <= 0.
/// Source: Peng et al., tri-dexel Booleans.
BooleanStats subtract_capsule(TriDexel& model, const Segment& seg_m, double radius_m);

}  // namespace tridex::compute
