// core/capsule_chord.hpp - the chord of a line through a ball, a finite cylinder and a capsule, in float or double.
// The sculpting engine cuts with the float form (its GPU kernels repeat it bit for bit); the haptic loop cuts its
// own recent sweeps out of a snapshot with the double form.
#pragma once

#include <cmath>
#include <limits>

#include <glm/glm.hpp>

namespace tridex::chord {

/// std::fmin as the C library defines it (a NaN operand yields the other operand; otherwise the smaller, the second
/// on a tie), written inline: the compiler keeps the library call, and this runs several times per ray of a sweep.
template <class T>
inline T min_of(T a, T b) {
    return (a < b || b != b) ? a : b;
}
/// std::fmax likewise.
template <class T>
inline T max_of(T a, T b) {
    return (a > b || b != b) ? a : b;
}

/// p . q written out left to right, so the evaluation order is fixed (a shader uses the same order).
template <class T>
inline T dot3(glm::vec<3, T> p, glm::vec<3, T> q) {
    return p.x * q.x + p.y * q.y + p.z * q.z;
}
/// p x q written out, for the same reason.
template <class T>
inline glm::vec<3, T> cross3(glm::vec<3, T> p, glm::vec<3, T> q) {
    return glm::vec<3, T>(p.y * q.z - p.z * q.y, p.z * q.x - p.x * q.z, p.x * q.y - p.y * q.x);
}

/// Extends [lo, hi] by the chord of the line o + t*d (dd = |d|^2 > 0) with the ball (centre c, radius r), in the
/// cross-product form: disc = dd * r^2 - |(o - c) x d|^2.
template <class T>
inline void add_ball(glm::vec<3, T> o, glm::vec<3, T> d, T dd, glm::vec<3, T> c, T r, T& lo, T& hi) {
    const glm::vec<3, T> m = o - c;
    const glm::vec<3, T> md = cross3(m, d);
    const T disc = dd * (r * r) - dot3(md, md);  // = dd * (r^2 - squared distance of c from the line)
    if (disc < T(0)) return;
    const T mid = -dot3(m, d) / dd;
    const T half = std::sqrt(disc) / dd;
    lo = min_of(lo, mid - half);
    hi = max_of(hi, mid + half);
}

/// Extends [lo, hi] by the chord of the line o + t*d with the finite cylinder (axis a -> a + e, radius r), given
/// m = o - a, e, ee = |e|^2 > 0 and the terms that do not depend on o: de = d x e, qa = |de|^2, eerr = ee * r^2 and
/// ds = d . e (Lagrange's identity: qa = ee*dd - (d.e)^2).
template <class T>
[[gnu::always_inline]] inline void add_cylinder_from(glm::vec<3, T> m, glm::vec<3, T> e, T ee, glm::vec<3, T> de, T qa,
                                                     T eerr, T ds, T& lo, T& hi) {
    constexpr T kInf = std::numeric_limits<T>::infinity();
    const glm::vec<3, T> me = cross3(m, e);
    const T qb = dot3(me, de);         // (m x e).(d x e) = ee*(m.d) - (m.e)*(d.e)
    const T qc = dot3(me, me) - eerr;  // ee * (squared distance of o from the axis - r^2)
    const T ms = dot3(m, e);           // axial position: s(t) = (ms + t*ds) / ee in [0, 1]
    T c0, c1;
    if (qa > T(0)) {
        const T disc = qb * qb - qa * qc;
        if (disc < T(0)) return;
        const T s = std::sqrt(disc);
        c0 = (-qb - s) / qa;
        c1 = (-qb + s) / qa;
    } else {  // line parallel to the axis: inside the infinite cylinder everywhere or nowhere
        if (qc > T(0)) return;
        c0 = -kInf;
        c1 = kInf;
    }
    if (ds != T(0)) {  // clip to the slab between the end caps
        const T ta = -ms / ds, tb = (ee - ms) / ds;
        c0 = max_of(c0, min_of(ta, tb));
        c1 = min_of(c1, max_of(ta, tb));
    } else if (ms < T(0) || ms > ee) {
        return;
    }
    if (!(c0 <= c1)) return;
    lo = min_of(lo, c0);
    hi = max_of(hi, c1);
}

/// Extends [lo, hi] by the chord of the line o + t*d with the finite cylinder (axis a -> a + e, radius r),
/// ee = |e|^2 > 0.
template <class T>
inline void add_cylinder(glm::vec<3, T> o, glm::vec<3, T> d, glm::vec<3, T> a, glm::vec<3, T> e, T ee, T r, T& lo,
                         T& hi) {
    const glm::vec<3, T> de = cross3(d, e);
    add_cylinder_from(o - a, e, ee, de, dot3(de, de), ee * (r * r), dot3(d, e), lo, hi);
}

/// Chord of the line {o + t*d} (d unit or not; t in the units of o per unit of d) with the capsule (segment a-b,
/// radius r, the swept volume of a ball moved from a to b): returns false if the line misses it (or d is zero, or
/// r <= 0 or NaN), else true with t0 <= t1 (t0 == t1 for a tangent line). Closed form: the union of the two end-ball
/// chords and the finite-cylinder chord (the capsule is convex, so the union is one interval). T is float or
/// double; with float, no fused multiply-add (-ffp-contract=off) and the fixed order above, a GPU shader reproduces
/// it bit for bit. Pass coordinates relative to a local origin near the tool to keep precision. Source: Peng et al.,
/// tri-dexel Booleans with a ball tool's sweep.
template <class T>
inline bool capsule_chord(glm::vec<3, T> o, glm::vec<3, T> d, glm::vec<3, T> a, glm::vec<3, T> b, T r, T& t0, T& t1) {
    const T dd = dot3(d, d);
    if (!(dd > T(0)) || !(r > T(0))) return false;
    T lo = std::numeric_limits<T>::infinity(), hi = -std::numeric_limits<T>::infinity();
    add_ball(o, d, dd, a, r, lo, hi);
    const glm::vec<3, T> e = b - a;
    const T ee = dot3(e, e);
    if (ee > T(0)) {
        add_ball(o, d, dd, b, r, lo, hi);
        add_cylinder(o, d, a, e, ee, r, lo, hi);
    }
    if (!(lo <= hi)) return false;
    t0 = lo;
    t1 = hi;
    return true;
}

}  // namespace tridex::chord
