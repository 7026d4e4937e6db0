// core/distance_grid.cpp - trilinear sampling of a signed distance grid.
#include "core/distance_grid.hpp"

#include <cmath>

namespace tridex {

bool DistanceGrid::valid() const {
    if (!(std::isfinite(cell_m) && cell_m > 0.0) || !is_finite(origin_m)) return false;
    for (int n : nodes)
        if (n < 2) return false;
    return distance_m.size() == static_cast<std::size_t>(nodes[0]) * nodes[1] * nodes[2];
}

bool DistanceGrid::sample(const Vec3& p_m, double& distance, Vec3& gradient) const {
    const Vec3 g = (p_m - origin_m) / cell_m;
    std::array<int, 3> c{};
    std::array<double, 3> t{};
    for (int a = 0; a < 3; ++a) {
        // Also refuses NaN: every comparison with it is false.
        if (!(g[a] >= 0.0 && g[a] <= static_cast<double>(nodes[a] - 1))) return false;
        c[a] = static_cast<int>(g[a]);
        if (c[a] > nodes[a] - 2) c[a] = nodes[a] - 2;
        t[a] = g[a] - c[a];
    }
    double v[2][2][2];
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) v[dz][dy][dx] = distance_m[index(c[0] + dx, c[1] + dy, c[2] + dz)];
    const double x = t[0], y = t[1], z = t[2];
    // Along x first, then y, then z; the gradient differentiates the same blend.
    double vy[2][2], dvy[2][2];
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy) {
            vy[dz][dy] = v[dz][dy][0] + x * (v[dz][dy][1] - v[dz][dy][0]);
            dvy[dz][dy] = v[dz][dy][1] - v[dz][dy][0];
        }
    const double a0 = vy[0][0] + y * (vy[0][1] - vy[0][0]), a1 = vy[1][0] + y * (vy[1][1] - vy[1][0]);
    const double gx0 = dvy[0][0] + y * (dvy[0][1] - dvy[0][0]), gx1 = dvy[1][0] + y * (dvy[1][1] - dvy[1][0]);
    const double gy0 = vy[0][1] - vy[0][0], gy1 = vy[1][1] - vy[1][0];
    distance = a0 + z * (a1 - a0);
    gradient = Vec3(gx0 + z * (gx1 - gx0), gy0 + z * (gy1 - gy0), a1 - a0) / cell_m;
    return true;
}

}  // namespace tridex
