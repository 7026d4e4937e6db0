// compute/model/volume.hpp - the volume of a tri-dexel solid.
#pragma once

#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// Volume of the solid, m^3: for each ray set the sum of its interval lengths (grid units, summed
/// in double) times h^3 (each ray stands for the h x h column around its node), averaged over the
/// three sets. Exact for boxes whose faces are lattice-aligned (on or between nodes) with whole-cell
/// sides; otherwise a midpoint-rule estimate whose error is a small fraction of (surface area x h).
/// O(intervals). Never throws.
double dexel_volume_m3(const TriDexel& model);

/// Volume of one ray set alone (same rule as dexel_volume_m3 without the averaging), m^3.
/// `axis` must be 0, 1 or 2, else throws tridex::Error.
double ray_set_volume_m3(const TriDexel& model, int axis);

}  // namespace tridex::compute
