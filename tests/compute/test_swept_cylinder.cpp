// tests/compute/test_swept_cylinder.cpp - swept_cylinder_chord (a flat-end mill moved along a segment, in closed
// form) against the moving cylinder sampled densely in double: random axes, motions (across, along, oblique
// to the axis, zero) and lines (lattice-aligned and oblique). The chord must cover every sampled pose's chord
// and its ends must lie on the swept volume's surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "compute/tools/capsule.hpp"

using namespace tridex::compute;

namespace {

using D3 = glm::dvec3;

/// Exact chord (double) of the line o + t*d (|d| = 1) with the cylinder at `a`: unit axis n, length len, radius r.
bool cylinder_chord_d(D3 o, D3 d, D3 a, D3 n, double len, double r, double& t0, double& t1) {
    const D3 m = o - a;
    const D3 mp = m - n * glm::dot(m, n), dp = d - n * glm::dot(d, n);
    const double qa = glm::dot(dp, dp), qb = glm::dot(mp, dp), qc = glm::dot(mp, mp) - r * r;
    double lo = -1e300, hi = 1e300;
    if (qa > 1e-300) {
        const double disc = qb * qb - qa * qc;
        if (disc < 0.0) return false;
        lo = (-qb - std::sqrt(disc)) / qa;
        hi = (-qb + std::sqrt(disc)) / qa;
    } else if (qc > 0.0) {
        return false;
    }
    const double ms = glm::dot(m, n), ds = glm::dot(d, n);
    if (std::abs(ds) > 1e-300) {
        const double ta = -ms / ds, tb = (len - ms) / ds;
        lo = std::max(lo, std::min(ta, tb));
        hi = std::min(hi, std::max(ta, tb));
    } else if (ms < 0.0 || ms > len) {
        return false;
    }
    if (!(lo <= hi)) return false;
    t0 = lo;
    t1 = hi;
    return true;
}

/// Signed distance-like measure of p outside the cylinder (0 on its surface, < 0 inside; exact outside the
/// caps' rims, a lower bound of the distance there).
double cylinder_sdf(D3 p, D3 a, D3 n, double len, double r) {
    const D3 m = p - a;
    const double h = glm::dot(m, n);
    const double radial = glm::length(m - n * h) - r;
    const double axial = std::max(-h, h - len);
    if (radial > 0.0 && axial > 0.0) return std::hypot(radial, axial);
    return std::max(radial, axial);
}

D3 random_unit(std::mt19937& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    for (;;) {
        const D3 v(g(rng), g(rng), g(rng));
        if (glm::length(v) > 1e-3) return glm::normalize(v);
    }
}

}  // namespace

TEST(SweptCylinderChord, RandomLinesMatchTheSampledMotion) {
    std::mt19937 rng(20);
    std::uniform_real_distribution<double> u01(0.0, 1.0), span(-12.0, 12.0);
    const D3 axes[3] = {D3(1, 0, 0), D3(0, 1, 0), D3(0, 0, 1)};
    constexpr int kSamples = 4000;
    int hits = 0, checked = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const int shape = trial % 6;
        const D3 n = shape < 3 ? axes[trial / 6 % 3] : random_unit(rng);
        const double r = 0.5 + 5.0 * u01(rng), len = 1.0 + 10.0 * u01(rng);
        D3 delta = random_unit(rng) * (12.0 * u01(rng));
        if (shape == 0 || shape == 3) delta -= n * glm::dot(delta, n);  // across the axis: an extruded stadium
        if (shape == 1) delta = n * (8.0 * (u01(rng) - 0.5));          // along the axis: a longer cylinder
        if (trial % 50 == 7) delta = D3(0.0);                           // no motion: the cylinder
        const D3 d = trial % 4 == 3 ? random_unit(rng) : axes[trial % 3];
        // A line through a random point of the swept box (grown by 2): most lines cut the volume, many graze it.
        const D3 o = delta * u01(rng) + n * (len * u01(rng)) + D3(span(rng), span(rng), span(rng)) * ((r + 2.0) / 12.0);
        // Float inputs, and the double reference on the very same (float-rounded) numbers.
        const glm::vec3 of(o), df(d), ef(n * len), delf(delta);
        const D3 od(of), dd(df), nd = glm::normalize(D3(ef)), deld(delf);
        const double lend = glm::length(D3(ef));
        float t0 = 0.0f, t1 = 0.0f;
        const bool hit = swept_cylinder_chord(of, df, ef, delf, static_cast<float>(r), t0, t1);
        // Every pose's chord lies inside ours; a miss means no pose is cut by more than a grazing sliver.
        double ref_lo = 1e300, ref_hi = -1e300;
        for (int k = 0; k <= kSamples; ++k) {
            double a0, a1;
            if (cylinder_chord_d(od, dd, deld * (double(k) / kSamples), nd, lend, r, a0, a1)) {
                ref_lo = std::min(ref_lo, a0);
                ref_hi = std::max(ref_hi, a1);
            }
        }
        const double tol = 1e-4 * (1.0 + std::abs(ref_lo) + std::abs(ref_hi));  // float rounding of ours
        if (!hit) {
            EXPECT_TRUE(ref_lo > ref_hi || ref_hi - ref_lo < 1e-2) << "trial " << trial << ": missed a chord of length " << ref_hi - ref_lo;
            continue;
        }
        ++hits;
        ASSERT_LE(t0, t1);
        if (ref_lo <= ref_hi) {
            EXPECT_LE(t0, ref_lo + tol) << "trial " << trial << " shape " << shape;
            EXPECT_GE(t1, ref_hi - tol) << "trial " << trial << " shape " << shape;
        }
        // Both ends lie on the swept volume's surface: some pose's cylinder comes within the sampling bound.
        const double bound = glm::length(deld) / kSamples + 1e-3;
        for (const float t : {t0, t1}) {
            const D3 p = od + dd * double(t);
            double best = 1e300;
            for (int k = 0; k <= kSamples; ++k) best = std::min(best, cylinder_sdf(p, deld * (double(k) / kSamples), nd, lend, r));
            EXPECT_LE(best, bound) << "trial " << trial << " shape " << shape << ": end t = " << t << " lies off the swept volume";
            ++checked;
        }
    }
    EXPECT_GT(hits, 1200);  // about half the lines cut the volume
    EXPECT_EQ(checked, 2 * hits);
}

TEST(SweptCylinderChord, ExtrudedStadiumClosedForm) {
    // Axis +z, length 4, radius 2, moved 10 along +x: the solid is the stadium x in [-2, 12] (round ends)
    // extruded over z in [0, 4].
    float t0, t1;
    ASSERT_TRUE(swept_cylinder_chord({-10, 1, 2}, {1, 0, 0}, {0, 0, 4}, {10, 0, 0}, 2.0f, t0, t1));
    const double half = std::sqrt(4.0 - 1.0);
    EXPECT_NEAR(t0, 10.0 - half, 1e-5);
    EXPECT_NEAR(t1, 20.0 + half, 1e-5);
    ASSERT_TRUE(swept_cylinder_chord({5, -10, 1}, {0, 1, 0}, {0, 0, 4}, {10, 0, 0}, 2.0f, t0, t1));  // across the flat walls
    EXPECT_NEAR(t0, 8.0, 1e-5);
    EXPECT_NEAR(t1, 12.0, 1e-5);
    ASSERT_TRUE(swept_cylinder_chord({5, 1, -3}, {0, 0, 1}, {0, 0, 4}, {10, 0, 0}, 2.0f, t0, t1));  // along the axis
    EXPECT_NEAR(t0, 3.0, 1e-5);
    EXPECT_NEAR(t1, 7.0, 1e-5);
    EXPECT_FALSE(swept_cylinder_chord({5, 2.5f, -3}, {0, 0, 1}, {0, 0, 4}, {10, 0, 0}, 2.0f, t0, t1));
    EXPECT_FALSE(swept_cylinder_chord({5, 0, 4.5f}, {1, 0, 0}, {0, 0, 4}, {10, 0, 0}, 2.0f, t0, t1));  // above the top
    // Oblique motion (down and across): the line y = 0, z = 1 meets the tool while its span [-4l, 4 - 4l]
    // along z covers 1, i.e. for the poses l in [0, 0.75]: x in [-2, 7.5 + 2].
    ASSERT_TRUE(swept_cylinder_chord({-10, 0, 1}, {1, 0, 0}, {0, 0, 4}, {10, 0, -4}, 2.0f, t0, t1));
    EXPECT_NEAR(t0, 8.0, 1e-5);
    EXPECT_NEAR(t1, 19.5, 1e-5);
}

TEST(SweptCylinderChord, LineNearlyInTheCapPlane) {
    // A lattice line at 0.4 degrees to the flat end's plane, the tool moving steeply through it: the cap
    // crossing must be found with the slope of its parametrisation kept within 1 (else float cancellation
    // shortens the chord by 0.05 cell). Reference: the cylinder at 200,000 poses, in double.
    const glm::dvec3 n = glm::normalize(glm::dvec3(-0.004792, 0.504368, -0.502509));
    const glm::vec3 e(n * 10.454740), delta(-10.710659f, 0.485882f, -10.298403f);
    float t0, t1;
    ASSERT_TRUE(swept_cylinder_chord({-7.0f, 0.0f, -7.0f}, {1, 0, 0}, e, delta, 0.521695f, t0, t1));
    EXPECT_NEAR(t0, -0.225751, 1e-4);  // t is x: the line starts at x = -7 from the tool start at x = 7
    EXPECT_NEAR(t1, 0.318101, 1e-4);
}

TEST(SweptCylinderChord, DegenerateInputsMiss) {
    float t0, t1;
    EXPECT_FALSE(swept_cylinder_chord({0, 0, 0}, {0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 1.0f, t0, t1));
    EXPECT_FALSE(swept_cylinder_chord({0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {1, 0, 0}, 1.0f, t0, t1));
    EXPECT_FALSE(swept_cylinder_chord({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {1, 0, 0}, 0.0f, t0, t1));
    EXPECT_FALSE(swept_cylinder_chord({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {1, 0, 0}, NAN, t0, t1));
    // An axis nearly across the line: products near the float range must not give a chord from NaN.
    const bool hit = swept_cylinder_chord({0, 30, 0.5f}, {0, 0, 1}, {1e3f, 0, 1e-30f}, {0, 5, 0}, 1.0f, t0, t1);
    EXPECT_FALSE(hit);
}
