// haptics/forces/force_clamp.cpp - magnitude clamp with non-finite rejection.
#include "haptics/forces/force_clamp.hpp"

#include <algorithm>
#include <cmath>

namespace tridex::haptics {

Vec3 clamp_magnitude(const Vec3& v, double max_norm) {
    if (!is_finite(v) || !std::isfinite(max_norm) || max_norm <= 0.0) return Vec3(0.0);
    const double n = glm::length(v);
    if (!std::isfinite(n)) {
        // |v| overflowed: rescale first so the direction survives.
        const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
        const Vec3 u = v / m;
        return u * (max_norm / glm::length(u));
    }
    if (n <= max_norm) return v;
    return v * (max_norm / n);
}

}  // namespace tridex::haptics
