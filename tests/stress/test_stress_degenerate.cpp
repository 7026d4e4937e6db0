// tests/stress/test_stress_degenerate.cpp - degenerate swept Booleans against the exact answer:
// every ball sweep is also applied in double precision, ray by ray, with the
// exact ray-capsule chord (stress_common.hpp), and the model's rays are compared with that exact solid
// (symmetric-difference length per ray, cells). Cases: rays tangent to the ball (whole-cell radius,
// centre on a node), centre on a lattice line and on a lattice plane, zero-length segments, segments far
// longer than the workpiece, tools of 0.1 cell (only rays near the path change) and tools larger than
// the workpiece (everything goes), removed volumes against 4/3 pi r^3 and pi r^2 L + 4/3 pi r^3, and the
// same stroke program with the workpiece at the origin and 1 km (and 100 km) away, rays compared bit for bit.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "compute/tools/sweep.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"
#include "stress_common.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

using Solid1d = std::vector<std::pair<double, double>>;

Solid1d to_1d(const std::vector<Interval>& ray) {
    Solid1d s;
    for (const Interval& iv : ray) s.emplace_back(iv.enter, iv.exit);
    return s;
}

Solid1d subtract_1d(const Solid1d& s, double t0, double t1) {
    Solid1d out;
    for (const auto& [a, b] : s) {
        if (b <= t0 || a >= t1) { out.emplace_back(a, b); continue; }
        if (a < t0) out.emplace_back(a, t0);
        if (b > t1) out.emplace_back(t1, b);
    }
    return out;
}

/// Length of the symmetric difference of two sorted, disjoint interval lists.
double symdiff_1d(const Solid1d& x, const Solid1d& y) {
    std::vector<std::pair<double, int>> ev;
    for (const auto& [a, b] : x) ev.push_back({a, 1}), ev.push_back({b, -1});
    for (const auto& [a, b] : y) ev.push_back({a, 2}), ev.push_back({b, -2});
    std::sort(ev.begin(), ev.end());
    double len = 0.0, last = 0.0;
    int in_x = 0, in_y = 0;
    for (const auto& [t, e] : ev) {
        if ((in_x > 0) != (in_y > 0)) len += t - last;
        last = t;
        if (e == 1 || e == -1) in_x += e; else in_y += e / 2;
    }
    return len;
}

/// A ball sweep in grid units (start a, end b, radius r), for the exact solid.
struct BallCut {
    Vec3 a, b;
    double r;
};

Sweep ball_sweep(const Lattice& L, const BallCut& c, ToolOp op = ToolOp::kSubtract) {
    Sweep s;
    s.op = op;
    s.tool = SweepTool{ToolKind::kBall, c.r * L.cell_m, 0.0};
    s.path_m = Segment{L.to_world(c.a), L.to_world(c.b)};
    return s;
}

struct ExactReport {
    double max_symdiff = 0.0;   ///< worst ray, cells
    double total_symdiff = 0.0; ///< summed over all rays of all sets, cells
    std::size_t rays_off = 0;   ///< rays with symdiff > 1e-4 cells
    std::size_t untouched_changed = 0;  ///< rays farther than r + 1e-3 from every path that changed anyway
    std::size_t invariant_bad = 0;
    int worst[3] = {-1, -1, -1};  ///< set, u, v of the worst ray
    std::size_t tie_closed = 0, tie_open = 0;  ///< grazing rays (> 0.5 cell apart) matching only the closed / open capsule
    std::string tie_rays;                      ///< the first few closed-only rays, set:(u,v)
};

/// Applies `cuts` (subtract) to a copy of `m` with apply_sweep and exactly in double; compares.
ExactReport cut_and_compare(TriDexel& m, const std::vector<BallCut>& cuts) {
    const TriDexel before = m;
    for (const BallCut& c : cuts) apply_sweep(m, ball_sweep(m.lattice, c));
    ExactReport rep;
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = m.sets[a];
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u) {
                Vec3 o(0.0);
                o[(a + 1) % 3] = u;
                o[(a + 2) % 3] = v;
                // The exact solid with the open capsule (a grazing ray keeps its material) and with the
                // closed one (radius r (1 + 1e-9): a ray tangent along a cylinder loses the tangent line).
                Solid1d open = to_1d(before.sets[a].ray(u, v)), closed = open;
                bool near = false;
                for (const BallCut& c : cuts) {
                    double t0, t1;
                    if (test::exact_capsule_chord(o, a, c.a, c.b, c.r, t0, t1)) open = subtract_1d(open, t0, t1);
                    if (test::exact_capsule_chord(o, a, c.a, c.b, c.r * (1.0 + 1e-9), t0, t1)) closed = subtract_1d(closed, t0, t1);
                    if (test::exact_capsule_chord(o, a, c.a, c.b, c.r + 1e-3, t0, t1)) near = true;
                }
                const auto& now = set.ray(u, v);
                if (!test::ray_violation(now).empty()) ++rep.invariant_bad;
                if (!near && !test::same_bits(now, before.sets[a].ray(u, v))) ++rep.untouched_changed;
                const double d_open = symdiff_1d(to_1d(now), open), d_closed = symdiff_1d(to_1d(now), closed);
                const double d = std::min(d_open, d_closed);
                if (d_open > 0.5 && d_closed < 0.5 && ++rep.tie_closed <= 4)
                    rep.tie_rays += " " + std::to_string(a) + ":(" + std::to_string(u) + "," + std::to_string(v) + ")";
                if (d_closed > 0.5 && d_open < 0.5) ++rep.tie_open;
                if (d > rep.max_symdiff) rep.worst[0] = a, rep.worst[1] = u, rep.worst[2] = v;
                rep.max_symdiff = std::max(rep.max_symdiff, d);
                rep.total_symdiff += d;
                if (d > 1e-4) ++rep.rays_off;
            }
    }
    return rep;
}

void print(const char* what, const ExactReport& r) {
    std::printf("%-44s max |model - exact| per ray %.3g cells, total %.3g cells, rays off by > 1e-4 cell %zu, "
                "far rays changed %zu, invariant violations %zu; worst ray: set %d (u, v) = (%d, %d); grazing rays cut as by the "
                "closed capsule %zu%s, as by the open one %zu\n",
                what, r.max_symdiff, r.total_symdiff, r.rays_off, r.untouched_changed, r.invariant_bad, r.worst[0], r.worst[1],
                r.worst[2], r.tie_closed, r.tie_rays.c_str(), r.tie_open);
}

// Bound on a ray's error (cells). Float chords of a ray at distance d from the axis: h = sqrt(r^2 - d^2)
// has an error of about eps * r^2 / h, largest at grazing (h ~ sqrt(eps) r), so up to ~1e-3 cells there.
constexpr double kRayTol = 2e-3;

TEST(StressDegenerate, TangentRaysCentreOnNodeLineAndPlane) {
    for (double r : {1.0, 3.0, 4.0, 7.0}) {
        TriDexel m = test::stress_box(64, 2.5, 61.5);
        // Zero-length ball centred on node (32, 32, 32), whole-cell radius: the rays at distance r graze it.
        const ExactReport rep = cut_and_compare(m, {{Vec3(32.0), Vec3(32.0), r}});
        print(("tangent ball r " + std::to_string(int(r)) + " on a node").c_str(), rep);
        EXPECT_LT(rep.max_symdiff, kRayTol) << r;
        EXPECT_EQ(rep.untouched_changed, 0u);
        EXPECT_EQ(rep.invariant_bad, 0u);
        // The grazing rays (distance exactly r) keep their single interval: no zero-length piece survives.
        EXPECT_EQ(m.sets[0].ray(32 + int(r), 32).size(), 1u) << r;
        EXPECT_EQ(m.sets[2].ray(32, 32 - int(r)).size(), 1u) << r;
    }
    const std::vector<std::pair<const char*, BallCut>> cases = {
        {"segment on a lattice line (x, y=20, z=30)", {Vec3(10.0, 20.0, 30.0), Vec3(50.0, 20.0, 30.0), 4.0}},
        {"segment in a lattice plane (z=30)", {Vec3(10.0, 14.3, 30.0), Vec3(50.0, 41.7, 30.0), 3.5}},
        {"segment node to node, whole-cell radius", {Vec3(12.0, 15.0, 18.0), Vec3(44.0, 31.0, 47.0), 5.0}},
        {"zero-length, off the lattice", {Vec3(31.37, 29.81, 33.06), Vec3(31.37, 29.81, 33.06), 6.2}},
    };
    for (const auto& [what, c] : cases) {
        TriDexel m = test::stress_box(64, 2.5, 61.5);
        const ExactReport rep = cut_and_compare(m, {c});
        print(what, rep);
        EXPECT_LT(rep.max_symdiff, kRayTol) << what;
        EXPECT_EQ(rep.untouched_changed, 0u) << what;
        EXPECT_EQ(rep.invariant_bad, 0u) << what;
    }
}

TEST(StressDegenerate, VeryLongAndTinyAndHugeTools) {
    {  // Much longer than the workpiece (both ends far outside the lattice).
        // Per-ray bound found: ~1e-5 cell for 700 cells, ~1e-2 cell on a ray grazing a 10^4-cell segment (the
        // float delta carries ~1e4 * 2^-24 cells, which the grazing sqrt amplifies).
        for (const auto& [what, c, tol] : {std::tuple{"segment 700 cells long", BallCut{Vec3(-300.0, 20.3, 30.7), Vec3(400.0, 40.1, 33.2), 3.7}, kRayTol},
                                          std::tuple{"segment 10^4 cells long, grazing rays", BallCut{Vec3(32.0, -5000.0, 10.0), Vec3(32.0, 5000.0, 50.0), 2.0}, 0.03},
                                          std::tuple{"segment 10^4 cells long, generic", BallCut{Vec3(32.3, -5000.0, 10.0), Vec3(32.3, 5000.0, 50.0), 2.1}, 0.03}}) {
            TriDexel m1 = test::stress_box(64, 2.5, 61.5);
            const ExactReport rep = cut_and_compare(m1, {c});
            print(what, rep);
            EXPECT_LT(rep.max_symdiff, tol) << what;
            EXPECT_EQ(rep.untouched_changed, 0u) << what;
            EXPECT_EQ(rep.invariant_bad, 0u) << what;
        }
        TriDexel m = test::stress_box(64, 2.5, 61.5);
        // Beyond 2^24 cells the sweep is refused and the model is unchanged.
        const std::size_t n = m.interval_count();
        EXPECT_THROW(apply_sweep(m, ball_sweep(m.lattice, {Vec3(32.0), Vec3(3.0e7, 32.0, 32.0), 2.0})), Error);
        EXPECT_EQ(m.interval_count(), n);
    }
    {  // Tools of 0.1 cell: only the rays within 0.1 cell of the path change, each by the exact chord.
        TriDexel m = test::stress_box(64, 2.5, 61.5);
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> pos(4.0, 60.0), step(-3.0, 3.0);
        std::vector<BallCut> cuts;
        for (int i = 0; i < 400; ++i) {
            Vec3 a(pos(rng), pos(rng), pos(rng));
            if (i % 4 == 0) a = glm::round(a);  // on nodes: the rays through them are hit
            const Vec3 b = i % 3 == 0 ? a : a + Vec3(step(rng), step(rng), step(rng));
            cuts.push_back({a, b, 0.1});
        }
        const ExactReport rep = cut_and_compare(m, cuts);
        print("400 sweeps of radius 0.1 cell", rep);
        EXPECT_LT(rep.max_symdiff, kRayTol);
        EXPECT_EQ(rep.untouched_changed, 0u);
        EXPECT_EQ(rep.invariant_bad, 0u);
        EXPECT_GT(rep.total_symdiff + static_cast<double>(m.interval_count()), 0.0);
    }
    {  // Larger than the workpiece: a ball and a flat-end mill each remove everything.
        for (int kind = 0; kind < 2; ++kind) {
            TriDexel m = test::stress_box(64, 2.5, 61.5);
            Sweep s = ball_sweep(m.lattice, {Vec3(32.0), Vec3(40.0), 100.0});
            if (kind == 1) {
                s.tool = SweepTool{ToolKind::kFlatEnd, 100.0 * m.lattice.cell_m, 200.0 * m.lattice.cell_m};
                s.path_m = Segment{m.lattice.to_world(Vec3(32.0, 32.0, -10.0)), m.lattice.to_world(Vec3(32.0, 32.0, -5.0))};
            }
            apply_sweep(m, s);
            std::printf("tool larger than the workpiece (%s): intervals left %zu, volume %.3g m^3\n",
                        kind ? "flat-end r 100 cells" : "ball r 100 cells", m.interval_count(), dexel_volume_m3(m));
            EXPECT_EQ(m.interval_count(), 0u);
            EXPECT_EQ(dexel_volume_m3(m), 0.0);
        }
        // A huge union into an empty model fills every ray with exactly one interval.
        TriDexel m = test::stress_box(32, 0.0, 0.0);
        apply_sweep(m, ball_sweep(m.lattice, {Vec3(16.0), Vec3(16.0), 100.0}, ToolOp::kUnion));
        std::size_t one = 0, rays = 0;
        float lo = 0.0f, hi = 0.0f;
        for (const RaySet& set : m.sets)
            for (const auto& ray : set.rays) {
                ++rays;
                if (ray.size() == 1 && ray[0].enter <= 0.0f && ray[0].exit >= 32.0f) ++one;
                if (!ray.empty()) lo = std::min(lo, ray[0].enter), hi = std::max(hi, ray[0].exit);
            }
        std::printf("huge union into an empty 32^3 model: %zu of %zu rays hold one interval covering the lattice; "
                    "depths span [%.2f, %.2f] cells (not clipped to the lattice [0, 32])\n", one, rays, lo, hi);
        EXPECT_EQ(one, rays);
    }
}

TEST(StressDegenerate, RemovedVolumesMatchTheAnalyticSolids) {
    // Two references: the analytic volume, and the dexel estimate of the exact solid (each ray's exact
    // double chord, summed per set, averaged over the sets): the sweep's own error is the midpoint-rule
    // removed volume - the latter; the rest is the dexel sampling error (largest for lattice-aligned whole-cell radii, where
    // the node count in a disc is the Gauss circle problem).
    struct Case {
        const char* what;
        BallCut cut;
        double exact_cells3;
        double analytic_tol;  // relative
        double sampled_tol = 1e-5;  // relative, against the exact chords on the rays
    };
    const double pi = 3.14159265358979323846;
    const auto ball = [&](double r) { return 4.0 / 3.0 * pi * r * r * r; };
    const auto capsule = [&](double r, double L) { return pi * r * r * L + ball(r); };
    const Vec3 d = glm::normalize(Vec3(1.0, 0.7, -0.4));
    const std::vector<Case> cases = {
        {"ball r 10.3 (centre off the lattice)", {Vec3(40.2, 39.7, 40.4), Vec3(40.2, 39.7, 40.4), 10.3}, ball(10.3), 0.005},
        {"ball r 12 (centre on a node)", {Vec3(40.0), Vec3(40.0), 12.0}, ball(12.0), 0.01},
        {"ball r 2.5", {Vec3(40.2, 39.7, 40.4), Vec3(40.2, 39.7, 40.4), 2.5}, ball(2.5), 0.02},
        {"capsule r 8 L 30 on a lattice line", {Vec3(25.0, 40.0, 40.0), Vec3(55.0, 40.0, 40.0), 8.0}, capsule(8.0, 30.0), 0.025, 5e-3},  // 2 grazing rays cut (see above)
        {"capsule r 7.4 L 36 oblique", {Vec3(40.3) - 18.0 * d, Vec3(40.3) + 18.0 * d, 7.4}, capsule(7.4, 36.0), 0.005},
        {"capsule r 1.5 L 36 oblique", {Vec3(40.3) - 18.0 * d, Vec3(40.3) + 18.0 * d, 1.5}, capsule(1.5, 36.0), 0.02},
    };
    // The midpoint rule alone (no face correction), as the exact chords are summed.
    const auto raw_volume = [](const TriDexel& t) {
        return (ray_set_volume_m3(t, 0) + ray_set_volume_m3(t, 1) + ray_set_volume_m3(t, 2)) / 3.0;
    };
    for (const Case& c : cases) {
        TriDexel m = test::stress_box(80, 2.5, 77.5);
        const double h3 = std::pow(m.lattice.cell_m, 3);
        const double v0 = dexel_volume_m3(m), v0_raw = raw_volume(m);
        apply_sweep(m, ball_sweep(m.lattice, c.cut));
        double chords = 0.0;  // exact chord lengths, cells, all sets
        for (int a = 0; a < 3; ++a)
            for (int v = 0; v < m.sets[a].nv; ++v)
                for (int u = 0; u < m.sets[a].nu; ++u) {
                    Vec3 o(0.0);
                    o[(a + 1) % 3] = u;
                    o[(a + 2) % 3] = v;
                    double t0, t1;
                    if (test::exact_capsule_chord(o, a, c.cut.a, c.cut.b, c.cut.r, t0, t1)) chords += t1 - t0;
                }
        const double removed = v0 - dexel_volume_m3(m), exact = c.exact_cells3 * h3, sampled = chords / 3.0 * h3;
        const double removed_raw = v0_raw - raw_volume(m);
        const double rel = (removed - exact) / exact, rel_sampled = (removed_raw - sampled) / sampled;
        std::printf("%-36s removed %.6e m^3; analytic %.6e m^3 (%+.3f%%); exact chords sampled on the rays %.6e m^3 (%+.2e)\n",
                    c.what, removed, exact, 100.0 * rel, sampled, rel_sampled);
        EXPECT_LT(std::fabs(rel), c.analytic_tol) << c.what;
        EXPECT_LT(std::fabs(rel_sampled), c.sampled_tol) << c.what;
    }
    // A flat-end mill held still: a cylinder, pi r^2 L.
    TriDexel m = test::stress_box(80, 2.5, 77.5);
    const double v0 = dexel_volume_m3(m);
    Sweep s;
    s.tool = SweepTool{ToolKind::kFlatEnd, 9.3 * m.lattice.cell_m, 20.0 * m.lattice.cell_m};
    s.path_m = Segment{m.lattice.to_world(Vec3(40.2, 39.9, 30.1)), m.lattice.to_world(Vec3(40.2, 39.9, 30.1))};
    apply_sweep(m, s);
    const double removed = v0 - dexel_volume_m3(m), exact = pi * 9.3 * 9.3 * 20.0 * std::pow(m.lattice.cell_m, 3);
    std::printf("%-38s removed %.6e m^3, analytic %.6e m^3, error %+.3f%%\n", "flat-end r 9.3 L 20, still", removed, exact,
                100.0 * (removed - exact) / exact);
    EXPECT_LT(std::fabs(removed - exact) / exact, 0.01);
}

TEST(StressDegenerate, WorkpieceOneKilometreAwayGivesTheSameIntervals) {
    // The same random stroke program (ball and flat-end, subtract, union, paint) in grid units, on a
    // workpiece whose lattice origin is at o, o + 1 km and o + 100 km along every axis.
    const Vec3 base(0.3, -0.2, 0.7);
    auto run = [&](const Vec3& shift) {
        TriDexel m = test::stress_box(64, 3.5, 60.5, base + shift);
        std::mt19937 rng(9);
        std::uniform_real_distribution<double> pos(0.0, 64.0), unit(0.0, 1.0);
        for (int i = 0; i < 3000; ++i) {
            Sweep s;
            s.op = i % 7 == 3 ? ToolOp::kUnion : i % 11 == 5 ? ToolOp::kPaint : ToolOp::kSubtract;
            s.material = static_cast<std::uint8_t>(i % 5);
            const bool flat = unit(rng) < 0.3;
            s.tool = SweepTool{flat ? ToolKind::kFlatEnd : ToolKind::kBall, (0.3 + 6.0 * unit(rng)) * m.lattice.cell_m,
                               (1.0 + 8.0 * unit(rng)) * m.lattice.cell_m};
            s.axis = Vec3(unit(rng) - 0.5, unit(rng) - 0.5, 1.0);
            Vec3 a(pos(rng), pos(rng), pos(rng));
            if (i % 5 == 0) a = glm::round(a);
            const Vec3 b = a + Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5) * 8.0;
            s.path_m = Segment{m.lattice.to_world(a), m.lattice.to_world(b)};
            apply_sweep(m, s);
        }
        return m;
    };
    const TriDexel ref = run(Vec3(0.0));
    for (double km : {1.0, 100.0}) {
        const TriDexel far = run(Vec3(km * 1000.0));
        std::size_t differ = 0, bad = 0;
        double max_d = 0.0;
        for (int a = 0; a < 3; ++a)
            for (std::size_t i = 0; i < ref.sets[a].rays.size(); ++i) {
                const auto& x = ref.sets[a].rays[i];
                const auto& y = far.sets[a].rays[i];
                if (!test::ray_violation(y).empty()) ++bad;
                if (test::same_bits(x, y)) continue;
                ++differ;
                if (x.size() != y.size()) { max_d = INFINITY; continue; }
                for (std::size_t k = 0; k < x.size(); ++k)
                    max_d = std::max({max_d, std::fabs(double(x[k].enter) - y[k].enter), std::fabs(double(x[k].exit) - y[k].exit)});
            }
        std::printf("workpiece %g km from the origin: %zu rays (of %zu) differ from the run at the origin, max depth "
                    "difference %.3g cells; volumes %.9e / %.9e m^3; invariant violations %zu\n",
                    km, differ, 3 * ref.sets[0].rays.size(), max_d, dexel_volume_m3(ref), dexel_volume_m3(far), bad);
        EXPECT_EQ(bad, 0u);
        if (km == 1.0) {
            EXPECT_LE(max_d, 1e-3) << "1 km: the local origin should keep the result (near) identical";
        }
    }
}

}  // namespace
