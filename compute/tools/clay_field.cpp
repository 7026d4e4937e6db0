// compute/tools/clay_field.cpp - the clay tools' node field: built from the three ray sets (re-sampling it into them
// is compute/tools/clay_resample.cpp).
#include "compute/tools/clay_field.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include "compute/tools/capsule.hpp"
#include "compute/tools/clay_resample.hpp"

namespace tridex::compute {
namespace {

/// Distance (cells) from `depth` to the ray's nearest interval end within `search` cells, and whether the
/// depth is inside (enter < depth <= exit).
void ray_probe(const std::vector<Interval>& ray, float depth, float search, bool& inside, float& dist) {
    inside = false;
    dist = search;
    for (const Interval& iv : ray) {
        // The intervals are sorted: once one starts `dist` or more past the depth, no later end is nearer and none
        // holds the depth.
        if (iv.enter - depth >= dist) break;
        if (iv.enter < depth && depth <= iv.exit) inside = true;
        dist = std::min(dist, std::fabs(iv.enter - depth));
        dist = std::min(dist, std::fabs(iv.exit - depth));
    }
}
}  // namespace

bool clay_ray_inside(const std::vector<Interval>& ray, float depth) {
    for (const Interval& iv : ray)
        if (iv.enter < depth && depth <= iv.exit) return true;
    return false;
}

float clay_node_phi(const TriDexel& model, int i, int j, int k, float search) {
    const int n[3] = {i, j, k};
    int votes = 0;
    float inv = 0.0f;
    bool touching = false;
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = model.sets[a];
        bool in;
        float d;
        ray_probe(set.ray(n[(a + 1) % 3], n[(a + 2) % 3]), static_cast<float>(n[a]), search, in, d);
        votes += in ? 1 : 0;
        if (d == 0.0f)
            touching = true;
        else if (d < search)
            inv += 1.0f / (d * d);
    }
    float mag = search;
    if (touching)
        mag = 0.0f;
    else if (inv > 0.0f)
        mag = std::min(mag, 1.0f / std::sqrt(inv));
    mag = std::max(mag, 1e-6f);  // never 0: the sign carries the status
    return votes >= 2 ? -mag : mag;
}

namespace {
/// phi of `m` at grid point p, trilinear in the 8 nodes around it (clamped to the lattice).
float phi_at_point(const TriDexel& m, const float p[3]) {
    ClayField f;
    f.search = 64.0f;  // a measure, not a field to offset: look far
    for (int a = 0; a < 3; ++a) {
        const int b = std::clamp(static_cast<int>(std::floor(p[a])), 0, std::max(m.lattice.cells[a] - 1, 0));
        f.box.lo[a] = b;
        f.box.hi[a] = std::min(b + 1, m.lattice.cells[a]);
    }
    clay_build_phi(m, f);
    return clay_phi_at(f, p[0], p[1], p[2]);
}

double max_distance_of_ends(const TriDexel& from, const TriDexel& to) {
    double worst = 0.0;
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = from.sets[a];
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u) {
                const auto& ray = set.ray(u, v);
                if (clay_same_ray(ray, to.sets[a].ray(u, v))) continue;
                for (const Interval& iv : ray)
                    for (const float t : {iv.enter, iv.exit}) {
                        float p[3];
                        p[(a + 1) % 3] = static_cast<float>(u);
                        p[(a + 2) % 3] = static_cast<float>(v);
                        p[a] = t;
                        worst = std::max(worst, static_cast<double>(std::fabs(phi_at_point(to, p))));
                    }
            }
    }
    return worst;
}
}  // namespace

double clay_max_displacement_cells(const TriDexel& before, const TriDexel& after) {
    return std::max(max_distance_of_ends(after, before), max_distance_of_ends(before, after));
}

ClayBox clay_support_box(const float lo[3], const float hi[3], float reach, const ClayBox& outer) {
    ClayBox b;
    for (int a = 0; a < 3; ++a) {
        const float l = std::floor(lo[a] - reach) - static_cast<float>(kClayMarginCells);
        const float h = std::ceil(hi[a] + reach) + static_cast<float>(kClayMarginCells);
        b.lo[a] = l <= static_cast<float>(outer.lo[a]) ? outer.lo[a] : static_cast<int>(l);
        b.hi[a] = h >= static_cast<float>(outer.hi[a]) ? outer.hi[a] : static_cast<int>(h);
    }
    return b;
}

ClayBox clay_whole_box(const Lattice& L) {
    ClayBox b;
    for (int a = 0; a < 3; ++a) b.lo[a] = 0, b.hi[a] = L.cells[a];
    return b;
}

namespace {

/// The capsule region's chords along set a's rays (clay_region_chord's estimate), its ray-independent terms once.
AxisCapsule region_capsule(const ClayRegion& g, int a) {
    glm::vec3 e(0.0f);
    for (int k = 0; k < 3; ++k) e[k] = g.c1[k] - g.c[k];
    return AxisCapsule(a, e, g.r * 1.0001f + 1e-2f);
}

/// clay_region_chord with the region's capsule along set a (region_capsule) given.
void region_chord(const ClayField& f, const AxisCapsule& cap, int a, int u, int v, int& lo, int& hi) {
    lo = f.box.lo[a];
    hi = f.box.hi[a];
    const ClayRegion& g = f.region;
    if (!std::isfinite(g.r)) return;
    const int ua = (a + 1) % 3, va = (a + 2) % 3;
    // The line's chord through the capsule a cell longer each way, then trimmed to the nodes the predicate accepts
    // (they form one run: the capsule is convex).
    float t0, t1;
    if (g.c1[0] == g.c[0] && g.c1[1] == g.c[1] && g.c1[2] == g.c[2]) {  // a ball: its chord in closed form
        const float du = static_cast<float>(u) - g.c[ua], dv = static_cast<float>(v) - g.c[va];
        const float side2 = du * du + dv * dv, r2 = g.r * g.r;
        if (side2 > r2 * 1.0001f + 1e-4f) {
            lo = 1;
            hi = 0;
            return;
        }
        t1 = std::sqrt(std::max(r2 - side2, 0.0f));
        t0 = -t1;
    } else {
        if (!cap.chord(static_cast<float>(u) - g.c[ua], static_cast<float>(v) - g.c[va], t0, t1)) {
            lo = 1;
            hi = 0;
            return;
        }
    }
    const int blo = lo, bhi = hi;
    const float flo = std::floor(g.c[a] + t0), fhi = std::ceil(g.c[a] + t1);
    if (fhi < static_cast<float>(blo) - 1.0f || flo > static_cast<float>(bhi) + 1.0f) {
        lo = 1;
        hi = 0;
        return;
    }
    int n[3];
    n[ua] = u;
    n[va] = v;
    auto in = [&](int dd) {
        n[a] = dd;
        return g.contains(n[0], n[1], n[2]);
    };
    // Each end from the closed form's node: outward while the next node is in, inward while this one is out, within
    // the estimate widened by a cell (the closed form is within a rounding of the predicate's boundary).
    const int wlo = std::max(static_cast<int>(flo) - 1, blo), whi = std::min(static_cast<int>(fhi) + 1, bhi);
    lo = std::clamp(static_cast<int>(flo), wlo, std::max(wlo, whi));
    if (in(lo))
        while (lo - 1 >= wlo && in(lo - 1)) --lo;
    else
        while (lo <= whi && !in(lo)) ++lo;
    hi = std::clamp(static_cast<int>(fhi), std::min(wlo, whi), whi);
    if (hi >= lo && in(hi))
        while (hi + 1 <= whi && in(hi + 1)) ++hi;
    else
        while (hi >= lo && !in(hi)) --hi;
}

}  // namespace

void clay_region_chord(const ClayField& f, int a, int u, int v, int& lo, int& hi) {
    region_chord(f, region_capsule(f.region, a), a, u, v, lo, hi);
}

void clay_build_chords(ClayField& f) {
    const ClayBox& b = f.box;
    const bool whole = !std::isfinite(f.region.r);
    for (int a = 0; a < 3; ++a) {
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        f.chords[a].assign(static_cast<std::size_t>(b.n(ua)) * b.n(va), std::array<int, 2>{1, 0});
        if (a > 0 && !whole) continue;  // read off set 0's chords below
        // The region's shadow on the set's rays, widened beyond clay_region_chord's own (r * 1.0001 + 0.01) and
        // beyond float rounding: rays outside it have no chord.
        const ClayRegion& g = f.region;
        const double eu = g.c1[ua] - g.c[ua], ev = g.c1[va] - g.c[va];
        const double margin = 2e-2 + 1e-5 * (g.r + std::fabs(eu) + std::fabs(ev) + std::fabs(g.c[ua]) + std::fabs(g.c[va]));
        const CapsuleShadow shadow(eu, ev, whole ? 0.0 : g.r * 1.0001 + margin, g.c[ua], g.c[va]);
        const AxisCapsule cap = whole ? AxisCapsule() : region_capsule(g, a);
        for (int v = b.lo[va]; v <= b.hi[va]; ++v) {
            int u_lo = b.lo[ua], u_hi = b.hi[ua];
            if (!whole && !shadow.row(v, u_lo, u_hi)) continue;  // the row misses the region
            for (int u = u_lo; u <= u_hi; ++u) {
                int dlo, dhi;
                region_chord(f, cap, a, u, v, dlo, dhi);
                if (dlo > dhi) continue;
                f.chords[a][static_cast<std::size_t>(u - b.lo[ua]) +
                            static_cast<std::size_t>(b.n(ua)) * (v - b.lo[va])] = {dlo, dhi};
            }
        }
    }
    if (whole) return;
    // Sets 1 and 2: the region's nodes are those of set 0's chords (the same predicate), and the capsule is convex,
    // so each of their rays meets them in one run, from its first node to its last in the walk below (k outer, j
    // inner: along a set 1 ray j grows, along a set 2 ray k grows).
    const std::size_t n0 = static_cast<std::size_t>(b.n(0)), n2 = static_cast<std::size_t>(b.n(2));
    for (int k = b.lo[2]; k <= b.hi[2]; ++k)
        for (int j = b.lo[1]; j <= b.hi[1]; ++j) {
            const std::array<int, 2>& run = f.chord(0, j, k);
            for (int i = run[0]; i <= run[1]; ++i) {
                std::array<int, 2>& c1 = f.chords[1][static_cast<std::size_t>(k - b.lo[2]) + n2 * (i - b.lo[0])];
                if (c1[0] > c1[1]) c1[0] = j;
                c1[1] = j;
                std::array<int, 2>& c2 = f.chords[2][static_cast<std::size_t>(i - b.lo[0]) + n0 * (j - b.lo[1])];
                if (c2[0] > c2[1]) c2[0] = k;
                c2[1] = k;
            }
        }
}

void clay_build_phi(const TriDexel& model, ClayField& f) {
    // clay_node_phi at every node of the region, one walk along each ray of each set (over its chord through the
    // region) instead of a scan per node: the same predicates and the same float operations in the same order
    // (sets 0, 1, 2), so the same values.
    const ClayBox& b = f.box;
    const std::size_t n = b.count();
    f.phi.resize(n);
    std::memset(f.phi.data(), 0xff, n * sizeof(float));  // all ones: a NaN at every node until built
    f.s0.assign(n, 0.0f);
    f.s1.assign(n, 0.0f);
    clay_build_chords(f);
    // Set 0 visits every node of the region first and so sets these; the other nodes are never read.
    thread_local std::vector<std::uint8_t> votes, touching;
    votes.resize(n);
    touching.resize(n);
    std::vector<float>& inv = f.s1;  // scratch until the end
    const float K = f.search;
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = model.sets[a];
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        const std::size_t stride = b.stride(a);
        int nd[3];
        for (int v = b.lo[va]; v <= b.hi[va]; ++v)
            for (int u = b.lo[ua]; u <= b.hi[ua]; ++u) {
                const std::array<int, 2>& run = f.chord(a, u, v);
                const int dlo = run[0], dhi = run[1];
                if (dlo > dhi) continue;
                const std::vector<Interval>& ray = set.ray(u, v);
                const std::size_t ne = 2 * ray.size();
                auto end = [&](std::size_t k) { return (k & 1u) ? ray[k >> 1].exit : ray[k >> 1].enter; };
                nd[ua] = u;
                nd[va] = v;
                nd[a] = dlo;
                std::size_t x = b.index(nd[0], nd[1], nd[2]);
                std::size_t q = 0;  // first end >= depth
                int d = dlo;
                while (d <= dhi) {
                    const float depth = static_cast<float>(d);
                    while (q < ne && end(q) < depth) ++q;
                    float dist = K;
                    if (q > 0) dist = std::min(dist, std::fabs(end(q - 1) - depth));
                    if (q < ne) dist = std::min(dist, std::fabs(end(q) - depth));
                    const std::uint8_t in = (q & 1u) ? 1 : 0;
                    votes[x] = a == 0 ? in : static_cast<std::uint8_t>(votes[x] + in);
                    if (a == 0) touching[x] = 0;
                    if (dist == 0.0f)
                        touching[x] = 1;
                    else if (dist < K)
                        inv[x] += 1.0f / (dist * dist);
                    ++d, x += stride;
                    if (dist < K) continue;
                    // Past the last end's reach: every node before the one within K of the next end (or the chord's
                    // end) has dist == K and the same parity, so it only votes.
                    int stop = dhi + 1;
                    if (q < ne) {
                        const float e = end(q);
                        const float first = std::ceil(e - K);  // no node below this lies within K of e
                        if (first <= static_cast<float>(dhi)) stop = std::max(d, static_cast<int>(first) - 1);
                    }
                    if (a == 0) {
                        for (; d < stop; ++d, x += stride) votes[x] = in, touching[x] = 0;
                    } else if (in) {
                        for (; d < stop; ++d, x += stride) ++votes[x];
                    } else {
                        x += static_cast<std::size_t>(stop - d) * stride;
                        d = stop;
                    }
                }
            }
    }
    // The region's nodes, along the chords of set 0's rays.
    for (int k = b.lo[2]; k <= b.hi[2]; ++k)
        for (int j = b.lo[1]; j <= b.hi[1]; ++j) {
            const std::array<int, 2>& run = f.chord(0, j, k);
            for (int i = run[0]; i <= run[1]; ++i) {
                const std::size_t x = b.index(i, j, k);
                float mag = K;
                if (touching[x])
                    mag = 0.0f;
                else if (inv[x] > 0.0f)
                    mag = std::min(mag, 1.0f / std::sqrt(inv[x]));
                mag = std::max(mag, 1e-6f);
                f.phi[x] = votes[x] >= 2 ? -mag : mag;
                inv[x] = 0.0f;
            }
        }
}

float clay_phi_at(const ClayField& f, float px, float py, float pz) {
    const float p[3] = {px, py, pz};
    int i0[3];
    float w[3];
    for (int a = 0; a < 3; ++a) {
        const float lo = static_cast<float>(f.box.lo[a]), hi = static_cast<float>(f.box.hi[a]);
        const float c = std::clamp(p[a], lo, hi);
        float fl = std::floor(c);
        if (fl >= hi) fl = hi - 1.0f;
        if (fl < lo) fl = lo;  // a box one node thick
        i0[a] = static_cast<int>(fl);
        w[a] = c - fl;
    }
    auto at = [&](int dx, int dy, int dz) {
        const int x = std::min(i0[0] + dx, f.box.hi[0]), y = std::min(i0[1] + dy, f.box.hi[1]),
                  z = std::min(i0[2] + dz, f.box.hi[2]);
        return f.phi[f.box.index(x, y, z)];
    };
    const float c00 = at(0, 0, 0) + w[0] * (at(1, 0, 0) - at(0, 0, 0));
    const float c10 = at(0, 1, 0) + w[0] * (at(1, 1, 0) - at(0, 1, 0));
    const float c01 = at(0, 0, 1) + w[0] * (at(1, 0, 1) - at(0, 0, 1));
    const float c11 = at(0, 1, 1) + w[0] * (at(1, 1, 1) - at(0, 1, 1));
    const float c0 = c00 + w[1] * (c10 - c00), c1 = c01 + w[1] * (c11 - c01);
    return c0 + w[2] * (c1 - c0);
}

std::size_t clay_set_disagreement(const TriDexel& model, const ClayBox& box) {
    std::size_t n = 0;
    for (int k = box.lo[2]; k <= box.hi[2]; ++k)
        for (int j = box.lo[1]; j <= box.hi[1]; ++j)
            for (int i = box.lo[0]; i <= box.hi[0]; ++i) {
                const bool x = clay_ray_inside(model.sets[0].ray(j, k), static_cast<float>(i));
                const bool y = clay_ray_inside(model.sets[1].ray(k, i), static_cast<float>(j));
                const bool z = clay_ray_inside(model.sets[2].ray(i, j), static_cast<float>(k));
                if (x != y || y != z) ++n;
            }
    return n;
}

}  // namespace tridex::compute
