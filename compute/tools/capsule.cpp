// compute/tools/capsule.cpp - line/capsule chord in float arithmetic.
#include "compute/tools/capsule.hpp"

#include <algorithm>
#include <cmath>

#include "core/capsule_chord.hpp"

namespace tridex::compute {
namespace {

// The float forms of core/capsule_chord.hpp's helpers (fixed order, as the shaders).
inline float min_f(float a, float b) { return chord::min_of(a, b); }
inline float max_f(float a, float b) { return chord::max_of(a, b); }
using chord::add_ball;
using chord::add_cylinder;
using chord::add_cylinder_from;
using chord::cross3;
using chord::dot3;

/// Extends [lo, hi] by t = tc + l*k over the l in [0, 1] where |p + l*g|^2 <= rr (a cap plane's path, |k| <= 1).
void add_cap_path(glm::vec3 p, glm::vec3 g, float rr, float tc, float k, float& lo, float& hi) {
    const float ga = dot3(g, g);
    const float gb = dot3(p, g);
    const float gc = dot3(p, p) - rr;
    float l0 = 0.0f, l1 = 1.0f;
    if (ga > 0.0f) {
        const float disc = gb * gb - ga * gc;
        if (!(disc >= 0.0f)) return;  // also NaN (overflow on a line nearly in the cap plane)
        const float s = std::sqrt(disc);
        const float r0 = (-gb - s) / ga, r1 = (-gb + s) / ga;
        if (!(r0 <= 1.0f && r1 >= 0.0f)) return;
        l0 = max_f(l0, r0);
        l1 = min_f(l1, r1);
    } else if (!(gc <= 0.0f)) {
        return;
    }
    const float ta = tc + l0 * k, tb = tc + l1 * k;
    lo = min_f(lo, min_f(ta, tb));
    hi = max_f(hi, max_f(ta, tb));
}

/// Extends [lo, hi] by the t where |p + t*g|^2 <= rr and l = lc + t*kl lies in [0, 1] (a cap plane's path
/// by t, |kl| < 1).
void add_cap_line(glm::vec3 p, glm::vec3 g, float rr, float lc, float kl, float& lo, float& hi) {
    const float ga = dot3(g, g);
    const float gb = dot3(p, g);
    const float gc = dot3(p, p) - rr;
    float t0 = -INFINITY, t1 = INFINITY;
    if (ga > 0.0f) {
        const float disc = gb * gb - ga * gc;
        if (!(disc >= 0.0f)) return;
        const float s = std::sqrt(disc);
        t0 = (-gb - s) / ga;
        t1 = (-gb + s) / ga;
    } else if (!(gc <= 0.0f)) {
        return;
    }
    if (kl != 0.0f) {
        const float ta = (0.0f - lc) / kl, tb = (1.0f - lc) / kl;
        t0 = max_f(t0, min_f(ta, tb));
        t1 = min_f(t1, max_f(ta, tb));
    } else if (!(lc >= 0.0f && lc <= 1.0f)) {
        return;
    }
    if (!(t0 <= t1)) return;
    lo = min_f(lo, t0);
    hi = max_f(hi, t1);
}

/// Extends [lo, hi] by where the line o + t*d crosses the cap plane h = c of the moving cylinder inside its
/// disc (h = ms + t*ds - l*cs, across = A + t*B - l*C): parametrised by l when |ds| >= |cs|, else by t, so
/// the slope of the parametrisation stays within [-1, 1] (a line nearly in the cap plane stays exact).
void add_cap(glm::vec3 A, glm::vec3 B, glm::vec3 C, float ms, float ds, float cs, float c, float rr, float& lo, float& hi) {
    if (std::fabs(ds) >= std::fabs(cs)) {
        if (ds == 0.0f) return;  // ds == cs == 0: the line never crosses the plane
        const float tc = (c - ms) / ds;
        const float k = cs / ds;
        add_cap_path(A + B * tc, B * k - C, rr, tc, k, lo, hi);
    } else {
        const float lc = (ms - c) / cs;
        const float kl = ds / cs;
        add_cap_line(A - C * lc, B - C * kl, rr, lc, kl, lo, hi);
    }
}

}  // namespace

bool capsule_chord(glm::vec3 o, glm::vec3 d, glm::vec3 a, glm::vec3 b, float r, float& t0, float& t1) {
    return chord::capsule_chord<float>(o, d, a, b, r, t0, t1);
}

AxisCapsule::AxisCapsule(int axis, glm::vec3 e, float r)
    : axis_(axis), ua_((axis + 1) % 3), va_((axis + 2) % 3), e_(e), r_(r), rr_(r * r), ee_(dot3(e, e)) {
    glm::vec3 d(0.0f);
    d[axis] = 1.0f;
    de_ = cross3(d, e);
    qa_ = dot3(de_, de_);
    eerr_ = ee_ * (r * r);
    ds_ = dot3(d, e);
}

bool AxisCapsule::chord(float ou, float ov, float& t0, float& t1) const {
    if (!(r_ > 0.0f)) return false;
    float lo = INFINITY, hi = -INFINITY;
    // The end balls (add_ball with d = e_axis, |d|^2 = 1): |m x d|^2 is the sum of m's two lateral squares and
    // m . d is m's axial component.
    const auto ball = [&](float cu, float cv, float ca) {
        const float mu = ou - cu, mv = ov - cv;
        const float disc = rr_ - (mu * mu + mv * mv);
        if (disc < 0.0f) return;
        const float mid = -(0.0f - ca);
        const float half = std::sqrt(disc);
        lo = min_f(lo, mid - half);
        hi = max_f(hi, mid + half);
    };
    ball(0.0f, 0.0f, 0.0f);
    if (ee_ > 0.0f) {
        ball(e_[ua_], e_[va_], e_[axis_]);
        glm::vec3 m(0.0f);  // the cylinder (add_cylinder with a = 0): m = o
        m[ua_] = ou;
        m[va_] = ov;
        add_cylinder_from(m, e_, ee_, de_, qa_, eerr_, ds_, lo, hi);
    }
    if (!(lo <= hi)) return false;
    t0 = lo;
    t1 = hi;
    return true;
}

CapsuleShadow::CapsuleShadow(double du, double dv, double r, double u_base, double v_base)
    : du_(du), dv_(dv), rr_(r * r), ll_(du * du + dv * dv), w_(r * std::sqrt(du * du + dv * dv)), u_base_(u_base),
      v_base_(v_base) {
    if (!(r >= 0.0)) rr_ = -1.0;
}

bool CapsuleShadow::section(int v, double& lo, double& hi) const {
    if (!(rr_ >= 0.0)) return false;
    const double ov = static_cast<double>(v) - v_base_;
    lo = INFINITY, hi = -INFINITY;
    const double h0 = rr_ - ov * ov;  // the discs at both ends
    if (h0 >= 0.0) lo = -std::sqrt(h0), hi = -lo;
    const double h1 = rr_ - (ov - dv_) * (ov - dv_);
    if (h1 >= 0.0) {
        const double q = std::sqrt(h1);
        lo = std::min(lo, du_ - q), hi = std::max(hi, du_ + q);
    }
    if (ll_ > 0.0) {  // the band: within r of the segment's line (|x*dv - ov*du| <= r*|d|), inside the segment
        double a = -INFINITY, b = INFINITY;  // (0 <= x*du + ov*dv <= |d|^2)
        if (dv_ != 0.0) {
            const double x1 = (ov * du_ - w_) / dv_, x2 = (ov * du_ + w_) / dv_;
            a = std::min(x1, x2), b = std::max(x1, x2);
        } else if (std::fabs(ov * du_) > w_) {
            b = -INFINITY;
        }
        if (du_ != 0.0) {
            const double x1 = -ov * dv_ / du_, x2 = (ll_ - ov * dv_) / du_;
            a = std::max(a, std::min(x1, x2)), b = std::min(b, std::max(x1, x2));
        } else if (ov * dv_ < 0.0 || ov * dv_ > ll_) {
            b = -INFINITY;
        }
        if (a <= b) lo = std::min(lo, a), hi = std::max(hi, b);
    }
    if (!(lo <= hi)) return false;
    lo += u_base_;  // node u lies at x = u - u_base
    hi += u_base_;
    return true;
}

bool CapsuleShadow::row(int v, int& u_lo, int& u_hi) const {
    double lo, hi;
    if (u_lo > u_hi || !section(v, lo, hi)) return false;
    return shadow_nodes(lo, hi, u_lo, u_hi);
}

bool shadow_nodes(double lo, double hi, int& u_lo, int& u_hi) {
    if (u_lo > u_hi || !(lo <= hi)) return false;
    // Clamped into [u_lo - 1, u_hi + 1] before the conversion to int.
    const double flo = static_cast<double>(u_lo), fhi = static_cast<double>(u_hi);
    u_lo = static_cast<int>(std::clamp(std::ceil(lo), flo, fhi + 1.0));
    u_hi = static_cast<int>(std::clamp(std::floor(hi), flo - 1.0, fhi));
    return u_lo <= u_hi;
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

bool swept_cylinder_chord(glm::vec3 o, glm::vec3 d, glm::vec3 e, glm::vec3 delta, float r, float& t0, float& t1) {
    const float dd = dot3(d, d);
    const float ee = dot3(e, e);
    if (!(dd > 0.0f) || !(ee > 0.0f) || !(r > 0.0f)) return false;
    const float len = std::sqrt(ee);
    const glm::vec3 n = e / len;  // unit axis: keeps the products below small enough for float
    const float rr = r * r;
    // Points o + t*d - l*delta with l in [0, 1] must lie in the cylinder at rest: axial h in [0, len] and
    // |w|^2 <= rr across the axis, with h = ms + t*ds - l*cs and w = A + t*B - l*C.
    const glm::vec3 A = cross3(o, n), B = cross3(d, n), C = cross3(delta, n);
    const float ms = dot3(o, n), ds = dot3(d, n), cs = dot3(delta, n);
    if (ds == 0.0f && cs == 0.0f && (ms < 0.0f || ms > len)) return false;  // the line never meets the slab
    float lo = INFINITY, hi = -INFINITY;
    // (1) the cylinder at both ends of the motion (l = 0, l = 1).
    add_cylinder(o, d, glm::vec3(0.0f), e, ee, r, lo, hi);
    add_cylinder(o, d, delta, e, ee, r, lo, hi);
    // (2) the two cap planes (h = 0, h = len) while the tool moves.
    add_cap(A, B, C, ms, ds, cs, 0.0f, rr, lo, hi);
    add_cap(A, B, C, ms, ds, cs, len, rr, lo, hi);
    // (3) the side walls: the t-extremes of the ellipse |w|^2 <= rr in (t, l), where l minimises |w|.
    const float cc = dot3(C, C);
    const glm::vec3 U = cross3(A, C), V = cross3(B, C);
    const float vv = dot3(V, V);
    if (cc > 0.0f && vv > 0.0f) {
        const float ub = dot3(U, V);
        const float uc = dot3(U, U) - cc * rr;
        const float disc = ub * ub - vv * uc;
        if (disc >= 0.0f) {
            const float s = std::sqrt(disc);
            const float ca = dot3(C, A), cb = dot3(C, B);
            for (int side = 0; side < 2; ++side) {
                const float t = side == 0 ? (-ub - s) / vv : (-ub + s) / vv;
                const float l = (ca + t * cb) / cc;
                const float h = ms + t * ds - l * cs;
                if (l >= 0.0f && l <= 1.0f && h >= 0.0f && h <= len) {
                    lo = min_f(lo, t);
                    hi = max_f(hi, t);
                }
            }
        }
    }
    if (!(lo <= hi)) return false;
    t0 = lo;
    t1 = hi;
    return true;
}

}  // namespace tridex::compute
