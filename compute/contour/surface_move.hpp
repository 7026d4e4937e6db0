// compute/contour/surface_move.hpp - how far one tri-dexel model's surface lies from another's (two lattices allowed):
// what a resample reports as the largest surface move.
#pragma once

#include "compute/model/tridexel.hpp"
#include "compute/tools/model_resample.hpp"

namespace tridex::compute {

/// The largest distance (m) of an interval end of either model from the other model's contoured surface: each model
/// is contoured whole on the CPU (Contourer, a copy with every tile dirty) and every interval end of the one is
/// measured against the other's triangles (TriangleGrid, exact point-to-triangle distance). The two models may be on
/// different lattices. 0 when both are empty; +infinity when only one is. The floor is the contour's own distance from
/// the ends it was made from (a few hundredths of a cell on smooth surfaces). Cost: two full contours plus
/// O(interval ends x log triangles).
double surface_move_m(const TriDexel& a, const TriDexel& b);

/// Fills stats.max_surface_move_m (surface_move_m(before, after)), stats.max_surface_move_cells (the same in cells
/// of the coarser of the two lattices) and stats.surface_move_floor_m (the largest distance of either model's ends
/// from its own contour). Contours each model once. 0 for all three when stats.identical.
void measure_surface_move(const TriDexel& before, const TriDexel& after, ResampleStats& stats);

}  // namespace tridex::compute
