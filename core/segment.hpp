// core/segment.hpp - a straight tool move from a to b, in metres.
#pragma once

#include "core/aabb.hpp"
#include "core/math.hpp"

namespace tridex {

/// A line segment from a to b (m). a == b is a valid, zero-length segment (a point).
struct Segment {
    Vec3 a{0.0};
    Vec3 b{0.0};

    /// Length |b - a|, m.
    double length() const { return glm::length(b - a); }
    /// Bounding box of the segment inflated by r (m): the box of a capsule of radius r.
    Aabb bounds(double r) const {
        Aabb box;
        box.add(a);
        box.add(b);
        return box.inflated(r);
    }
};

}  // namespace tridex
