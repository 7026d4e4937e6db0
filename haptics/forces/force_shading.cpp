// haptics/forces/force_shading.cpp - height-field gradient normals at dexel ends, barycentric blend, rotation.
#include "haptics/forces/force_shading.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tridex::haptics {

namespace {

// Depth of the end of type `exit_end` on ray (iu, iv) nearest to d, if one lies within the step limit.
bool neighbour_end(const ActiveSurface::Window& w, int iu, int iv, double d, bool exit_end, double max_step,
                   double& out) {
    if (iu < 0 || iv < 0 || iu >= w.nu || iv >= w.nv) return false;
    const int c = std::min<int>(w.intervals(iu, iv), ActiveSurface::kMaxIntervals);
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < c; ++i) {
        const double e = exit_end ? w.exit(iu, iv, i) : w.enter(iu, iv, i);
        if (std::abs(e - d) < std::abs(best - d)) best = e;
    }
    if (!(std::abs(best - d) <= max_step)) return false;
    out = best;
    return true;
}

// Slope of the height field at (iu, iv) along one window direction (du, dv), grid units per window ray
// spacing; max_step = the largest accepted depth step, grid units.
double slope(const ActiveSurface::Window& w, int iu, int iv, int du, int dv, double d, bool exit_end, double max_step) {
    double lo = 0.0, hi = 0.0;
    const bool has_lo = neighbour_end(w, iu - du, iv - dv, d, exit_end, max_step, lo);
    const bool has_hi = neighbour_end(w, iu + du, iv + dv, d, exit_end, max_step, hi);
    if (has_lo && has_hi) return 0.5 * (hi - lo);
    if (has_hi) return hi - d;
    if (has_lo) return d - lo;
    return 0.0;
}

}  // namespace

Vec3 dexel_end_normal(const ActiveSurface& surface, int axis, int iu, int iv, double depth_cells, bool exit_end) {
    const ActiveSurface::Window& w = surface.sets[axis];
    const double s = exit_end ? 1.0 : -1.0;
    Vec3 n(0.0);
    n[axis] = s;
    if (iu < 0 || iv < 0 || iu >= w.nu || iv >= w.nv) return n;
    const double spacing = surface.window_spacing_cells(axis);  // grid units between neighbouring window rays
    const double max_step = kShadingMaxStepCells * spacing;
    const double gu = slope(w, iu, iv, 1, 0, depth_cells, exit_end, max_step) / spacing;
    const double gv = slope(w, iu, iv, 0, 1, depth_cells, exit_end, max_step) / spacing;
    n[(axis + 1) % 3] = -s * gu;
    n[(axis + 2) % 3] = -s * gv;
    return n / glm::length(n);  // length >= 1: the axis component is +-1
}

Vec3 blend_normals(const Vec3 normal[3], const double weight[3]) {
    const Vec3 sum = weight[0] * normal[0] + weight[1] * normal[1] + weight[2] * normal[2];
    const double len = glm::length(sum);
    if (!(len > 0.0) || !std::isfinite(len)) return Vec3(0.0);
    return sum / len;
}

Vec3 rotate_between(const Vec3& from, const Vec3& to, const Vec3& v) {
    const double c = glm::dot(from, to);
    if (!(c > -1.0 + 1e-12)) return v;
    const Vec3 k = glm::cross(from, to);  // axis times sin(angle)
    return c * v + glm::cross(k, v) + k * (glm::dot(k, v) / (1.0 + c));
}

}  // namespace tridex::haptics
