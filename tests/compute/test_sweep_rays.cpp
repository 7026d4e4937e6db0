// tests/compute/test_sweep_rays.cpp - the per-set shortcuts of the ball Boolean (AxisCapsule, SweepShadow) give
// exactly what the generic per-ray chord gives: same chords, no reachable ray left out, same models.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "compute/tools/capsule.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/tools/sweep_parallel.hpp"
#include "sweep_programs.hpp"

namespace tridex::compute {
namespace {

// A float drawn from a few families: uniform, whole and half cells, tiny, exactly zero.
float pick(std::mt19937& rng, float span) {
    std::uniform_real_distribution<float> u(-span, span);
    switch (rng() % 6) {
        case 0: return std::round(u(rng));
        case 1: return 0.5f * std::round(2.0f * u(rng));
        case 2: return 0.0f;
        case 3: return 1e-6f * u(rng);
        default: return u(rng);
    }
}

TEST(AxisCapsule, GivesCapsuleChordsForEveryRayOfEverySet) {
    std::mt19937 rng(7);
    std::size_t hits = 0, n = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const glm::vec3 e(pick(rng, 4.0f), pick(rng, 4.0f), pick(rng, 4.0f));
        float r = std::fabs(pick(rng, 6.0f));
        if (trial % 97 == 0) r = 0.0f;  // degenerate: misses
        for (int axis = 0; axis < 3; ++axis) {
            const AxisCapsule cap(axis, e, r);
            const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
            for (int k = 0; k < 40; ++k) {
                float ou = pick(rng, 10.0f), ov = pick(rng, 10.0f);
                if (k == 0) ou = r, ov = 0.0f;  // tangent to the first end ball
                if (k == 1) ou = e[ua] + r, ov = e[va];  // tangent to the second
                glm::vec3 o(0.0f), d(0.0f);
                o[ua] = ou, o[va] = ov, d[axis] = 1.0f;
                float a0 = 0.0f, a1 = 0.0f, b0 = 0.0f, b1 = 0.0f;
                const bool a = capsule_chord(o, d, glm::vec3(0.0f), e, r, a0, a1);
                const bool b = cap.chord(ou, ov, b0, b1);
                ++n;
                ASSERT_EQ(a, b) << "axis " << axis << " e " << e.x << "," << e.y << "," << e.z << " r " << r << " o " << ou
                                << "," << ov;
                if (!a) continue;
                ++hits;
                // The same floats (a zero may differ in sign only, which the depth base + t removes).
                ASSERT_EQ(a0, b0);
                ASSERT_EQ(a1, b1);
            }
        }
    }
    EXPECT_GT(hits, n / 5);  // the draw reaches the capsules often enough to mean something
}

// A ball or flat-end sweep between two random points (some on lattice nodes, planes and whole-cell radii).
Sweep random_sweep(std::mt19937& rng, const Lattice& L, bool flat) {
    std::uniform_real_distribution<double> pos(4.0, L.cells[0] - 4.0), len(0.0, 6.0), rad(0.3, 5.0), unit(-1.0, 1.0);
    Vec3 a(pos(rng), pos(rng), pos(rng));
    Vec3 b = a + Vec3(len(rng) - 3.0, len(rng) - 3.0, len(rng) - 3.0);
    double r = rad(rng);
    switch (rng() % 4) {
        case 0: a = glm::round(a), b = glm::round(b), r = std::round(r) + 1.0; break;
        case 1: b = a + Vec3(0.0, 0.0, len(rng)); break;  // along one set's rays
        case 2: b = a; break;                              // a tool at rest
        default: break;
    }
    Sweep s;
    s.op = ToolOp::kSubtract;
    s.tool.kind = flat ? ToolKind::kFlatEnd : ToolKind::kBall;
    s.tool.radius_m = r * L.cell_m;
    s.tool.length_m = (1.0 + len(rng)) * L.cell_m;
    s.axis = rng() % 3 == 0 ? Vec3(0.0, 0.0, 1.0) : Vec3(unit(rng), unit(rng), unit(rng) + 1.5);
    s.path_m = Segment{L.to_world(a), L.to_world(b)};
    return s;
}

TEST(SweepRowSpan, KeepsEveryRayTheSweptToolReaches) {
    const TriDexel m = test::box_model(40, 0.0, 0.0);
    std::mt19937 rng(11);
    for (const bool flat : {false, true}) {
        std::size_t kept = 0, footprint = 0, reached = 0;
        for (int trial = 0; trial < 600; ++trial) {
            const GridSweep g = to_grid_sweep(m.lattice, random_sweep(rng, m.lattice, flat));
            for (int axis = 0; axis < 3; ++axis) {
                int u_lo, u_hi, v_lo, v_hi;
                if (!sweep_footprint(g, m.sets[axis], u_lo, u_hi, v_lo, v_hi)) continue;
                for (int v = v_lo; v <= v_hi; ++v) {
                    int a = u_lo, b = u_hi;
                    const bool row = SweepShadow(g, axis).row(v, a, b);
                    footprint += static_cast<std::size_t>(u_hi - u_lo + 1);
                    if (row) kept += static_cast<std::size_t>(b - a + 1);
                    for (int u = u_lo; u <= u_hi; ++u) {
                        float d0, d1;
                        if (!sweep_chord(g, axis, u, v, 0, d0, d1)) continue;
                        ++reached;
                        ASSERT_TRUE(row && u >= a && u <= b)
                            << (flat ? "flat end" : "ball") << " trial " << trial << " axis " << axis << " ray " << u << "," << v;
                    }
                }
            }
        }
        EXPECT_LE(kept, footprint * 9 / 10) << flat;  // it does leave out rays of the footprint
        EXPECT_GE(kept, reached);
    }
}

TEST(SweepRowSpan, MeshToolsKeepTheFootprint) {
    GridSweep g{};
    g.code = static_cast<std::uint32_t>(ToolOp::kSubtract) | (static_cast<std::uint32_t>(ToolKind::kMesh) << 8);
    g.radius = 1.0f;
    int a = 3, b = 30;
    EXPECT_TRUE(SweepShadow(g, 2).row(100, a, b));
    EXPECT_EQ(a, 3);
    EXPECT_EQ(b, 30);
}

// apply_sweep and apply_sweeps_parallel (ball, flat end, every operation) against the plain reference: every ray of
// the footprint through sweep_chord.
TEST(SweepRays, BooleansMatchTheRayByRayReferenceBitForBit) {
    TriDexel fast = test::box_model(48, 6.3, 41.7), parallel = fast, ref = fast;
    const std::vector<Sweep> program = test::random_program(fast.lattice, 400, 5);
    std::size_t balls = 0;
    for (const Sweep& s : program) {
        apply_sweep(fast, s);
        balls += s.tool.kind == ToolKind::kBall;
        ToolTable tools;
        const GridSweep g = to_grid_sweep(ref.lattice, s, &tools);
        for (int axis = 0; axis < 3; ++axis) {
            RaySet& set = ref.sets[axis];
            int u_lo, u_hi, v_lo, v_hi;
            if (!sweep_footprint(g, set, u_lo, u_hi, v_lo, v_hi)) continue;
            for (int v = v_lo; v <= v_hi; ++v)
                for (int u = u_lo; u <= u_hi; ++u)
                    apply_sweep_to_ray(g, axis, u, v, set.ray(u, v), static_cast<float>(ref.lattice.cells[axis]), tools);
        }
    }
    for (std::size_t i = 0; i < program.size(); i += 37)
        apply_sweeps_parallel(parallel, std::span<const Sweep>(program).subspan(i, std::min<std::size_t>(37, program.size() - i)), 2);
    EXPECT_GT(balls, program.size() / 4);
    EXPECT_EQ(test::compare(fast, ref).rays, 0u);
    EXPECT_EQ(test::compare(parallel, ref).rays, 0u);
}

}  // namespace
}  // namespace tridex::compute
