// haptics/grab_spring.cpp - the grab's spring to its anchor.
#include "haptics/grab_spring.hpp"

namespace tridex::haptics {

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
