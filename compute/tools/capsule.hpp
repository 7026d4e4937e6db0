// compute/tools/capsule.hpp - the chord of a line through a capsule (the swept volume of a moving ball).
#pragma once

#include <glm/glm.hpp>

namespace tridex::compute {

/// Chord of the line {o + t*d} (d unit or not; t in the units of o per unit of d) with the capsule
/// (segment a-b, radius r): returns false if the line misses it (or d is zero, or r <= 0 or NaN),
/// else true with t0 <= t1 (t0 == t1 for a tangent line). Closed form: the union of the two end-ball
/// chords and the finite-cylinder chord (the capsule is convex, so the union is one interval).
/// Arithmetic: float only, no fused multiply-add (the build uses -ffp-contract=off), dot and cross
/// products written out left to right, discriminants in the cross-product form
/// (ball: |d|^2 r^2 - |m x d|^2; cylinder via Lagrange's identity), so a GPU shader can reproduce it
/// bit for bit. Pass coordinates relative to a local origin near the tool (e.g. the segment start)
/// to keep float precision. Source: Peng et al., tri-dexel Booleans with a ball tool's sweep. The float
/// form of core/capsule_chord.hpp's chord::capsule_chord (the haptic loop uses the double form).
bool capsule_chord(glm::vec3 o, glm::vec3 d, glm::vec3 a, glm::vec3 b, float r, float& t0, float& t1);

/// capsule_chord for the rays of one ray set: the lines o + t*e_axis (o[axis] = 0, o lateral = (ou, ov) on the set's
/// two other axes (axis + 1) % 3 and (axis + 2) % 3) against the capsule from the origin to e, radius r. What does not
/// depend on the ray (|d|^2 = 1, |e|^2, d x e, r^2, ...) is computed once. chord() gives what
/// capsule_chord(o, e_axis, 0, e, r, t0, t1) gives, to the bit up to the sign of a zero t0 or t1: the products
/// with d's components (exactly 0 and 1) are exact, so they are left out, and the sums of two squares commute.
class AxisCapsule {
public:
    /// A capsule no ray meets (r = 0).
    AxisCapsule() = default;
    /// axis in 0..2 (throws nothing; other values are undefined); e and r as capsule_chord's b - a and r.
    AxisCapsule(int axis, glm::vec3 e, float r);
    /// The chord of the ray through lateral offsets (ou, ov); false when it misses (or r <= 0 or NaN).
    bool chord(float ou, float ov, float& t0, float& t1) const;

private:
    int axis_ = 0, ua_ = 1, va_ = 2;
    glm::vec3 e_{0.0f}, de_{0.0f};
    float r_ = 0.0f, rr_ = 0.0f, ee_ = 0.0f, qa_ = 0.0f, eerr_ = 0.0f, ds_ = 0.0f;
};

/// The shadow of a capsule on the rays of one set, row by row: the 2D capsule of radius r around the segment from
/// (u_base, v_base) to (u_base + du, v_base + dv) (grid units on the set's two lateral axes; the capsule's projection
/// along the set's axis). row(v) narrows [u_lo, u_hi] to the nodes u of row v inside it (in double; a caller that
/// must not lose a ray passes r with a margin for its own rounding). Returns false when the row misses it (or the
/// range is empty). Default: a shadow no row meets.
class CapsuleShadow {
public:
    CapsuleShadow() = default;
    CapsuleShadow(double du, double dv, double r, double u_base, double v_base);
    bool row(int v, int& u_lo, int& u_hi) const;
    /// The row's section [lo, hi] of the shadow, in node coordinates u (not rounded); false when the row misses.
    bool section(int v, double& lo, double& hi) const;

private:
    double du_ = 0.0, dv_ = 0.0, rr_ = -1.0, ll_ = 0.0, w_ = 0.0, u_base_ = 0.0, v_base_ = 0.0;
};

/// Narrows [u_lo, u_hi] to the nodes u with lo <= u <= hi; false when none is left (or lo > hi or NaN).
bool shadow_nodes(double lo, double hi, int& u_lo, int& u_hi);

/// Chord of the line {o + t*d} with the solid finite cylinder of radius r whose axis runs from a to
/// a + e, closed by flat caps at both ends (a flat-end mill: a is the centre of the flat end, e the
/// shank). Same contract and arithmetic rules as capsule_chord; false when the line misses it, d or e
/// is zero, or r <= 0 or NaN. The cylinder is convex, so the chord is one interval.
bool cylinder_chord(glm::vec3 o, glm::vec3 d, glm::vec3 a, glm::vec3 e, float r, float& t0, float& t1);

/// Chord of the line {o + t*d} with the volume swept by the flat-end cylinder of cylinder_chord (flat end
/// centred at the origin, shank e, radius r) moved without turning from the origin to `delta`: the convex
/// hull of the cylinder at both ends of the motion, so the chord is one interval. Closed form, exact up to
/// float rounding for every motion (across, along or oblique to the axis): in the plane of parameters
/// (t, l), l in [0, 1] the motion's fraction, the points with o + t*d - l*delta inside the resting cylinder
/// form a convex region (an ellipse, or a strip, cut by the axial slab and 0 <= l <= 1); its t-extremes lie
/// (1) on l = 0 or l = 1 (cylinder_chord at both ends), (2) on a cap plane (a quadratic in l along it) or
/// (3) at the ellipse's own t-extremes (the flat side walls of the swept stadium). Arithmetic as
/// capsule_chord (float, fixed order, no contraction; the axis is normalised first, n = e / sqrt(e.e), so
/// products stay within float range); the GPU kernel (shaders/dexel_sweep.comp) repeats it step for step.
/// False when the line misses the volume, d or e is zero, or r <= 0 or NaN. Source: the swept volume of a
/// convex tool under translation is the Minkowski sum of the tool and the motion segment (the convex hull
/// of its two end poses); the exact ray chord is our own derivation for the flat-end cylinder.
bool swept_cylinder_chord(glm::vec3 o, glm::vec3 d, glm::vec3 e, glm::vec3 delta, float r, float& t0, float& t1);

}  // namespace tridex::compute
