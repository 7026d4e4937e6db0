// compute/contour/surface_move.hpp - how far one tri-dexel model's surface lies from another's (two lattices allowed):
// what a resample reports as the largest surface move.
#pragma once

#include "compute/model/tridexel.hpp"
#include "compute/tools/model_resample.hpp"

namespace tridex::compute {

/// Calls fn(world point (m), material id) for every interval end of `model`: each interval's enter and exit, set by
/// set (x, y, z), ray by ray. O(interval ends).
template <class Fn>
void for_each_interval_end(const TriDexel& model, Fn&& fn) {
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = model.sets[a];
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u)
                for (const Interval& iv : set.ray(u, v)) {
                    Vec3 g(0.0);
                    g[(a + 1) % 3] = u;
                    g[(a + 2) % 3] = v;
                    g[a] = iv.enter;
                    fn(model.lattice.to_world(g), iv.enter_material);
                    g[a] = iv.exit;
                    fn(model.lattice.to_world(g), iv.exit_material);
                }
    }
}

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
