// tests/stress/stress_paint.hpp - material checks of the stress tests: exact (double) per-ray chords of a
// sweep (ball: capsule; flat-end: the swept cylinder), the expected material of every interval end after a paint-only batch, and "every material id is
// one that was used".
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "compute/tools/sweep.hpp"
#include "compute/model/tridexel.hpp"
#include "stress_common.hpp"

namespace tridex::test {

using Chords = std::vector<std::pair<double, double>>;

/// Exact chord (double) of the line o + t*e_axis (grid units) with the solid finite cylinder of radius r
/// whose axis runs from a to a + e (flat caps at both ends): false when the line misses it or only
/// touches it.
inline bool exact_cylinder_chord(const Vec3& o, int axis, const Vec3& a, const Vec3& e, double r, double& t0, double& t1) {
    const double len = glm::length(e);
    if (!(len > 0.0) || !(r > 0.0)) return false;
    const Vec3 n = e / len, w = o - a;
    Vec3 d(0.0);
    d[axis] = 1.0;
    double lo = -INFINITY, hi = INFINITY;
    const Vec3 dp = d - n * glm::dot(d, n), wp = w - n * glm::dot(w, n);  // parts across the axis
    const double A = glm::dot(dp, dp), B = glm::dot(dp, wp), C = glm::dot(wp, wp) - r * r;
    if (A > 1e-300) {
        const double disc = B * B - A * C;
        if (!(disc > 0.0)) return false;
        lo = (-B - std::sqrt(disc)) / A;
        hi = (-B + std::sqrt(disc)) / A;
    } else if (C >= 0.0) {
        return false;  // parallel to the axis, outside the radius
    }
    const double s0 = glm::dot(w, n), sd = glm::dot(d, n);  // axial position s(t) = s0 + t sd in [0, len]
    if (sd != 0.0) {
        double ta = (0.0 - s0) / sd, tb = (len - s0) / sd;
        if (ta > tb) std::swap(ta, tb);
        lo = std::max(lo, ta);
        hi = std::min(hi, tb);
    } else if (!(s0 > 0.0 && s0 < len)) {
        return false;
    }
    if (!(hi > lo)) return false;
    t0 = lo;
    t1 = hi;
    return true;
}

/// Chord (double) of the ray of set `axis` through o with the volume swept by the flat-end cylinder at `a`
/// (unit axis n, length len, radius r) moved by `m`: the extremes in t of the convex set of (t, l), l in
/// [0, 1], with o + t e - l m inside the resting cylinder, taken over its boundary pieces (l = 0, l = 1,
/// the two cap planes, the ellipse's own t-extremes), written with projections across the axis.
inline bool exact_swept_cylinder_chord(const Vec3& o, int axis, const Vec3& a, const Vec3& n, double len, const Vec3& m,
                                       double r, double& t0, double& t1) {
    if (!(len > 0.0) || !(r > 0.0)) return false;
    Vec3 e(0.0);
    e[axis] = 1.0;
    auto across = [&](const Vec3& x) { return x - n * glm::dot(x, n); };
    const Vec3 w = o - a;
    const Vec3 A = across(w), B = across(e), C = across(m);
    const double ms = glm::dot(w, n), ds = glm::dot(e, n), cs = glm::dot(m, n), rr = r * r;
    double lo = INFINITY, hi = -INFINITY;
    auto take = [&](double t) { lo = std::min(lo, t), hi = std::max(hi, t); };
    for (const double l : {0.0, 1.0})
        if (exact_cylinder_chord(o, axis, a + m * l, n * len, r, t0, t1)) take(t0), take(t1);
    auto roots = [](double qa, double qb, double qc, double& x0, double& x1) {  // qa x^2 + 2 qb x + qc <= 0
        const double disc = qb * qb - qa * qc;
        if (!(qa > 1e-300) || disc < 0.0) return false;
        x0 = (-qb - std::sqrt(disc)) / qa, x1 = (-qb + std::sqrt(disc)) / qa;
        return true;
    };
    for (const double c : {0.0, len}) {
        if (std::abs(ds) > 1e-15) {  // on the cap plane: t = tc + l k
            const double tc = (c - ms) / ds, k = cs / ds;
            const Vec3 p = A + B * tc, g = B * k - C;
            double l0 = 0.0, l1 = 1.0;
            if (glm::dot(g, g) > 1e-300) {
                double x0, x1;
                if (!roots(glm::dot(g, g), glm::dot(p, g), glm::dot(p, p) - rr, x0, x1)) continue;
                l0 = std::max(l0, x0), l1 = std::min(l1, x1);
            } else if (glm::dot(p, p) > rr) {
                continue;
            }
            if (l0 <= l1) take(tc + l0 * k), take(tc + l1 * k);
        } else if (std::abs(cs) > 1e-15) {  // the ray lies in the cap plane of pose l
            const double l = (ms - c) / cs;
            double x0, x1;
            if (l >= 0.0 && l <= 1.0 && roots(glm::dot(B, B), glm::dot(A - C * l, B), glm::dot(A - C * l, A - C * l) - rr, x0, x1))
                take(x0), take(x1);
        }
    }
    const double cc = glm::dot(C, C);
    if (cc > 1e-300) {  // minimise |A + t B - l C| over l: the part of A + t B across C
        const Vec3 Ap = A - C * (glm::dot(A, C) / cc), Bp = B - C * (glm::dot(B, C) / cc);
        double x0, x1;
        if (roots(glm::dot(Bp, Bp), glm::dot(Ap, Bp), glm::dot(Ap, Ap) - rr, x0, x1))
            for (const double t : {x0, x1}) {
                const double l = glm::dot(A + B * t, C) / cc, h = ms + t * ds - l * cs;
                if (l >= 0.0 && l <= 1.0 && h >= 0.0 && h <= len) take(t);
            }
    }
    if (!(lo <= hi)) return false;
    t0 = lo, t1 = hi;
    return true;
}

/// Sorts and merges overlapping or touching chords.
inline Chords merge_chords(Chords c) {
    std::sort(c.begin(), c.end());
    Chords out;
    for (const auto& x : c) {
        if (!out.empty() && x.first <= out.back().second) out.back().second = std::max(out.back().second, x.second);
        else out.push_back(x);
    }
    return out;
}

/// The exact solid of `sweep`, grown by `grow` cells (negative: shrunk; every tool part's radius and, for a
/// flat end, its length at both caps), on the ray of set `axis` at node (u, v), as merged depth intervals
/// (grid units along the axis): ball -> the capsule chord; flat-end -> the swept cylinder's chord
/// (exact_swept_cylinder_chord), computed in double from the sweep's world positions (so within float
/// rounding of what the model cuts).
inline Chords exact_sweep_chords(const compute::Lattice& L, const compute::Sweep& s, const compute::GridSweep& /*g*/, int axis,
                                 int u, int v, double grow = 0.0) {
    Vec3 o(0.0);
    o[(axis + 1) % 3] = u;
    o[(axis + 2) % 3] = v;
    const Vec3 a = L.to_grid(s.path_m.a), b = L.to_grid(s.path_m.b);
    const double r = s.tool.radius_m / L.cell_m + grow;
    Chords c;
    if (!(r > 0.0)) return c;
    double t0, t1;
    if (s.tool.kind == compute::ToolKind::kBall) {
        if (exact_capsule_chord(o, axis, a, b, r, t0, t1)) c.emplace_back(t0, t1);
        return c;
    }
    const Vec3 n = glm::normalize(s.axis);
    const double len = s.tool.length_m / L.cell_m + 2.0 * grow;
    if (!(len > 0.0)) return c;
    if (exact_swept_cylinder_chord(o, axis, a - n * grow, n, len, b - a, r, t0, t1)) c.emplace_back(t0, t1);
    return c;
}

/// One sweep's exact solid on a ray, shrunk and grown by the margin.
struct SweepChords {
    std::size_t sweep = 0;  ///< index in the batch
    Chords inner, outer;    ///< chords of the solid shrunk / grown by the margin
};

/// Where depth t lies against a sweep: 1 inside the shrunk solid (inside by more than the margin, in 3D),
/// -1 outside the grown one (farther than the margin), 0 in between (undecided).
inline int chord_side(const SweepChords& c, double t) {
    for (const auto& [t0, t1] : c.inner)
        if (t > t0 && t < t1) return 1;
    for (const auto& [t0, t1] : c.outer)
        if (t >= t0 && t <= t1) return 0;
    return -1;
}

/// Result of check_paint_batch.
struct PaintReport {
    std::size_t ends = 0;       ///< interval ends checked
    std::size_t painted = 0;    ///< ends inside some sweep by more than the margin (expected: the last such sweep's material)
    std::size_t kept = 0;       ///< ends outside every sweep by more than the margin (expected: the old material)
    std::size_t undecided = 0;  ///< ends within the margin of the surface of a sweep that could decide them (not checked)
    std::size_t bad = 0;        ///< ends with another material, or rays whose depths or counts changed
    std::string first;          ///< what the first few bad ends were
};

/// Checks a paint-only batch (every sweep op kPaint) applied to the rays `rays` (set, index; every ray a
/// sweep's footprint holds must be listed) whose state before the batch is `before` (same order):
/// depths and counts bit-identical; an end that lies inside the exact solid of some sweep by more than
/// `margin` (grid units, 3D: inside the solid shrunk by the margin) has the material of the LAST such sweep
/// in batch order, unless a later sweep is within the margin of it (then undecided); an end farther than
/// the margin from every sweep's solid keeps its old material. Cost: O(sum over sweeps of footprint rays + ends x sweeps on the ray).
inline PaintReport check_paint_batch(const compute::TriDexel& m, std::span<const compute::Sweep> batch,
                                     const std::vector<std::pair<int, std::size_t>>& rays,
                                     const std::vector<std::vector<compute::Interval>>& before, double margin) {
    PaintReport rep;
    std::array<std::vector<std::int32_t>, 3> slot;
    for (int a = 0; a < 3; ++a) slot[a].assign(m.sets[a].rays.size(), -1);
    for (std::size_t k = 0; k < rays.size(); ++k) slot[rays[k].first][rays[k].second] = static_cast<std::int32_t>(k);
    std::vector<std::vector<SweepChords>> hits(rays.size());  // per ray, in batch order
    for (std::size_t k = 0; k < batch.size(); ++k) {
        const compute::GridSweep g = compute::to_grid_sweep(m.lattice, batch[k]);
        for (int a = 0; a < 3; ++a) {
            int u0, u1, v0, v1;
            if (!compute::sweep_footprint(g, m.sets[a], u0, u1, v0, v1)) continue;
            for (int v = v0; v <= v1; ++v)
                for (int u = u0; u <= u1; ++u) {
                    const std::size_t i = static_cast<std::size_t>(u) + static_cast<std::size_t>(m.sets[a].nu) * v;
                    SweepChords c{k, exact_sweep_chords(m.lattice, batch[k], g, a, u, v, -margin),
                                  exact_sweep_chords(m.lattice, batch[k], g, a, u, v, margin)};
                    if (c.outer.empty()) continue;
                    if (slot[a][i] < 0) {
                        if (++rep.bad <= 3) rep.first += " [set " + std::to_string(a) + " ray " + std::to_string(i) + " not listed]";
                        continue;
                    }
                    hits[slot[a][i]].push_back(std::move(c));
                }
        }
    }
    auto note = [&rep](int a, std::size_t i, std::size_t j, const char* end, int got, int want) {
        if (++rep.bad > 4) return;
        std::ostringstream s;
        s << " [set " << a << " ray " << i << " interval " << j << " " << end << ": material " << got << ", expected " << want << "]";
        rep.first += s.str();
    };
    for (std::size_t k = 0; k < rays.size(); ++k) {
        const auto& now = m.sets[rays[k].first].rays[rays[k].second];
        const auto& old = before[k];
        bool same_depths = now.size() == old.size();
        for (std::size_t j = 0; same_depths && j < now.size(); ++j)
            same_depths = std::memcmp(&now[j].enter, &old[j].enter, 4) == 0 && std::memcmp(&now[j].exit, &old[j].exit, 4) == 0;
        if (!same_depths) {
            if (++rep.bad <= 4) rep.first += " [set " + std::to_string(rays[k].first) + " ray " + std::to_string(rays[k].second) + ": depths changed]";
            continue;
        }
        for (std::size_t j = 0; j < now.size(); ++j)
            for (int e = 0; e < 2; ++e) {
                const double t = e == 0 ? now[j].enter : now[j].exit;
                const int got = e == 0 ? now[j].enter_material : now[j].exit_material;
                const int was = e == 0 ? old[j].enter_material : old[j].exit_material;
                int want = was;  // walk the sweeps backwards: the last one that decides the end
                bool decided = false;
                for (auto h = hits[k].rbegin(); h != hits[k].rend() && !decided; ++h) {
                    const int side = chord_side(*h, t);
                    if (side == 0) break;
                    if (side == 1) want = batch[h->sweep].material, decided = true;
                }
                ++rep.ends;
                bool undecided = !decided;
                if (!decided) {  // kept only if every sweep is clearly outside
                    undecided = false;
                    for (const auto& h : hits[k]) undecided |= chord_side(h, t) == 0;
                }
                if (undecided) {
                    ++rep.undecided;
                    continue;
                }
                ++(decided ? rep.painted : rep.kept);
                if (got != want) note(rays[k].first, rays[k].second, j, e == 0 ? "enter" : "exit", got, want);
            }
    }
    return rep;
}

/// The rays (set, index) whose node lies in the footprint of some sweep of `batch`, each listed once.
inline std::vector<std::pair<int, std::size_t>> footprint_rays(const compute::TriDexel& m, std::span<const compute::Sweep> batch) {
    std::vector<std::pair<int, std::size_t>> list;
    std::array<std::vector<char>, 3> seen;
    for (int a = 0; a < 3; ++a) seen[a].assign(m.sets[a].rays.size(), 0);
    for (const compute::Sweep& s : batch) {
        const compute::GridSweep g = compute::to_grid_sweep(m.lattice, s);
        for (int a = 0; a < 3; ++a) {
            int u0, u1, v0, v1;
            if (!compute::sweep_footprint(g, m.sets[a], u0, u1, v0, v1)) continue;
            for (int v = v0; v <= v1; ++v)
                for (int u = u0; u <= u1; ++u) {
                    const std::size_t i = static_cast<std::size_t>(u) + static_cast<std::size_t>(m.sets[a].nu) * v;
                    if (!seen[a][i]) seen[a][i] = 1, list.emplace_back(a, i);
                }
        }
    }
    return list;
}

/// Counts interval ends of `ray` whose material id is not flagged in `used` (256 flags).
inline std::size_t unused_materials(const std::vector<compute::Interval>& ray, const std::array<bool, 256>& used) {
    std::size_t n = 0;
    for (const compute::Interval& iv : ray) n += !used[iv.enter_material] + !used[iv.exit_material];
    return n;
}

}  // namespace tridex::test
