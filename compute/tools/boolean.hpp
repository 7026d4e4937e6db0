// compute/tools/boolean.hpp - CPU reference tri-dexel Booleans with the ball tool's swept volume.
#pragma once

#include <cstddef>
#include <vector>

#include "compute/model/interval_ops.hpp"
#include "compute/model/tridexel.hpp"
#include "core/segment.hpp"

namespace tridex::compute {

/// What a Boolean did: rays whose line passes within the tool's bounding box, and rays whose
/// intervals actually changed.
struct BooleanStats {
    std::size_t rays_visited = 0;
    std::size_t rays_changed = 0;
};

/// Subtracts the swept volume of a ball of radius radius_m moved along seg_m (world metres; a capsule)
/// from every ray of all three sets whose line passes within the capsule's bounding box, and from no
/// other ray; marks dirty the tiles around the capsule's box (TriDexel::mark_dirty) when a ray changed.
/// Same as apply_sweep (sweep.hpp) with a ball tool and ToolOp::kSubtract: each chord is computed by
/// capsule_chord in float, relative to the segment's start (sweep_chord). A zero-length segment is a ball.
/// Cost: O(rays in the box's footprint x intervals per ray).
/// Throws tridex::Error (model unchanged) on non-finite input or radius_m <= 0.
/// Source: Peng et al., tri-dexel Booleans.
BooleanStats subtract_capsule(TriDexel& model, const Segment& seg_m, double radius_m);

}  // namespace tridex::compute
