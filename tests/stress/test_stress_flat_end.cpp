// tests/stress/test_stress_flat_end.cpp - flat-end mill sweeps against their exact swept solids, ray by
// ray, in double precision. Cases with an analytic swept volume:
//   (a) plunge along an axis-aligned tool axis: the swept solid is a longer cylinder;
//   (b) motion perpendicular to an axis-aligned tool axis: a stadium prism (cylinder at the start, cylinder
//       at the end and the box between, extruded along the axis);
//   (c) an axis oblique to the lattice, motion along the axis: a longer oblique cylinder.
// Each sweep is subtracted from a box with apply_sweep (and through GpuSculptor, compared bit for bit).
// Per ray, the exact chord of the swept solid (an extruded 2D capsule cut by the axial slab) is computed
// in double; the model must (1) keep no solid inside the solid eroded by 1e-4 cells,
// (2) keep all the box outside the solid dilated by 1e-4 cells, and (3) every interval end must lie within
// 1e-4 cells of the exact surface of box minus swept solid (3D distance). The swept volume is cut in
// closed form (swept_cylinder_chord, one pose: no scallops), so the bound is float rounding for every case.
// Measured numbers (3D end distance, along-ray symmetric difference) are printed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/tools/sweep.hpp"
#include "gpu/context.hpp"
#include "stress_common.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

constexpr int kN = 48;
constexpr double kBoxLo = 2.5, kBoxHi = 45.5;  // grid units
constexpr double kTol = 1e-4;                  // cells: float rounding allowance in 3D

/// A flat-end sweep in grid units: flat end centred at `a`, moved to `b`; unit axis `n`; radius r, length len.
struct FlatCase {
    const char* name;
    Vec3 a, b, n;
    double r, len;
};

/// The exact swept solid: points whose axial coordinate (p - a).n lies in [0, len] and whose part across
/// the axis lies within r of the segment a -> b projected across the axis (an extruded stadium).
struct Prism {
    Vec3 a, m, n;  ///< base point, motion across the axis, unit axis
    double len, r;
};

Prism exact_solid(const FlatCase& c) {
    const Vec3 d = c.b - c.a;
    const double along = glm::dot(d, c.n);
    Prism p{c.a, d - c.n * along, c.n, c.len, c.r};
    if (std::abs(along) > 1e-12) {  // motion along the axis: one longer cylinder
        p.m = Vec3(0.0);
        p.len = c.len + std::abs(along);
        if (along < 0.0) p.a = c.b;
    }
    return p;
}

/// Chord of the line o + t p (p non-zero) with the infinite solid cylinder of radius R around the
/// segment 0 -> m (or the ball-capped capsule: union of balls at 0, m and the side), t in [lo, hi].
void capsule_2d(const Vec3& o, const Vec3& p, const Vec3& m, double R, double& lo, double& hi) {
    lo = INFINITY, hi = -INFINITY;
    auto quad = [&](double A, double B, double C, double& q0, double& q1) {  // A t^2 + 2 B t + C <= 0
        if (A < 1e-300) {
            if (C < 0.0) q0 = -INFINITY, q1 = INFINITY; else q0 = INFINITY, q1 = -INFINITY;
            return;
        }
        const double disc = B * B - A * C;
        if (disc <= 0.0) { q0 = INFINITY, q1 = -INFINITY; return; }
        q0 = (-B - std::sqrt(disc)) / A;
        q1 = (-B + std::sqrt(disc)) / A;
    };
    for (const Vec3& c : {Vec3(0.0), m}) {
        double q0, q1;
        const Vec3 w = o - c;
        quad(glm::dot(p, p), glm::dot(p, w), glm::dot(w, w) - R * R, q0, q1);
        if (q1 > q0) lo = std::min(lo, q0), hi = std::max(hi, q1);
    }
    const double mm = glm::dot(m, m);
    if (mm <= 0.0) return;
    const Vec3 pp = p - m * (glm::dot(p, m) / mm), op = o - m * (glm::dot(o, m) / mm);
    double q0, q1;
    quad(glm::dot(pp, pp), glm::dot(pp, op), glm::dot(op, op) - R * R, q0, q1);
    const double s0 = glm::dot(o, m) / mm, sd = glm::dot(p, m) / mm;  // projection on the segment, in [0, 1]
    if (sd != 0.0) {
        double ta = -s0 / sd, tb = (1.0 - s0) / sd;
        if (ta > tb) std::swap(ta, tb);
        q0 = std::max(q0, ta), q1 = std::min(q1, tb);
    } else if (s0 < 0.0 || s0 > 1.0) {
        return;
    }
    if (q1 > q0) lo = std::min(lo, q0), hi = std::max(hi, q1);
}

/// Chord of the ray of set `axis` through o with the prism grown by `grow` cells (negative: eroded) in
/// radius and at both caps; false when empty.
bool prism_chord(const Prism& P, const Vec3& o, int axis, double grow, double& t0, double& t1) {
    Vec3 e(0.0);
    e[axis] = 1.0;
    const Vec3 w = o - P.a;
    const double en = glm::dot(e, P.n), wn = glm::dot(w, P.n);
    double lo, hi;
    capsule_2d(w - P.n * wn, e - P.n * en, P.m, P.r + grow, lo, hi);
    if (en != 0.0) {
        double ta = (-grow - wn) / en, tb = (P.len + grow - wn) / en;
        if (ta > tb) std::swap(ta, tb);
        lo = std::max(lo, ta), hi = std::min(hi, tb);
    } else if (wn < -grow || wn > P.len + grow) {
        return false;
    }
    if (!(hi > lo)) return false;
    t0 = lo, t1 = hi;
    return true;
}

/// Signed distance (cells) to the exact box-minus-prism solid (negative inside).
double final_sdf(const Prism& P, const Vec3& p) {
    const Vec3 q = glm::abs(p - Vec3(0.5 * (kBoxLo + kBoxHi))) - Vec3(0.5 * (kBoxHi - kBoxLo));
    const double box = glm::length(glm::max(q, Vec3(0.0))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
    const Vec3 w = p - P.a;
    const double s = glm::dot(w, P.n);
    const Vec3 across = w - P.n * s;
    const double mm = glm::dot(P.m, P.m);
    const double f = mm > 0.0 ? std::clamp(glm::dot(across, P.m) / mm, 0.0, 1.0) : 0.0;
    const double radial = glm::length(across - P.m * f) - P.r, axial = std::abs(s - 0.5 * P.len) - 0.5 * P.len;
    const double prism = std::hypot(std::max(radial, 0.0), std::max(axial, 0.0)) + std::min(std::max(radial, axial), 0.0);
    return std::max(box, -prism);
}

struct Result {
    double max_end_dist = 0.0;   ///< max |sdf| at interval ends, cells
    double max_symdiff = 0.0;    ///< max per-ray |model - exact| along the ray, cells
    std::size_t rays_cut = 0, rays_off = 0, ends = 0, eroded_hit = 0, dilated_lost = 0, invariant_bad = 0;
};

Result compare(const TriDexel& before, const TriDexel& m, const Prism& P, double bound) {
    Result res;
    for (int a = 0; a < 3; ++a)
        for (int v = 0; v < m.sets[a].nv; ++v)
            for (int u = 0; u < m.sets[a].nu; ++u) {
                Vec3 o(0.0);
                o[(a + 1) % 3] = u;
                o[(a + 2) % 3] = v;
                const auto& ray = m.sets[a].ray(u, v);
                if (!test::ray_violation(ray).empty()) ++res.invariant_bad;
                double e0, e1;
                if (prism_chord(P, o, a, -(bound + kTol), e0, e1))  // (1) nothing kept inside the eroded solid
                    for (const Interval& iv : ray) res.eroded_hit += std::min<double>(iv.exit, e1) > std::max<double>(iv.enter, e0);
                double d0 = 0, d1 = 0;
                const bool dil = prism_chord(P, o, a, kTol, d0, d1);
                double x0 = 0, x1 = 0;
                const bool hit = prism_chord(P, o, a, 0.0, x0, x1);
                res.rays_cut += hit;
                double sym = 0.0;
                for (const Interval& b : before.sets[a].ray(u, v)) {
                    // (2) the box outside the dilated solid is kept
                    std::vector<std::pair<double, double>> keep;
                    if (!dil || d1 <= b.enter || d0 >= b.exit) keep.emplace_back(b.enter, b.exit);
                    else {
                        if (d0 > b.enter) keep.emplace_back(b.enter, d0);
                        if (d1 < b.exit) keep.emplace_back(d1, b.exit);
                    }
                    for (const auto& [k0, k1] : keep) {
                        bool in = false;
                        for (const Interval& iv : ray) in |= iv.enter <= k0 && iv.exit >= k1;
                        res.dilated_lost += !in;
                    }
                    // along-ray symmetric difference of the model and box - exact chord (both within b)
                    double exact_len = b.exit - b.enter, common = 0.0, model_len = 0.0;
                    if (hit) exact_len -= std::max(0.0, std::min<double>(x1, b.exit) - std::max<double>(x0, b.enter));
                    for (const Interval& iv : ray) {
                        const double lo = std::max<double>(iv.enter, b.enter), hi = std::min<double>(iv.exit, b.exit);
                        if (hi <= lo) continue;
                        model_len += hi - lo;
                        common += hi - lo;
                        if (hit) common -= std::max(0.0, std::min(hi, x1) - std::max(lo, x0));
                    }
                    sym += exact_len + model_len - 2.0 * common;
                }
                res.max_symdiff = std::max(res.max_symdiff, sym);
                res.rays_off += sym > 1e-3;
                for (const Interval& iv : ray)  // (3) ends on the exact surface
                    for (const double t : {double(iv.enter), double(iv.exit)}) {
                        Vec3 p = o;
                        p[a] = t;
                        res.max_end_dist = std::max(res.max_end_dist, std::abs(final_sdf(P, p)));
                        ++res.ends;
                    }
            }
    return res;
}

Sweep to_sweep(const Lattice& L, const FlatCase& c) {
    Sweep s;
    s.op = ToolOp::kSubtract;
    s.tool = SweepTool{ToolKind::kFlatEnd, c.r * L.cell_m, c.len * L.cell_m};
    s.axis = c.n;
    s.path_m = Segment{L.to_world(c.a), L.to_world(c.b)};
    return s;
}

TEST(StressFlatEnd, SweptSolidsMatchTheExactChords) {
    const Vec3 z(0, 0, 1), x(1, 0, 0), y(0, 1, 0);
    const Vec3 n1 = glm::normalize(Vec3(0.3, -0.5, 0.81)), n2 = glm::normalize(Vec3(-0.62, 0.41, 0.67));
    const Vec3 a3(11.7, 13.4, 28.3), a6(20.4, 25.3, 21.7), a7(27.1, 18.9, 24.4);
    const std::vector<FlatCase> cases = {
        {"(a) plunge down, axis z", Vec3(23.3, 24.6, 30.2), Vec3(23.3, 24.6, 15.8), z, 6.3, 10.7},
        {"(a) retract along +x, axis x", Vec3(8.1, 20.2, 19.7), Vec3(20.7, 20.2, 19.7), x, 4.5, 7.0},
        {"(b) axis z, motion along x", Vec3(12.2, 15.1, 30.6), Vec3(29.5, 15.1, 30.6), z, 4.6, 10.7},
        {"(b) axis z, motion at 0.6 rad in xy", a3, a3 + 17.9 * Vec3(std::cos(0.6), std::sin(0.6), 0.0), z, 3.2, 9.0},
        {"(b) axis y, motion in xz", Vec3(14.3, 30.1, 12.8), Vec3(29.5, 30.1, 23.9), y, 5.5, 8.0},
        {"(c) oblique axis, motion along +axis", a6, a6 + 9.7 * n1, n1, 5.2, 8.3},
        {"(c) oblique axis, motion along -axis", a7, a7 - 11.2 * n2, n2, 3.7, 6.1},
    };
    gpu::Context ctx = gpu::Context::create({});
    const TriDexel box = test::stress_box(kN, kBoxLo, kBoxHi);
    for (const FlatCase& c : cases) {
        SCOPED_TRACE(c.name);
        const Sweep s = to_sweep(box.lattice, c);
        const GridSweep g = to_grid_sweep(box.lattice, s);
        EXPECT_EQ(g.stamps, 1u);  // closed form, no stamping
        TriDexel cpu = box;
        apply_sweep(cpu, s);
        const Result r = compare(box, cpu, exact_solid(c), 0.0);
        std::printf("%-40s r %.1f: max end distance to the exact surface %.3g cells; max per-ray |model - exact| "
                    "%.3g cells, rays off by > 1e-3 cell %zu of %zu cut; ends %zu\n",
                    c.name, c.r, r.max_end_dist, r.max_symdiff, r.rays_off, r.rays_cut, r.ends);
        EXPECT_EQ(r.invariant_bad, 0u);
        EXPECT_GT(r.rays_cut, 300u);
        EXPECT_EQ(r.eroded_hit, 0u);
        EXPECT_EQ(r.dilated_lost, 0u);
        EXPECT_LE(r.max_end_dist, kTol);
        EXPECT_LE(r.max_symdiff, 1e-4);  // float chords

        TriDexel mirror = box;  // the GPU path gives the same bits
        {
            GpuSculptor sculptor(ctx, mirror);
            sculptor.apply(std::span<const Sweep>(&s, 1));
        }
        std::size_t differ = 0;
        for (int a = 0; a < 3; ++a)
            for (std::size_t i = 0; i < cpu.sets[a].rays.size(); ++i) differ += !test::same_bits(cpu.sets[a].rays[i], mirror.sets[a].rays[i]);
        EXPECT_EQ(differ, 0u) << "rays where GpuSculptor differs from apply_sweep";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
