// compute/tools/capsule.cpp - line/capsule chord in float arithmetic.
#include "compute/tools/capsule.hpp"

#include <cmath>

namespace tridex::compute {
namespace {

// Written out so the evaluation order is fixed (a shader uses the same order).
float dot3(glm::vec3 p, glm::vec3 q) { return p.x * q.x + p.y * q.y + p.z * q.z; }
glm::vec3 cross3(glm::vec3 p, glm::vec3 q) {
    return glm::vec3(p.y * q.z - p.z * q.y, p.z * q.x - p.x * q.z, p.x * q.y - p.y * q.x);
}

/// Extends [lo, hi] by the chord of the line with the ball (c, r).
void add_ball(glm::vec3 o, glm::vec3 d, float dd, glm::vec3 c, float r, float& lo, float& hi) {
    const glm::vec3 m = o - c;
    const glm::vec3 md = cross3(m, d);
    const float disc = dd * (r * r) - dot3(md, md);  // = dd * (r^2 - squared distance of c from the line)
    if (disc < 0.0f) return;
    const float mid = -dot3(m, d) / dd;
    const float half = std::sqrt(disc) / dd;
    lo = std::fmin(lo, mid - half);
    hi = std::fmax(hi, mid + half);
}

/// Extends [lo, hi] by the chord of the line with the finite cylinder (axis a -> a+e, radius r), ee = |e|^2 > 0.
void add_cylinder(glm::vec3 o, glm::vec3 d, glm::vec3 a, glm::vec3 e, float ee, float r, float& lo, float& hi) {
    const glm::vec3 m = o - a;
    const glm::vec3 me = cross3(m, e);
    const glm::vec3 de = cross3(d, e);
    const float qa = dot3(de, de);                 // |d x e|^2 = ee*dd - (d.e)^2
    const float qb = dot3(me, de);                 // (m x e).(d x e) = ee*(m.d) - (m.e)*(d.e)
    const float qc = dot3(me, me) - ee * (r * r);  // ee * (squared distance of o from the axis - r^2)
    const float ms = dot3(m, e), ds = dot3(d, e);  // axial position: s(t) = (ms + t*ds) / ee in [0, 1]
    float c0, c1;
    if (qa > 0.0f) {
        const float disc = qb * qb - qa * qc;
        if (disc < 0.0f) return;
        const float s = std::sqrt(disc);
        c0 = (-qb - s) / qa;
        c1 = (-qb + s) / qa;
    } else {  // line parallel to the axis: inside the infinite cylinder everywhere or nowhere
        if (qc > 0.0f) return;
        c0 = -INFINITY;
        c1 = INFINITY;
    }
    if (ds != 0.0f) {  // clip to the slab between the end caps
        const float ta = -ms / ds, tb = (ee - ms) / ds;
        c0 = std::fmax(c0, std::fmin(ta, tb));
        c1 = std::fmin(c1, std::fmax(ta, tb));
    } else if (ms < 0.0f || ms > ee) {
        return;
    }
    if (!(c0 <= c1)) return;
    lo = std::fmin(lo, c0);
    hi = std::fmax(hi, c1);
}

}  // namespace

bool capsule_chord(glm::vec3 o, glm::vec3 d, glm::vec3 a, glm::vec3 b, float r, float& t0, float& t1) {
    const float dd = dot3(d, d);
    if (!(dd > 0.0f) || !(r > 0.0f)) return false;
    float lo = INFINITY, hi = -INFINITY;
    add_ball(o, d, dd, a, r, lo, hi);
    const glm::vec3 e = b - a;
    const float ee = dot3(e, e);
    if (ee > 0.0f) {
        add_ball(o, d, dd, b, r, lo, hi);
        add_cylinder(o, d, a, e, ee, r, lo, hi);
    }
    if (!(lo <= hi)) return false;
    t0 = lo;
    t1 = hi;
    return true;
}

bool cylinder_chord(glm::vec3 o, glm::vec3 d, glm::vec3 a, glm::vec3 e, float r, float& t0, float& t1) {
    const float dd = dot3(d, d);
    const float ee = dot3(e, e);
    if (!(dd > 0.0f) || !(ee > 0.0f) || !(r > 0.0f)) return false;
    float lo = INFINITY, hi = -INFINITY;
    add_cylinder(o, d, a, e, ee, r, lo, hi);
    if (!(lo <= hi)) return false;
    t0 = lo;
    t1 = hi;
    return true;
}

}  // namespace tridex::compute
