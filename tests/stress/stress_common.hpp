// tests/stress/stress_common.hpp - shared helpers of the stress tests: box workpieces, the per-ray
// invariant check, containment of one ray's solid in another's, bitwise ray comparison, and an exact
// (double) ray-capsule chord.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "compute/mesh/scan_convert.hpp"
#include "compute/model/tridexel.hpp"
#include "core/primitives.hpp"

namespace tridex::test {

/// A model on an n^3-cell lattice (cell cell_m, origin origin_m) holding the box [lo, hi]^3 (grid
/// units); empty when hi <= lo.
inline compute::TriDexel stress_box(int n, double lo, double hi, const Vec3& origin_m = Vec3(0.3, -0.2, 0.7),
                                    double cell_m = 1e-3) {
    compute::Lattice L;
    L.origin_m = origin_m;
    L.cell_m = cell_m;
    L.cells = {n, n, n};
    compute::TriDexel m = compute::TriDexel::empty(L, std::size_t{1} << 31);
    if (hi > lo) compute::scan_convert(box_mesh(Aabb{L.to_world(Vec3(lo)), L.to_world(Vec3(hi))}), m);
    return m;
}

/// The ray invariants: every end finite and within 2^24 cells, enter < exit, intervals sorted, disjoint
/// and not touching (exit of one < enter of the next). Empty string when they hold, else what broke.
inline std::string ray_violation(const std::vector<compute::Interval>& ray) {
    for (std::size_t k = 0; k < ray.size(); ++k) {
        const compute::Interval& iv = ray[k];
        const bool finite = std::isfinite(iv.enter) && std::isfinite(iv.exit) && std::fabs(iv.enter) <= 16777216.0f &&
                            std::fabs(iv.exit) <= 16777216.0f;
        const bool ordered = iv.enter < iv.exit;
        const bool apart = k == 0 || ray[k - 1].exit < iv.enter;
        if (finite && ordered && apart) continue;
        std::ostringstream why;  // built only for a broken ray: the checks above run on millions of rays
        if (!finite)
            why << "interval " << k << " not finite or beyond 2^24: [" << iv.enter << ", " << iv.exit << "]";
        else if (!ordered)
            why << "interval " << k << " has enter >= exit: [" << iv.enter << ", " << iv.exit << "]";
        else
            why << "intervals " << k - 1 << ", " << k << " overlap or touch: exit " << ray[k - 1].exit << " enter " << iv.enter;
        return why.str();
    }
    return {};
}

/// True when every point of ray a's solid lies in ray b's solid (both must satisfy the invariants).
inline bool solid_within(const std::vector<compute::Interval>& a, const std::vector<compute::Interval>& b) {
    std::size_t j = 0;
    for (const compute::Interval& x : a) {
        while (j < b.size() && b[j].exit < x.exit) ++j;
        if (j == b.size() || b[j].enter > x.enter) return false;
    }
    return true;
}

/// Bitwise equality of two rays, depths and materials.
inline bool same_bits(const std::vector<compute::Interval>& x, const std::vector<compute::Interval>& y) {
    if (x.size() != y.size()) return false;
    for (std::size_t k = 0; k < x.size(); ++k)
        if (std::memcmp(&x[k].enter, &y[k].enter, 4) != 0 || std::memcmp(&x[k].exit, &y[k].exit, 4) != 0 ||
            x[k].enter_material != y[k].enter_material || x[k].exit_material != y[k].exit_material)
            return false;
    return true;
}

/// Exact chord (double) of the line p(t) = o + t*e_axis with the capsule of radius r around segment
/// a-b (all in grid units): false when the line misses it or only touches it (zero length).
inline bool exact_capsule_chord(const Vec3& o, int axis, const Vec3& a, const Vec3& b, double r, double& t0, double& t1) {
    Vec3 e(0.0);
    e[axis] = 1.0;
    double lo = INFINITY, hi = -INFINITY;
    auto ball = [&](const Vec3& c) {  // |o + t e - c| = r
        const Vec3 w = o - c;
        const double bq = glm::dot(w, e), cq = glm::dot(w, w) - r * r, disc = bq * bq - cq;
        if (disc > 0.0) {
            const double s = std::sqrt(disc);
            lo = std::min(lo, -bq - s);
            hi = std::max(hi, -bq + s);
        }
    };
    ball(a);
    ball(b);
    const Vec3 d = b - a;
    const double dd = glm::dot(d, d);
    if (dd > 0.0) {  // the open cylinder: distance to the line a-b below r and projection in [0, 1]
        const Vec3 w = o - a;
        const Vec3 ep = e - d * (glm::dot(e, d) / dd), wp = w - d * (glm::dot(w, d) / dd);
        const double A = glm::dot(ep, ep), B = glm::dot(ep, wp), C = glm::dot(wp, wp) - r * r;
        double c0 = -INFINITY, c1 = INFINITY;
        bool any = true;
        if (A > 1e-300) {
            const double disc = B * B - A * C;
            if (disc > 0.0) {
                c0 = (-B - std::sqrt(disc)) / A;
                c1 = (-B + std::sqrt(disc)) / A;
            } else {
                any = false;
            }
        } else if (C >= 0.0) {
            any = false;
        }
        // projection s(t) = (w.d + t e.d) / dd in [0, 1]
        const double s0 = glm::dot(w, d) / dd, sd = glm::dot(e, d) / dd;
        if (sd != 0.0) {
            double ta = (0.0 - s0) / sd, tb = (1.0 - s0) / sd;
            if (ta > tb) std::swap(ta, tb);
            c0 = std::max(c0, ta);
            c1 = std::min(c1, tb);
        } else if (s0 < 0.0 || s0 > 1.0) {
            any = false;
        }
        if (any && c1 > c0) {
            lo = std::min(lo, c0);
            hi = std::max(hi, c1);
        }
    }
    if (!(hi > lo)) return false;
    t0 = lo;
    t1 = hi;
    return true;
}

}  // namespace tridex::test
