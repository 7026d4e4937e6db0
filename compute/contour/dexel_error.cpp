// compute/contour/dexel_error.cpp - a surface against the tri-dexel model's own surface samples.
#include "compute/contour/dexel_error.hpp"

#include <algorithm>
#include <limits>

#include "compute/contour/surface_distance.hpp"

namespace tridex::compute {

namespace {

// Calls f(grid point) for each interval end of the model's rays in the cells of `box` until it returns false.
template <typename F>
void for_each_end(const TriDexel& model, const CellBox& box, F&& f) {
    const Lattice& l = model.lattice;
    // The box's own nodes and ends: [lo, hi + 1) along each axis (the far plane is the next box's), the lattice's
    // last plane included.
    std::array<int, 3> lo{}, end{};
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::max(box.lo[a], 0);
        end[a] = box.hi[a] + 1 >= l.cells[a] ? l.cells[a] + 1 : box.hi[a] + 1;
        if (lo[a] >= end[a]) return;
    }
    for (const RaySet& set : model.sets) {
        const int a = set.axis, ua = (a + 1) % 3, va = (a + 2) % 3;
        const auto lo_t = static_cast<float>(lo[a]), end_t = static_cast<float>(end[a]);
        for (int v = lo[va]; v < end[va] && v < set.nv; ++v)
            for (int u = lo[ua]; u < end[ua] && u < set.nu; ++u)
                for (const Interval& in : set.ray(u, v)) {
                    if (in.exit < lo_t) continue;
                    if (in.enter >= end_t) break;  // the intervals are in order along the ray
                    for (const float t : {in.enter, in.exit}) {
                        if (t < lo_t || t >= end_t) continue;
                        Vec3 g(0.0);
                        g[a] = t;
                        g[ua] = u;
                        g[va] = v;
                        if (!f(g)) return;
                    }
                }
    }
}

}  // namespace

std::vector<Vec3> dexel_surface_points(const TriDexel& model, const CellBox& box) {
    std::vector<Vec3> points;
    for_each_end(model, box, [&](const Vec3& g) {
        points.push_back(model.lattice.to_world(g));
        return true;
    });
    return points;
}

bool dexel_surface_in(const TriDexel& model, const CellBox& box) {
    bool found = false;
    for_each_end(model, box, [&](const Vec3&) {
        found = true;
        return false;
    });
    return found;
}

double dexel_surface_error(const TriDexel& model, const CellBox& box, const TriMesh& surface, double bucket_m,
                           std::size_t samples) {
    const std::vector<Vec3> points = dexel_surface_points(model, box);
    if (points.empty()) return 0.0;
    if (surface.triangles.empty()) return std::numeric_limits<double>::infinity();
    TriangleGrid grid(surface, bucket_m);
    std::size_t k = 0;
    return sampled_distance(points, grid, points.size() / std::max<std::size_t>(samples, 1), k, 0.0);
}

}  // namespace tridex::compute
