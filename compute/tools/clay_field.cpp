// compute/tools/clay_field.cpp - the clay tools' node field: built from the three ray sets, re-sampled into them.
#include "compute/tools/clay_field.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

namespace tridex::compute {
namespace {

struct Crossing {
    float t;
    std::uint8_t material;
};

/// Distance (cells) from `depth` to the ray's nearest interval end within `search` cells, and whether the
/// depth is inside (enter < depth <= exit).
void ray_probe(const std::vector<Interval>& ray, float depth, float search, bool& inside, float& dist) {
    inside = false;
    dist = search;
    for (const Interval& iv : ray) {
        if (iv.enter < depth && depth <= iv.exit) inside = true;
        dist = std::min(dist, std::fabs(iv.enter - depth));
        dist = std::min(dist, std::fabs(iv.exit - depth));
    }
}

double ray_length(const std::vector<Interval>& ray) {
    double s = 0.0;
    for (const Interval& iv : ray) s += static_cast<double>(iv.exit) - static_cast<double>(iv.enter);
    return s;
}

/// Material of the ray's old end nearest to depth t (0 when the ray had none).
std::uint8_t nearest_material(const std::vector<Interval>& ray, float t) {
    std::uint8_t m = 0;
    float best = 3.4e38f;
    for (const Interval& iv : ray) {
        const float d0 = std::fabs(iv.enter - t), d1 = std::fabs(iv.exit - t);
        if (d0 < best) best = d0, m = iv.enter_material;
        if (d1 < best) best = d1, m = iv.exit_material;
    }
    return m;
}

/// One ray (set `axis`, node (u, v)) re-sampled from the field over its edges that touch a moved node, which all
/// lie between depth nodes [lo, hi] (the moved nodes' span widened by one node below, inside the box); the rest of
/// the ray is kept. `out` gets the new intervals.
void resample_ray(const std::vector<Interval>& ray, const ClayField& f, int axis, int u, int v, int lo, int hi,
                  float beta, std::vector<Interval>& out) {
    const ClayBox& b = f.box;
    int n[3];
    n[(axis + 1) % 3] = u;
    n[(axis + 2) % 3] = v;
    n[axis] = lo;
    const std::size_t base = b.index(n[0], n[1], n[2]);
    const std::size_t stride = axis == 0   ? 1
                               : axis == 1 ? static_cast<std::size_t>(b.n(0))
                                           : static_cast<std::size_t>(b.n(0)) * b.n(1);
    thread_local std::vector<Crossing> xs;
    xs.clear();
    std::size_t q = 0;  // next old crossing (2 per interval)
    auto old_t = [&](std::size_t k) { return (k & 1u) ? ray[k >> 1].exit : ray[k >> 1].enter; };
    auto old_m = [&](std::size_t k) { return (k & 1u) ? ray[k >> 1].exit_material : ray[k >> 1].enter_material; };
    const std::size_t nx = 2 * ray.size();
    const float flo = static_cast<float>(lo);
    while (q < nx && old_t(q) < flo) xs.push_back({old_t(q), old_m(q)}), ++q;
    bool status = (q & 1u) != 0;  // the ray's status just below node lo
    for (int d = lo; d < hi; ++d) {
        const std::size_t i0 = base + static_cast<std::size_t>(d - lo) * stride, i1 = i0 + stride;
        const float s0 = f.s0[i0] + beta * f.s1[i0];
        const float s1 = f.s0[i1] + beta * f.s1[i1];
        const float fd1 = static_cast<float>(d + 1);
        if (s0 == 0.0f && s1 == 0.0f) {  // the edge keeps its old crossings
            while (q < nx && old_t(q) < fd1) xs.push_back({old_t(q), old_m(q)}), ++q;
            status = (q & 1u) != 0;
            continue;
        }
        const float p0 = f.phi[i0] + s0, p1 = f.phi[i1] + s1;
        // Status at each end: the field's where the node moved, the ray's own where it did not.
        const bool st0 = s0 != 0.0f ? p0 < 0.0f : status;
        std::size_t q1 = q;
        while (q1 < nx && old_t(q1) < fd1) ++q1;
        const bool st1 = s1 != 0.0f ? p1 < 0.0f : (q1 & 1u) != 0;
        q = q1;
        if (st0 != st1) {
            float t;
            if ((p0 < 0.0f) != (p1 < 0.0f)) {
                const float w = p0 / (p0 - p1);
                t = static_cast<float>(d) + std::clamp(w, 0.0f, 1.0f);
            } else {
                t = static_cast<float>(d) + 0.5f;  // the old ray disagreed with the field at its unmoved end
            }
            xs.push_back({t, nearest_material(ray, t)});
        }
        status = st1;
    }
    while (q < nx) xs.push_back({old_t(q), old_m(q)}), ++q;
    // Pair the crossings into sorted, disjoint, non-touching intervals; zero-length ones vanish.
    out.clear();
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
        const Crossing a = xs[k], e = xs[k + 1];
        if (!(a.t < e.t)) continue;
        if (!out.empty() && !(out.back().exit < a.t)) {  // touches the previous one: merge
            out.back().exit = std::max(out.back().exit, e.t);
            out.back().exit_material = e.material;
            continue;
        }
        out.push_back({a.t, e.t, a.material, e.material});
    }
}

bool same_ray(const std::vector<Interval>& a, const std::vector<Interval>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].enter != b[i].enter || a[i].exit != b[i].exit || a[i].enter_material != b[i].enter_material ||
            a[i].exit_material != b[i].exit_material)
            return false;
    return true;
}

/// A ray of the box that holds a moved node: its set, its index in the set, its (u, v), the depth nodes [lo, hi]
/// its re-sampling walks (the moved nodes' span and one node below it), whether a node on it has s1 != 0 (else its
/// re-sampling is the same for every beta), and its old length (cells).
struct MovedRay {
    std::uint8_t set;
    std::uint32_t index;
    int u, v, lo, hi;
    bool varies;
    double old_length;
};

/// A node with s0 or s1 != 0: its index in the box and its lattice node indices.
struct MovedNode {
    std::uint32_t x;
    int n[3];
};

/// The moved nodes of the field's region, in increasing box index (the order every sum over them takes).
void moved_nodes(const ClayField& f, std::vector<MovedNode>& out) {
    const ClayBox& b = f.box;
    out.clear();
    const bool built = f.chords[0].size() == static_cast<std::size_t>(b.n(1)) * b.n(2);  // else scan the whole box
    for (int k = b.lo[2]; k <= b.hi[2]; ++k)
        for (int j = b.lo[1]; j <= b.hi[1]; ++j) {
            int ilo = b.lo[0], ihi = b.hi[0];
            if (built) ilo = f.chord(0, j, k)[0], ihi = f.chord(0, j, k)[1];
            for (int i = ilo; i <= ihi; ++i) {
                const std::size_t x = b.index(i, j, k);
                if (f.s0[x] != 0.0f || f.s1[x] != 0.0f) out.push_back({static_cast<std::uint32_t>(x), {i, j, k}});
            }
        }
}

/// The moved rays of the three sets, in the order set, v, u (the order their images are written).
void moved_rays(const TriDexel& model, const ClayField& f, const std::vector<MovedNode>& nodes,
                std::vector<MovedRay>& out) {
    const ClayBox& b = f.box;
    struct Span {
        int lo, hi;
        bool varies;
    };
    thread_local std::array<std::vector<Span>, 3> span;
    for (int a = 0; a < 3; ++a)
        span[a].assign(static_cast<std::size_t>(b.n((a + 1) % 3)) * b.n((a + 2) % 3), Span{1, 0, false});
    for (const MovedNode& m : nodes)
        for (int a = 0; a < 3; ++a) {
            const int ua = (a + 1) % 3, va = (a + 2) % 3;
            Span& sp = span[a][static_cast<std::size_t>(m.n[ua] - b.lo[ua]) +
                               static_cast<std::size_t>(b.n(ua)) * (m.n[va] - b.lo[va])];
            if (sp.lo > sp.hi) sp.lo = sp.hi = m.n[a];
            sp.lo = std::min(sp.lo, m.n[a]);
            sp.hi = std::max(sp.hi, m.n[a]);
            sp.varies |= f.s1[m.x] != 0.0f;
        }
    out.clear();
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = model.sets[a];
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        for (int v = b.lo[va]; v <= b.hi[va]; ++v)
            for (int u = b.lo[ua]; u <= b.hi[ua]; ++u) {
                const Span& sp = span[a][static_cast<std::size_t>(u - b.lo[ua]) +
                                         static_cast<std::size_t>(b.n(ua)) * (v - b.lo[va])];
                if (sp.lo > sp.hi) continue;
                // Edges [d, d + 1] with a moved end: d in [lo - 1, hi], within the box.
                out.push_back({static_cast<std::uint8_t>(a), static_cast<std::uint32_t>(u + set.nu * v), u, v,
                               std::max(sp.lo - 1, b.lo[a]), std::min(sp.hi + 1, b.hi[a]), sp.varies,
                               ray_length(set.ray(u, v))});
            }
    }
}

/// One re-sampling of some of the moved rays: per moved ray (same index), whether it changed, its new intervals
/// and its length change (cells).
struct Resampled {
    std::vector<std::uint8_t> changed;
    std::vector<std::vector<Interval>> rays;
    std::vector<double> dlen;
};

/// Re-samples at `beta` the moved rays with varies == `varying` without writing, into the same slots of `out`.
void evaluate(const TriDexel& model, const ClayField& f, const std::vector<MovedRay>& moved, bool varying, float beta,
              Resampled& out) {
    if (out.rays.size() < moved.size()) out.rays.resize(moved.size());
    out.changed.resize(moved.size());
    out.dlen.resize(moved.size());
    for (std::size_t k = 0; k < moved.size(); ++k) {
        const MovedRay& m = moved[k];
        if (m.varies != varying) continue;
        const std::vector<Interval>& ray = model.sets[m.set].rays[m.index];
        std::vector<Interval>& nr = out.rays[k];
        resample_ray(ray, f, m.set, m.u, m.v, m.lo, m.hi, beta, nr);
        out.changed[k] = same_ray(ray, nr) ? 0 : 1;
        out.dlen[k] = out.changed[k] ? ray_length(nr) - m.old_length : 0.0;
    }
}

/// The volume change (cells^3, mean of the three sets) of the moved rays re-sampled as `fixed` (varies == false)
/// and `var` (varies == true), summed per set in the rays' order.
double volume_change(const std::vector<MovedRay>& moved, const Resampled& fixed, const Resampled& var) {
    double dv[3] = {0.0, 0.0, 0.0};
    for (std::size_t k = 0; k < moved.size(); ++k) {
        const Resampled& r = moved[k].varies ? var : fixed;
        if (r.changed[k]) dv[moved[k].set] += r.dlen[k];
    }
    return (dv[0] + dv[1] + dv[2]) / 3.0;
}

/// The field's volume indicator at a node: the share (0..1) of the node's cell-sized column element that lies
/// inside for signed distance p, a linear ramp over one cell. Summed over the nodes, it measures a plane's position
/// exactly at any sub-cell offset, which the three sets' nodal sampling across their rays does not.
float ramp(float p) { return std::clamp(0.5f - p, 0.0f, 1.0f); }

/// beta so that the field's volume (sum of ramp over the moved nodes) is unchanged: bisection on the monotone,
/// piecewise-linear change in [-8, 8] (s1 of one sign), 26 steps, float. The nodes that can change are gathered once
/// into contiguous arrays (phi + s0, s1) with their ramp sum at rest, and each step sums four interleaved partial
/// sums in a fixed order, so a step costs one pass over those nodes.
float solve_beta(const ClayField& f, const std::vector<MovedNode>& nodes) {
    // Nodes whose ramp can change for beta in [-8, 8]; the others add 0 to every sum.
    thread_local std::vector<float> p0, p1;
    p0.clear();
    p1.clear();
    double rest = 0.0;
    for (const MovedNode& m : nodes) {
        const std::size_t i = m.x;
        if (std::fabs(f.phi[i]) < 0.5f + std::fabs(f.s0[i]) + 8.0f * std::fabs(f.s1[i])) {
            p0.push_back(f.phi[i] + f.s0[i]);
            p1.push_back(f.s1[i]);
            rest += static_cast<double>(ramp(f.phi[i]));
        }
    }
    const std::size_t n = p0.size();
    auto change = [&](float beta) {
        double acc[4] = {0.0, 0.0, 0.0, 0.0};
        std::size_t i = 0;
        for (; i + 4 <= n; i += 4)
            for (std::size_t l = 0; l < 4; ++l) acc[l] += static_cast<double>(ramp(p0[i + l] + beta * p1[i + l]));
        for (; i < n; ++i) acc[0] += static_cast<double>(ramp(p0[i] + beta * p1[i]));
        return ((acc[0] + acc[1]) + (acc[2] + acc[3])) - rest;
    };
    float lo = -8.0f, hi = 8.0f;
    const double flo = change(lo), fhi = change(hi);
    if (!(flo * fhi < 0.0)) return std::fabs(flo) < std::fabs(fhi) ? lo : hi;  // no root in range: the nearest end
    const bool rising = fhi > flo;
    for (int k = 0; k < 26; ++k) {  // 16 / 2^26: below a float's resolution of the offsets
        const float mid = 0.5f * (lo + hi);
        const double fm = change(mid);
        if (fm == 0.0) return mid;
        if ((fm < 0.0) == rising)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5f * (lo + hi);
}

/// beta that keeps the model's own volume (the mean of the three sets' interval lengths) in the box: the field's
/// estimate b1 (solve_beta), then, while the measured change exceeds 1% of what s0 moved (field measure), up to two
/// secant steps, the first with the slope of the field's own (the ramp sum's change per unit beta, a central
/// difference over 0.1), the second with the measured one; the beta with the smallest measured change wins and its
/// re-sampled rays are kept in `best` (written without re-sampling again). One to three re-samplings of the rays
/// whose result depends on beta (`fixed` holds the others, re-sampled once by the caller). The measured
/// change moves in steps (a set's rays sample across them at whole nodes), so one operation keeps it within about
/// one such step, not exactly 0.
float solve_measured(const TriDexel& model, const ClayField& f, const std::vector<MovedNode>& nodes,
                     const std::vector<MovedRay>& moved, const Resampled& fixed, Resampled& best, double& best_dv) {
    const float b1 = solve_beta(f, nodes);
    double slope = 0.0, dent = 0.0;  // field volume change per unit beta; field volume change of s0 alone
    for (const MovedNode& m : nodes) {
        const std::size_t i = m.x;
        if (f.s0[i] != 0.0f) dent += static_cast<double>(ramp(f.phi[i] + f.s0[i])) - ramp(f.phi[i]);
        if (f.s1[i] == 0.0f) continue;
        const float base = f.phi[i] + (f.s0[i] + b1 * f.s1[i]);
        slope += (static_cast<double>(ramp(base + 0.05f * f.s1[i])) - ramp(base - 0.05f * f.s1[i])) / 0.1;
    }
    // Good enough: within 1% of what the dent (or the smoothing) moved, or of a hundredth of a cell^3.
    const double tolerance = std::max(0.01 * std::fabs(dent), 0.01);
    float best_beta = b1;
    evaluate(model, f, moved, true, b1, best);
    best_dv = volume_change(moved, fixed, best);
    thread_local Resampled trial;
    float b = b1;
    double dv = best_dv;
    for (int k = 0; k < 2 && std::fabs(dv) > tolerance && slope != 0.0; ++k) {
        const float nb = std::clamp(static_cast<float>(static_cast<double>(b) - dv / slope), -8.0f, 8.0f);
        if (nb == b) break;
        evaluate(model, f, moved, true, nb, trial);
        const double ndv = volume_change(moved, fixed, trial);
        if (std::fabs(ndv) < std::fabs(best_dv)) {
            std::swap(best, trial);
            best_beta = nb;
            best_dv = ndv;
        }
        if (ndv != dv) slope = (ndv - dv) / (static_cast<double>(nb) - static_cast<double>(b));  // measured from now on
        b = nb;
        dv = ndv;
    }
    return best_beta;
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
                if (same_ray(ray, to.sets[a].ray(u, v))) continue;
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

void clay_region_chord(const ClayField& f, int a, int u, int v, int& lo, int& hi) {
    lo = f.box.lo[a];
    hi = f.box.hi[a];
    const ClayRegion& g = f.region;
    if (!std::isfinite(g.r)) return;
    const int ua = (a + 1) % 3, va = (a + 2) % 3;
    const float du = static_cast<float>(u) - g.c[ua], dv = static_cast<float>(v) - g.c[va];
    const float side2 = du * du + dv * dv, r2 = g.r * g.r;
    if (side2 > r2 * 1.0001f + 1e-4f) {
        lo = 1;
        hi = 0;
        return;
    }
    // A chord a cell longer each way than the ball's, then trimmed to the nodes the predicate accepts (they form
    // one run: the squared distance grows monotonically away from the centre).
    const float h = std::sqrt(std::max(r2 - side2, 0.0f)) + 1.0f;
    lo = static_cast<int>(std::max(std::floor(g.c[a] - h), static_cast<float>(lo)));
    hi = static_cast<int>(std::min(std::ceil(g.c[a] + h), static_cast<float>(hi)));
    int n[3];
    n[ua] = u;
    n[va] = v;
    auto in = [&](int d) {
        n[a] = d;
        return g.contains(n[0], n[1], n[2]);
    };
    while (lo <= hi && !in(lo)) ++lo;
    while (hi >= lo && !in(hi)) --hi;
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
    // Set 0 visits every node of the region first and so sets these; the other nodes are never read.
    thread_local std::vector<std::uint8_t> votes, touching;
    votes.resize(n);
    touching.resize(n);
    std::vector<float>& inv = f.s1;  // scratch until the end
    const float K = f.search;
    const bool whole = !std::isfinite(f.region.r);
    const float r2 = f.region.r * f.region.r;
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = model.sets[a];
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        f.chords[a].assign(static_cast<std::size_t>(b.n(ua)) * b.n(va), std::array<int, 2>{1, 0});
        const std::size_t stride = a == 0   ? 1
                                   : a == 1 ? static_cast<std::size_t>(b.n(0))
                                            : static_cast<std::size_t>(b.n(0)) * b.n(1);
        int nd[3];
        for (int v = b.lo[va]; v <= b.hi[va]; ++v) {
            const float dv = static_cast<float>(v) - f.region.c[va];
            if (!whole && dv * dv > r2 * 1.0001f + 1e-4f) continue;  // the row misses the region
            for (int u = b.lo[ua]; u <= b.hi[ua]; ++u) {
                int dlo, dhi;
                clay_region_chord(f, a, u, v, dlo, dhi);
                if (dlo > dhi) continue;
                f.chords[a][static_cast<std::size_t>(u - b.lo[ua]) +
                            static_cast<std::size_t>(b.n(ua)) * (v - b.lo[va])] = {dlo, dhi};
                const std::vector<Interval>& ray = set.ray(u, v);
                const std::size_t ne = 2 * ray.size();
                auto end = [&](std::size_t k) { return (k & 1u) ? ray[k >> 1].exit : ray[k >> 1].enter; };
                nd[ua] = u;
                nd[va] = v;
                nd[a] = dlo;
                std::size_t x = b.index(nd[0], nd[1], nd[2]);
                std::size_t q = 0;  // first end >= depth
                for (int d = dlo; d <= dhi; ++d, x += stride) {
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

ClayStats clay_resample(TriDexel& model, const ClayField& f, bool volume_preserving, std::vector<RayImage>* before) {
    ClayStats st;
    if (f.box.empty()) return st;
    thread_local std::vector<MovedNode> nodes;
    moved_nodes(f, nodes);
    if (nodes.empty()) return st;
    bool any1 = false;
    for (const MovedNode& m : nodes) any1 |= f.s1[m.x] != 0.0f;
    thread_local std::vector<MovedRay> moved;
    moved_rays(model, f, nodes, moved);
    float beta = 0.0f;
    thread_local Resampled fixed, var;
    evaluate(model, f, moved, false, 0.0f, fixed);  // the same at every beta
    double dv = 0.0;
    if (volume_preserving && any1) {
        beta = solve_measured(model, f, nodes, moved, fixed, var, dv);
    } else {
        evaluate(model, f, moved, true, 0.0f, var);
        dv = volume_change(moved, fixed, var);
    }
    for (const MovedNode& m : nodes)
        st.max_displacement_cells =
            std::max(st.max_displacement_cells, static_cast<double>(std::fabs(f.s0[m.x] + beta * f.s1[m.x])));
    st.beta = beta;
    st.volume_change_cells = dv;
    for (int a = 0; a < 3; ++a)
        st.rays.rays_visited += static_cast<std::size_t>(f.box.n((a + 1) % 3)) * f.box.n((a + 2) % 3);
    for (std::size_t k = 0; k < moved.size(); ++k) {
        Resampled& r = moved[k].varies ? var : fixed;
        if (!r.changed[k]) continue;
        ++st.rays.rays_changed;
        std::vector<Interval>& ray = model.sets[moved[k].set].rays[moved[k].index];
        if (before) before->push_back({moved[k].set, moved[k].index, ray});
        ray.swap(r.rays[k]);
    }
    if (st.rays.rays_changed > 0) {
        const Lattice& L = model.lattice;
        Aabb box;
        box.add(L.to_world(Vec3(f.box.lo[0], f.box.lo[1], f.box.lo[2])));
        box.add(L.to_world(Vec3(f.box.hi[0], f.box.hi[1], f.box.hi[2])));
        model.mark_dirty(box);
    }
    return st;
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
