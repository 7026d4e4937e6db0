// tests/compute/test_capsule.cpp - capsule_chord against analytic chords and a double-precision
// reference built from the capsule's distance function.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "compute/tools/capsule.hpp"

using tridex::compute::capsule_chord;

namespace {

/// Distance from p to the segment a-b, double precision.
double seg_dist(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 e = b - a;
    const double ee = glm::dot(e, e);
    const double s = ee > 0.0 ? std::clamp(glm::dot(p - a, e) / ee, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + s * e));
}

/// Reference chord: f(t) = distance(o + t d, segment) is convex, so its minimum is found by ternary
/// search and the two crossings of f = r by bisection on each side. Double precision throughout.
bool reference_chord(glm::dvec3 o, glm::dvec3 d, glm::dvec3 a, glm::dvec3 b, double r, double& t0, double& t1) {
    auto f = [&](double t) { return seg_dist(o + t * d, a, b) - r; };
    double lo = -1e3, hi = 1e3;
    for (int i = 0; i < 300; ++i) {
        const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
        if (f(m1) < f(m2)) hi = m2;
        else lo = m1;
    }
    const double tmin = 0.5 * (lo + hi);
    if (f(tmin) > 0.0) return false;
    auto root = [&](double inside, double outside) {
        for (int i = 0; i < 200; ++i) {
            const double mid = 0.5 * (inside + outside);
            (f(mid) <= 0.0 ? inside : outside) = mid;
        }
        return 0.5 * (inside + outside);
    };
    t0 = root(tmin, -1e3);
    t1 = root(tmin, 1e3);
    return true;
}

const glm::vec3 kA(0, 0, 0), kB(0, 0, 4);  // capsule along z, length 4
constexpr float kR = 1.0f;

}  // namespace

TEST(CapsuleChord, RayThroughTheAxis) {
    float t0, t1;
    ASSERT_TRUE(capsule_chord({-5, 0, 2}, {1, 0, 0}, kA, kB, kR, t0, t1));  // through the cylinder part
    EXPECT_NEAR(t0, 4.0f, 1e-6f);
    EXPECT_NEAR(t1, 6.0f, 1e-6f);
    ASSERT_TRUE(capsule_chord({-5, 0, 4.5f}, {1, 0, 0}, kA, kB, kR, t0, t1));  // through the end ball at b
    EXPECT_NEAR(t0, 5.0f - std::sqrt(0.75f), 1e-6f);
    EXPECT_NEAR(t1, 5.0f + std::sqrt(0.75f), 1e-6f);
    ASSERT_TRUE(capsule_chord({3, 0, -3}, {-1, 0, 1}, kA, kB, kR, t0, t1));  // slanted, crossing the axis at z = 0
    // Enters through the ball at a: |(3 - t, 0, t - 3)| = 1 -> t = 3 - 1/sqrt(2); leaves through the
    // cylinder wall x = -1 at t = 4 (z = 1).
    EXPECT_NEAR(t0, 3.0f - std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(t1, 4.0f, 1e-6f);
}

TEST(CapsuleChord, GrazingAndMissing) {
    float t0, t1;
    const float y = 1.0f - 1e-3f;
    ASSERT_TRUE(capsule_chord({-5, y, 2}, {1, 0, 0}, kA, kB, kR, t0, t1));
    const float half = std::sqrt(1.0f - y * y);  // 0.0447
    EXPECT_NEAR(t0, 5.0f - half, 1e-5f);
    EXPECT_NEAR(t1, 5.0f + half, 1e-5f);
    EXPECT_FALSE(capsule_chord({-5, 1.001f, 2}, {1, 0, 0}, kA, kB, kR, t0, t1));
    EXPECT_FALSE(capsule_chord({-5, 0, 5.001f}, {1, 0, 0}, kA, kB, kR, t0, t1));  // just above the top ball
    ASSERT_TRUE(capsule_chord({-5, 1, 2}, {1, 0, 0}, kA, kB, kR, t0, t1));      // exactly tangent
    EXPECT_FLOAT_EQ(t0, 5.0f);
    EXPECT_FLOAT_EQ(t1, 5.0f);
}

TEST(CapsuleChord, ParallelToTheAxis) {
    float t0, t1;
    ASSERT_TRUE(capsule_chord({0.5f, 0, -10}, {0, 0, 1}, kA, kB, kR, t0, t1));
    EXPECT_NEAR(t0, 10.0f - std::sqrt(0.75f), 1e-5f);
    EXPECT_NEAR(t1, 14.0f + std::sqrt(0.75f), 1e-5f);
    ASSERT_TRUE(capsule_chord({0, 0, 10}, {0, 0, -2}, kA, kB, kR, t0, t1));  // reversed, non-unit direction
    EXPECT_NEAR(t0, 2.5f, 1e-6f);  // z = 5
    EXPECT_NEAR(t1, 5.5f, 1e-6f);  // z = -1
    ASSERT_TRUE(capsule_chord({1, 0, -10}, {0, 0, 1}, kA, kB, kR, t0, t1));  // along the wall
    EXPECT_FLOAT_EQ(t0, 10.0f);
    EXPECT_FLOAT_EQ(t1, 14.0f);
    EXPECT_FALSE(capsule_chord({1.5f, 0, -10}, {0, 0, 1}, kA, kB, kR, t0, t1));
}

TEST(CapsuleChord, ZeroLengthSegmentIsABall) {
    float t0, t1;
    const glm::vec3 c(1, 2, 3);
    ASSERT_TRUE(capsule_chord({1, 2, -10}, {0, 0, 2}, c, c, 2.0f, t0, t1));
    EXPECT_FLOAT_EQ(t0, 5.5f);  // z = 1
    EXPECT_FLOAT_EQ(t1, 7.5f);  // z = 5
    ASSERT_TRUE(capsule_chord({1, 3, -10}, {0, 0, 1}, c, c, 2.0f, t0, t1));  // 1 from the centre
    EXPECT_NEAR(t0, 13.0f - std::sqrt(3.0f), 1e-5f);
    EXPECT_NEAR(t1, 13.0f + std::sqrt(3.0f), 1e-5f);
    EXPECT_FALSE(capsule_chord({1, 4.01f, -10}, {0, 0, 1}, c, c, 2.0f, t0, t1));
}

TEST(CapsuleChord, DegenerateInputsMiss) {
    float t0 = -7, t1 = -7;
    EXPECT_FALSE(capsule_chord({0, 0, 0}, {0, 0, 0}, kA, kB, kR, t0, t1));
    EXPECT_FALSE(capsule_chord({-5, 0, 2}, {1, 0, 0}, kA, kB, 0.0f, t0, t1));
    EXPECT_FALSE(capsule_chord({-5, 0, 2}, {1, 0, 0}, kA, kB, -1.0f, t0, t1));
    EXPECT_FALSE(capsule_chord({-5, 0, 2}, {1, 0, 0}, kA, kB, NAN, t0, t1));
    EXPECT_EQ(t0, -7.0f);
    EXPECT_EQ(t1, -7.0f);
}

TEST(CapsuleChord, RandomLinesMatchDoubleReference) {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> pos(-6.0f, 6.0f), dir(-1.0f, 1.0f), rad(0.2f, 3.0f);
    int hits = 0, misses = 0;
    for (int i = 0; i < 400; ++i) {
        const glm::vec3 a(pos(rng), pos(rng), pos(rng));
        const glm::vec3 b = i % 10 == 0 ? a : glm::vec3(pos(rng), pos(rng), pos(rng));
        const glm::vec3 o(pos(rng), pos(rng), pos(rng)), d(dir(rng), dir(rng), dir(rng));
        const float r = rad(rng);
        if (glm::length(d) < 0.1f) continue;
        double r0, r1;
        const bool ref = reference_chord(o, d, a, b, r, r0, r1);
        float t0, t1;
        const bool got = capsule_chord(o, d, a, b, r, t0, t1);
        // Lines within 1e-4 of tangent may go either way in float.
        if (ref != got) {
            double q0, q1;
            EXPECT_TRUE(ref ? !reference_chord(o, d, a, b, r - 1e-4, q0, q1) : reference_chord(o, d, a, b, r + 1e-4, q0, q1))
                << "case " << i;
            continue;
        }
        if (!ref) {
            ++misses;
            continue;
        }
        ++hits;
        // Tolerance: float rounding of terms of size ~|o|^2 |e|^2, relative 1e-6, plus the sqrt
        // amplification near tangency (not reached at this sampling).
        EXPECT_NEAR(t0, r0, 2e-3 * (1.0 + std::abs(r0))) << "case " << i;
        EXPECT_NEAR(t1, r1, 2e-3 * (1.0 + std::abs(r1))) << "case " << i;
    }
    EXPECT_GT(hits, 50);
    EXPECT_GT(misses, 50);
}
