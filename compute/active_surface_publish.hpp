// compute/active_surface_publish.hpp - copying the dexels near the tool into the haptic cache.
#pragma once

#include <cstdint>

#include "compute/tridexel.hpp"
#include "core/active_surface.hpp"

namespace tridex::compute {

/// Copies into `out` (core/active_surface.hpp) the rays of each set in a window of at most
/// ActiveSurface::kWindow x kWindow rays centred on centre_m (m; the window's first ray is the node
/// nearest centre_m minus kWindow/2, clamped so the window stays inside the lattice), with each
/// ray's intervals (grid units). When a ray has more than kMaxIntervals intervals, keeps the
/// kMaxIntervals consecutive intervals nearest centre_m along the ray (distance from the centre's
/// depth to an interval, 0 inside it) and sets that window's `truncated`. Fills origin_m, cell_m,
/// nodes, centre_m; sets out.sequence = sequence; zeroes the counts of unused window slots.
/// Allocation-free and O(kWindow^2 x (kMaxIntervals + log intervals per ray)) per set, whatever the
/// model size. Throws tridex::Error (before touching `out`) when centre_m is not finite.
/// Source: Peng et al., active triangle built from the dexel points around the HIP.
void extract_active_surface(const TriDexel& model, const Vec3& centre_m, std::uint64_t sequence, ActiveSurface& out);

}  // namespace tridex::compute
