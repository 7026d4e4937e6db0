// compute/contour/surface_move.cpp - the distance between two models' surfaces, through their contours.
#include "compute/contour/surface_move.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/surface_distance.hpp"

namespace tridex::compute {
namespace {

/// `model`'s whole surface, contoured on the CPU from a copy with every tile dirty.
TriMesh contoured(const TriDexel& model) {
    TriDexel copy = model;
    std::fill(copy.tiles.dirty.begin(), copy.tiles.dirty.end(), TileGrid::kWhole);
    Contourer contourer(copy);
    contourer.update(copy);
    return contourer.mesh();
}

/// The world positions of every interval end of `model`.
std::vector<Vec3> interval_ends(const TriDexel& model) {
    std::vector<Vec3> out;
    out.reserve(2 * model.interval_count());
    for_each_interval_end(model, [&](const Vec3& p, std::uint8_t) { out.push_back(p); });
    return out;
}

/// Largest distance (m) of `from`'s interval ends from `to`'s contour.
double one_way(const TriDexel& from, const TriMesh& to) {
    const std::vector<Vec3> ends = interval_ends(from);
    if (ends.empty()) return 0.0;
    TriangleGrid grid(to, 2.0 * from.lattice.cell_m);
    return max_distance(ends, grid);
}

}  // namespace

double surface_move_m(const TriDexel& a, const TriDexel& b) {
    const TriMesh ma = contoured(a), mb = contoured(b);
    return std::max(one_way(a, mb), one_way(b, ma));
}

void measure_surface_move(const TriDexel& before, const TriDexel& after, ResampleStats& stats) {
    stats.max_surface_move_m = stats.max_surface_move_cells = stats.surface_move_floor_m = 0.0;
    if (stats.identical) return;
    const TriMesh mb = contoured(before), ma = contoured(after);
    stats.max_surface_move_m = std::max(one_way(before, ma), one_way(after, mb));
    stats.max_surface_move_cells = stats.max_surface_move_m / std::max(before.lattice.cell_m, after.lattice.cell_m);
    stats.surface_move_floor_m = std::max(one_way(before, mb), one_way(after, ma));
}

}  // namespace tridex::compute
