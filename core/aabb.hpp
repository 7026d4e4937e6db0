// core/aabb.hpp - axis-aligned bounding box in metres.
#pragma once

#include <algorithm>
#include <limits>

#include "core/math.hpp"

namespace tridex {

/// Axis-aligned box [lo, hi] in metres. A default-constructed box is empty (lo > hi).
struct Aabb {
    Vec3 lo{std::numeric_limits<double>::infinity()};
    Vec3 hi{-std::numeric_limits<double>::infinity()};

    /// True when no point has been added (lo > hi on some axis).
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    /// Grows the box to contain p (m).
    void add(const Vec3& p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
    /// Grows the box by r (m) on every side.
    Aabb inflated(double r) const { return Aabb{lo - Vec3(r), hi + Vec3(r)}; }
    /// hi - lo, m (negative components when empty).
    Vec3 size() const { return hi - lo; }
    /// Midpoint, m.
    Vec3 centre() const { return 0.5 * (lo + hi); }
    /// True when p lies inside or on the boundary.
    bool contains(const Vec3& p) const {
        return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
    }
};

}  // namespace tridex
