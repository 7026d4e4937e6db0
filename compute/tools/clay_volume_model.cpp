// compute/tools/clay_volume_model.cpp - predicting a clay re-sampling's volume change per edge, and solving beta on it.
#include "compute/tools/clay_volume_model.hpp"

#include <algorithm>
#include <cmath>

namespace tridex::compute {
namespace {

/// The inside length (cells, 0..1) clay_resample_ray leaves on an edge whose ends have field values p0, p1 and
/// are moved (m0, m1: their status is the field's sign) or still (their status is the old ray's, pa, pb).
/// `d_root`, when not null, gets the length's derivative in the linear root p0 / (p0 - p1): +1 or -1 where the edge
/// is split strictly inside it, else 0.
[[gnu::always_inline]] inline float inside_on_edge(float p0, bool m0, bool pa, float p1, bool m1, bool pb,
                                                 float* d_root = nullptr) {
    if (d_root) *d_root = 0.0f;
    const bool st0 = m0 ? p0 < 0.0f : pa;
    const bool st1 = m1 ? p1 < 0.0f : pb;
    if (st0 == st1) return st0 ? 1.0f : 0.0f;
    float t = 0.5f;  // the old ray disagreed with the field at its still end
    if ((p0 < 0.0f) != (p1 < 0.0f)) {
        const float w = p0 / (p0 - p1);
        t = std::clamp(w, 0.0f, 1.0f);
        if (d_root && t == w) *d_root = st0 ? 1.0f : -1.0f;
    }
    return st0 ? t : 1.0f - t;
}

/// True when a node with these values is moved for every beta in [-kClayMaxBeta, kClayMaxBeta] (s0 != 0 or
/// s1 != 0; taken as moved) and its field keeps one sign over the range, with a margin for the float rounding of
/// phi + s0 + beta * s1.
bool fixed_status(float phi, float s0, float s1) {
    if (s0 == 0.0f && s1 == 0.0f) return false;
    const double p = static_cast<double>(phi) + s0, reach = kClayMaxBeta * std::fabs(static_cast<double>(s1)) + 1e-3;
    return p > reach || p < -reach;
}

}  // namespace

void ClayVolumeModel::build(const TriDexel& model, const ClayField& f, std::span<const ClayMovedRay> moved) {
    edges_.clear();
    constant_ = 0.0;
    const ClayBox& b = f.box;
    for (const ClayMovedRay& m : moved) {
        const int axis = m.set;
        const std::vector<Interval>& ray = model.sets[axis].rays[m.index];
        int n[3];
        n[(axis + 1) % 3] = m.u;
        n[(axis + 2) % 3] = m.v;
        n[axis] = m.lo;
        const std::size_t base = b.index(n[0], n[1], n[2]);
        const std::size_t stride = b.stride(axis);
        const std::size_t nx = 2 * ray.size();
        auto old_t = [&](std::size_t k) { return (k & 1u) ? ray[k >> 1].exit : ray[k >> 1].enter; };
        std::size_t q = 0;
        const float flo = static_cast<float>(m.lo);
        while (q < nx && old_t(q) < flo) ++q;
        for (int d = m.lo; d < m.hi; ++d) {
            const std::size_t i0 = base + static_cast<std::size_t>(d - m.lo) * stride, i1 = i0 + stride;
            // The old ray on [d, d + 1): its parity at d, its inside length, its parity at d + 1.
            const float fd = static_cast<float>(d), fd1 = static_cast<float>(d + 1);
            const bool pa = (q & 1u) != 0;
            bool inside = pa;
            float prev = fd, old_in = 0.0f;
            while (q < nx && old_t(q) < fd1) {
                if (inside) old_in += old_t(q) - prev;
                prev = old_t(q);
                inside = !inside;
                ++q;
            }
            if (inside) old_in += fd1 - prev;
            const bool pb = inside;
            const bool still0 = f.s0[i0] == 0.0f && f.s1[i0] == 0.0f, still1 = f.s0[i1] == 0.0f && f.s1[i1] == 0.0f;
            if (still0 && still1) continue;  // old crossings kept
            if ((f.s1[i0] == 0.0f && f.s1[i1] == 0.0f) ||
                (fixed_status(f.phi[i0], f.s0[i0], f.s1[i0]) && fixed_status(f.phi[i1], f.s0[i1], f.s1[i1]) &&
                 (f.phi[i0] + f.s0[i0] < 0.0f) == (f.phi[i1] + f.s0[i1] < 0.0f))) {
                // No s1 end, or both ends moved and on one side of the surface for every beta: wholly in or out.
                const float in = inside_on_edge(f.phi[i0] + f.s0[i0], !still0, pa, f.phi[i1] + f.s0[i1], !still1, pb);
                constant_ += static_cast<double>(in) - old_in;
                continue;
            }
            edges_.push_back({f.phi[i0] + f.s0[i0], f.s1[i0], f.phi[i1] + f.s0[i1], f.s1[i1], old_in,
                              static_cast<std::uint8_t>((still0 ? 0u : kMoved0) | (still1 ? 0u : kMoved1) |
                                                        (pa ? kInside0 : 0u) | (pb ? kInside1 : 0u))});
        }
    }
}

double ClayVolumeModel::change(float beta, double* slope) const {
    double sum = constant_, ds = 0.0;
    for (const Edge& e : edges_) {
        const float p0 = e.a0 + beta * e.b0, p1 = e.a1 + beta * e.b1;
        float d_root;
        const float in = inside_on_edge(p0, (e.flags & kMoved0) != 0, (e.flags & kInside0) != 0, p1,
                                        (e.flags & kMoved1) != 0, (e.flags & kInside1) != 0, &d_root);
        if (slope && d_root != 0.0f) {  // the crossing slides with the linear root: d root / d beta
            const double q = static_cast<double>(p0) - p1;
            const double dr = (static_cast<double>(p0) * e.b1 - static_cast<double>(p1) * e.b0) / (q * q);
            // An edge's length changes by at most a cell over the whole range: a root that races across its edge (ends
            // both near the surface) would let one edge swamp the slope, so its rate is capped at a cell per
            // kClaySlopeSpan of beta.
            ds += d_root * std::clamp(dr, -1.0 / kClaySlopeSpan, 1.0 / kClaySlopeSpan);
        }
        sum += static_cast<double>(in - e.old_inside);
    }
    if (slope) *slope = ds / 3.0;
    return sum / 3.0;
}

float ClayVolumeModel::solve(double target, double tolerance) const {
    // A Newton step from beta = 0 on the smooth part (the crossings sliding along their edges); then outward along
    // the secant through the last two values, at least doubling the distance from 0 each time, until the change
    // brackets the target or the range ends; then regula falsi with the Anderson-Bjorck rule inside the bracket,
    // bisecting whenever two steps in a row did not halve it.
    double slope = 0.0;
    const double f0 = change(0.0f, &slope) - target;
    if (std::fabs(f0) <= tolerance) return 0.0f;
    float step = slope != 0.0 ? static_cast<float>(-f0 / slope) : 1.0f;
    if (!std::isfinite(step) || step == 0.0f) step = 1.0f;
    step = std::clamp(step, -kClayMaxBeta, kClayMaxBeta);
    float b = 0.0f, lo = 0.0f, hi = 0.0f;
    double fb = f0, flo = f0, fhi = f0;
    for (int k = 0; k < 24; ++k) {  // walk outward until the sign changes or the range ends
        const float nb = std::clamp(b + step, -kClayMaxBeta, kClayMaxBeta);
        const double fn = change(nb) - target;
        if (std::fabs(fn) <= tolerance) return nb;
        if ((fn < 0.0) != (fb < 0.0)) {
            lo = b, flo = fb, hi = nb, fhi = fn;
            break;
        }
        if (nb == b || std::fabs(nb) >= kClayMaxBeta)  // no root in range: the value nearest to the target
            return std::fabs(fn) < std::fabs(f0) ? nb : 0.0f;
        // The secant's root a quarter beyond, but at least twice as far from 0 as nb.
        const double secant = (fn - fb) / (static_cast<double>(nb) - b);
        double next = 2.0 * nb;
        if (secant != 0.0 && std::isfinite(secant)) {
            const double root = nb - fn / secant;
            if ((root - nb) * nb > 0.0) next = nb + 1.25 * (root - nb);
            if (std::fabs(next) < 2.0 * std::fabs(nb)) next = 2.0 * nb;
        }
        b = nb, fb = fn;
        step = static_cast<float>(std::clamp(next, -static_cast<double>(kClayMaxBeta), static_cast<double>(kClayMaxBeta))) - b;
        if (step == 0.0f) return std::fabs(fb) < std::fabs(f0) ? b : 0.0f;
    }
    if (lo == hi) return std::fabs(fb) < std::fabs(f0) ? b : 0.0f;
    if (lo > hi) std::swap(lo, hi), std::swap(flo, fhi);
    int side = 0;  // which end was replaced last time
    float width2 = hi - lo;  // the bracket's width two steps ago
    for (int k = 0; k < 40 && hi - lo > kClayBetaResolution; ++k) {
        if (std::min(std::fabs(flo), std::fabs(fhi)) <= tolerance) break;
        float mid = static_cast<float>((static_cast<double>(lo) * fhi - static_cast<double>(hi) * flo) / (fhi - flo));
        if (k % 2 == 0) {
            if (k > 0 && hi - lo > 0.5f * width2) mid = 0.5f * (lo + hi);  // regula falsi stalled: bisect
            width2 = hi - lo;
        }
        if (!(mid > lo && mid < hi)) mid = 0.5f * (lo + hi);
        const double fm = change(mid) - target;
        if (fm == 0.0) return mid;
        // Anderson-Bjorck: when the same end is replaced twice running, the kept end's value is scaled by
        // 1 - fm / f(replaced end) (by 1/2 when that is not positive), so the next secant reaches past the root.
        if ((fm < 0.0) == (flo < 0.0)) {
            if (side == -1) {
                const double g = 1.0 - fm / flo;
                fhi *= g > 0.0 ? g : 0.5;
            }
            lo = mid, flo = fm;
            side = -1;
        } else {
            if (side == 1) {
                const double g = 1.0 - fm / fhi;
                flo *= g > 0.0 ? g : 0.5;
            }
            hi = mid, fhi = fm;
            side = 1;
        }
    }
    return std::fabs(flo) < std::fabs(fhi) ? lo : hi;
}

}  // namespace tridex::compute
