// haptics/grab_spring.cpp - the grab's spring to its anchor.
#include "haptics/grab_spring.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tridex::haptics {

bool cap_grab_stiffness(double& k, double cap_n_per_m) {
    if (!(std::isfinite(k) && k >= 0.0))
        throw Error("HapticLoopConfig.grab_stiffness_n_per_m = " + std::to_string(k) + " must be finite and >= 0 N/m");
    if (!(cap_n_per_m > 0.0 && k > cap_n_per_m)) return false;
    k = cap_n_per_m;
    return true;
}

Vec3 GrabSpring::update(bool grabbing, bool touching, const Vec3& hip_m) {
    if (!grabbing || !is_finite(hip_m)) {
        gripping_ = false;
        return Vec3(0.0);
    }
    if (!gripping_) {
        if (!touching) return Vec3(0.0);
        gripping_ = true;
        anchor_m_ = hip_m;
    }
    return -k_ * (hip_m - anchor_m_);
}

}  // namespace tridex::haptics
