// compute/contour/contour_sample.cpp - node occupancy blocks and edge crossings read from the rays.
#include "compute/contour/contour_sample.hpp"

#include <algorithm>
#include <cmath>

namespace tridex::compute::contour {

void OccupancyBlock::fill(const TriDexel& model, const Node& lo) {
    lo_ = lo;
    rows_.fill(0u);
    const auto& cells = model.lattice.cells;
    const RaySet& xs = model.sets[0];
    // Interior nodes only: boundary nodes stay outside.
    const int i_lo = std::max(1, lo[0]), i_hi = std::min(cells[0] - 1, lo[0] + kSpan - 1);
    if (i_lo > i_hi) return;
    for (int k = std::max(1, lo[2]); k <= std::min(cells[2] - 1, lo[2] + kSpan - 1); ++k) {
        for (int j = std::max(1, lo[1]); j <= std::min(cells[1] - 1, lo[1] + kSpan - 1); ++j) {
            std::uint32_t mask = 0u;
            for (const Interval& iv : xs.ray(j, k)) {
                if (!(iv.enter <= iv.exit)) continue;  // NaN or reversed: not a span (never crash on bad data)
                // Nodes i with enter <= i < exit.
                const double first = std::ceil(static_cast<double>(iv.enter));
                const double last = std::ceil(static_cast<double>(iv.exit)) - 1.0;
                if (last < i_lo) continue;
                if (first > i_hi) break;
                const int b0 = static_cast<int>(std::max<double>(first, i_lo)) - lo[0];
                const int b1 = static_cast<int>(std::min<double>(last, i_hi)) - lo[0];
                if (b0 > b1) continue;
                mask |= static_cast<std::uint32_t>((std::uint64_t{2} << b1) - (std::uint64_t{1} << b0));
            }
            rows_[static_cast<std::size_t>(j - lo[1]) + kSpan * static_cast<std::size_t>(k - lo[2])] = mask;
        }
    }
}

int OccupancyBlock::config(const Node& n) const {
    const int b = n[0] - lo_[0];
    int cfg = 0;
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy) {
            const std::uint32_t r = (row(n[1] + dy, n[2] + dz) >> b) & 3u;  // corners x = 0, 1
            cfg |= static_cast<int>(r) << (2 * dy + 4 * dz);
        }
    return cfg;
}

EdgeCrossing edge_crossing(const TriDexel& model, int a, const Node& n, bool start_inside) {
    const auto& ray = model.sets[a].ray(n[(a + 1) % 3], n[(a + 2) % 3]);
    const double lo = n[a], hi = lo + 1.0;
    // Walk the interval ends in ascending order.
    bool found = false, best_exit = false;
    double best = 0.0;
    std::uint8_t best_mat = 0;
    for (const Interval& iv : ray) {
        for (int side = 0; side < 2; ++side) {
            const double e = side == 0 ? iv.enter : iv.exit;
            const std::uint8_t mat = side == 0 ? iv.enter_material : iv.exit_material;
            if (!std::isfinite(e) || e < lo) continue;
            if (e > hi) break;
            if (start_inside && side == 0 && e == lo) continue;  // the inside node's own enter: not a crossing
            if (start_inside) return {e, false, mat, side == 1};  // first end from the low (inside) node
            best = e;                                             // last end, first from the high (inside) node
            best_mat = mat;
            best_exit = side == 1;
            found = true;
        }
        if (static_cast<double>(iv.exit) > hi) break;
    }
    if (found) return {best, false, best_mat, best_exit};
    // The ray disagrees with the occupancy: nearest end within half a cell, clamped into the edge.
    double nearest_gap = 0.5;
    bool near = false;
    for (const Interval& iv : ray)
        for (int side = 0; side < 2; ++side) {
            const double e = side == 0 ? iv.enter : iv.exit;
            if (!std::isfinite(e)) continue;
            const double gap = e < lo ? lo - e : e - hi;
            if (gap <= nearest_gap) {
                nearest_gap = gap;
                best = std::clamp(e, lo, hi);
                best_mat = side == 0 ? iv.enter_material : iv.exit_material;
                best_exit = side == 1;
                near = true;
            }
        }
    return {near ? best : lo + 0.5, true, near ? best_mat : std::uint8_t{0}, near && best_exit};
}

bool inside_at(const std::vector<Interval>& ray, double t) {
    for (const Interval& iv : ray)
        if (static_cast<double>(iv.enter) <= t && t < static_cast<double>(iv.exit)) return true;
    return false;
}

bool node_inside(const TriDexel& model, const Node& n) {
    for (int a = 0; a < 3; ++a)
        if (n[a] < 1 || n[a] > model.lattice.cells[a] - 1) return false;
    return inside_at(model.sets[0].ray(n[1], n[2]), static_cast<double>(n[0]));
}

Vec3 crossing_point(const Node& n, int a, const EdgeCrossing& x) {
    Vec3 p(n[0], n[1], n[2]);
    p[a] = x.t;
    return p;
}

}  // namespace tridex::compute::contour
