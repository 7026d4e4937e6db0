// haptics/forces/friction.hpp - Coulomb friction on the god-object (friction cone).
#pragma once

#include "core/math.hpp"

namespace tridex::haptics {

/// Where the friction cone puts the proxy, and whether it slides.
struct FrictionStep {
    Vec3 proxy_m{0.0};     ///< the proxy (m), on the constraint plane
    bool sliding = false;  ///< true when the proxy slid this step (tangential force at the dynamic cone)
};

/// Coulomb friction on a god-object whose spring to the HIP is isotropic (the friction-cone god-object
/// of Harwin & Melder, "Improved haptic rendering for multi-finger manipulation using friction cone
/// based god-objects", Eurohaptics 2002; static and dynamic coefficients as the proSense parameters of
/// Singapogu's thesis, ch. 3). Inputs, all on one constraint plane with normal n:
/// - stick_m: where the proxy would stay if it sticks (the previous proxy projected on the plane), m;
/// - frictionless_m: the frictionless proxy (the HIP projected on the plane), m;
/// - depth_m: the HIP's penetration along n, m (the normal spring force is k*depth_m, the tangential
///   one k*|stick - frictionless|, so the cone test needs no stiffness).
/// The proxy sticks (returns stick_m) while |stick - frictionless| <= mu*depth, mu = mu_s, or mu_d when
/// it slid on the previous step (was_sliding); otherwise it slides back along the line to the
/// frictionless proxy until |F_t| = mu_d*|F_n|: frictionless + (stick - frictionless) * mu_d*depth/|t|.
/// With mu_s = mu_d = 0 the result is frictionless_m exactly. depth_m <= 0 (no normal force) gives
/// frictionless_m. Needs finite inputs and 0 <= mu_d <= mu_s (checked where the materials are made).
FrictionStep friction_cone(const Vec3& stick_m, const Vec3& frictionless_m, double depth_m, double mu_s, double mu_d,
                           bool was_sliding);

}  // namespace tridex::haptics
