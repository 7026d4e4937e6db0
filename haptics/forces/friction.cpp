// haptics/forces/friction.cpp - stick or slide on the friction cone.
#include "haptics/forces/friction.hpp"

namespace tridex::haptics {

FrictionStep friction_cone(const Vec3& stick_m, const Vec3& frictionless_m, double depth_m, double mu_s, double mu_d,
                           bool was_sliding) {
    FrictionStep s;
    s.proxy_m = frictionless_m;
    if (!(depth_m > 0.0)) return s;
    const Vec3 t = stick_m - frictionless_m;
    const double len = glm::length(t);
    const double mu = was_sliding ? mu_d : mu_s;
    if (len <= mu * depth_m) {
        s.proxy_m = stick_m;
        return s;
    }
    // Slide: keep the tangential offset at the dynamic cone's edge, in the direction it was dragged.
    s.sliding = true;
    if (len > 0.0) s.proxy_m = frictionless_m + t * (mu_d * depth_m / len);
    return s;
}

}  // namespace tridex::haptics
