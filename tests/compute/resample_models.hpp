// tests/compute/resample_models.hpp - analytic solids built ray by ray (exact chords) for the resample tests, and
// their distance from a model's interval ends.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>

#include "compute/contour/surface_move.hpp"
#include "compute/model/tridexel.hpp"

namespace resample_test {

using namespace tridex;
using namespace tridex::compute;

/// The material of a surface point (world m).
using MaterialAt = std::function<std::uint8_t(const Vec3&)>;

/// An analytic solid: per ray (world line through `point`, along axis a) its one chord [t0, t1] (world m along a),
/// or false; and the distance (m) of a point from its surface.
struct Shape {
    std::function<bool(const Vec3& point, int a, double& t0, double& t1)> chord;
    std::function<double(const Vec3& p)> distance;
};

/// A ball of radius r (m) around c.
inline Shape ball(const Vec3& c, double r) {
    Shape s;
    s.chord = [c, r](const Vec3& p, int a, double& t0, double& t1) {
        Vec3 q = p - c;
        q[a] = 0.0;
        const double h2 = r * r - glm::dot(q, q);
        if (!(h2 > 0.0)) return false;
        t0 = c[a] - std::sqrt(h2);
        t1 = c[a] + std::sqrt(h2);
        return true;
    };
    s.distance = [c, r](const Vec3& p) { return std::fabs(glm::length(p - c) - r); };
    return s;
}

/// The axis-aligned box [lo, hi] (m).
inline Shape box(const Vec3& lo, const Vec3& hi) {
    Shape s;
    s.chord = [lo, hi](const Vec3& p, int a, double& t0, double& t1) {
        for (int b = 0; b < 3; ++b)
            if (b != a && !(p[b] > lo[b] && p[b] < hi[b])) return false;
        t0 = lo[a];
        t1 = hi[a];
        return true;
    };
    s.distance = [lo, hi](const Vec3& p) {
        const Vec3 c = (lo + hi) * 0.5, e = (hi - lo) * 0.5;
        const Vec3 q = glm::abs(p - c) - e;
        const double out = glm::length(glm::max(q, Vec3(0.0)));
        return out > 0.0 ? out : -std::max({q.x, q.y, q.z});
    };
    return s;
}

/// `shape` on lattice L, each end's material from `material` (0 everywhere when empty).
inline TriDexel build(const Lattice& L, const Shape& shape, const MaterialAt& material = {}) {
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    for (int a = 0; a < 3; ++a) {
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        RaySet& set = m.sets[a];
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u) {
                Vec3 g(0.0);
                g[ua] = u;
                g[va] = v;
                const Vec3 p = L.to_world(g);
                double t0, t1;
                if (!shape.chord(p, a, t0, t1)) continue;
                Interval iv;
                iv.enter = static_cast<float>(std::max(0.0, (t0 - L.origin_m[a]) / L.cell_m));
                iv.exit = static_cast<float>(std::min<double>(L.cells[a], (t1 - L.origin_m[a]) / L.cell_m));
                Vec3 pe = p, px = p;
                pe[a] = t0;
                px[a] = t1;
                if (material) iv.enter_material = material(pe), iv.exit_material = material(px);
                if (iv.enter < iv.exit) set.ray(u, v).push_back(iv);
            }
    }
    return m;
}

/// Calls fn(world point, material) for every interval end of `m`.
template <class Fn>
void for_each_end(const TriDexel& m, Fn&& fn) {
    compute::for_each_interval_end(m, std::forward<Fn>(fn));
}

/// The largest distance (m) of an interval end of `m` from the analytic surface of `shape`.
inline double max_error_m(const TriDexel& m, const Shape& shape) {
    double worst = 0.0;
    for_each_end(m, [&](const Vec3& p, std::uint8_t) { worst = std::max(worst, shape.distance(p)); });
    return worst;
}

}  // namespace resample_test
