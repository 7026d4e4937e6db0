// haptics/passivity_observer.cpp - energy books and the variable damper.
#include "haptics/passivity_observer.hpp"

#include <algorithm>
#include <cmath>

namespace tridex::haptics {

Vec3 PassivityObserver::control(const Vec3& force_n, const Vec3& v, double dt_s) {
    last_alpha_ = 0.0;
    if (!(dt_s > 0.0) || !std::isfinite(dt_s) || !is_finite(force_n) || !is_finite(v)) return force_n;
    const double vv = glm::dot(v, v);
    if (!(vv > 0.0)) return force_n;
    const double e_pre = energy_ - dt_s * glm::dot(force_n, v);
    if (!(e_pre < 0.0)) return force_n;
    last_alpha_ = std::min(-e_pre / (vv * dt_s), max_alpha_);
    return force_n - last_alpha_ * v;
}

void PassivityObserver::book(const Vec3& force_held_n, const Vec3& displacement_m) {
    if (!is_finite(force_held_n) || !is_finite(displacement_m)) return;
    energy_ -= glm::dot(force_held_n, displacement_m);
    min_energy_ = std::min(min_energy_, energy_);
}

void PassivityObserver::reset() {
    energy_ = 0.0;
    min_energy_ = 0.0;
    last_alpha_ = 0.0;
}

}  // namespace tridex::haptics
