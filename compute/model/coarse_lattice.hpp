// compute/model/coarse_lattice.hpp - the tri-dexel model read on a coarser lattice: every stride-th ray of each
// set, so a level of detail is contoured straight from the dexels rather than simplified from the full contour.
#pragma once

#include <vector>

#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// Largest stride coarse_model accepts (a coarse cell of 64 fine cells).
constexpr int kMaxLatticeStride = 64;

/// The lattice of `fine` read at `stride`: the same origin, spacing stride * h, and ceil(cells / stride) cells per
/// axis (the last coarse node may lie past the fine lattice's end; the rays through it are empty there).
/// Throws tridex::Error when stride is not a power of two in 1..kMaxLatticeStride.
Lattice coarse_lattice(const Lattice& fine, int stride);

/// The model `fine` on coarse_lattice(fine.lattice, stride): coarse ray (u, v) of set a is fine ray (u * stride,
/// v * stride) of that set (empty past the fine lattice), each interval end divided by stride (exact in float, a
/// power of two) with its material. So every edge of the coarse lattice lies on a ray of the fine model, and its
/// crossings are the fine model's own interval ends, not an average: a contour of the result is the surface at
/// the coarse spacing (Peng et al., tri-dexel model: each lattice edge on one ray), and features thinner than a
/// coarse cell between its rays are missed as a scan conversion at that spacing would miss them. Every tile of
/// the result is marked dirty (kWhole), ready for a first Contourer::update. stride 1 copies the model.
/// O(rays of the result + their intervals). Throws as coarse_lattice.
TriDexel coarse_model(const TriDexel& fine, int stride);

/// One ray of the fine model as coarse_model holds it at `stride` (a power of two, unchecked): each interval end
/// divided by stride, its materials kept, written into `out` (replaced; its capacity reused).
void coarse_ray(const std::vector<Interval>& fine_ray, int stride, std::vector<Interval>& out);

}  // namespace tridex::compute
