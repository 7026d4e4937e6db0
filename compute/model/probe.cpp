// compute/model/probe.cpp - top surface point of the ray nearest a point.
#include "compute/model/probe.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tridex::compute {

bool probe_top(const TriDexel& model, int axis, const Vec3& p_m, Vec3& surface_m) {
    if (axis < 0 || axis > 2) throw Error("probe_top: axis must be 0, 1 or 2, got " + std::to_string(axis));
    if (!is_finite(p_m)) throw Error("probe_top: probe point is not finite");
    const RaySet& set = model.sets[axis];
    if (set.nu < 1 || set.nv < 1) return false;
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    const Vec3 g = model.lattice.to_grid(p_m);
    const int u = static_cast<int>(std::clamp(std::round(g[ua]), 0.0, static_cast<double>(set.nu - 1)));
    const int v = static_cast<int>(std::clamp(std::round(g[va]), 0.0, static_cast<double>(set.nv - 1)));
    const auto& ray = set.ray(u, v);
    if (ray.empty()) return false;
    Vec3 top;
    top[axis] = ray.back().exit;
    top[ua] = u;
    top[va] = v;
    surface_m = model.lattice.to_world(top);
    return true;
}

}  // namespace tridex::compute
