// The clay field's narrow region: phi built over a ball of the box equals, node for node and bit for bit, phi built
// over the whole box; the nodes outside the ball hold NaN; each ray's chord is exactly the run of nodes the region
// contains.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>

#include "clay_test_models.hpp"
#include "compute/tools/clay_field.hpp"

namespace tridex::compute {
namespace {

using clay_test::same_bits;

TriDexel noisy_sphere() {
    return clay_test::from_implicit(clay_test::cube_lattice(32), [](double x, double y, double z) {
        const double dx = x - 16.0, dy = y - 16.0, dz = z - 16.0;
        const double noise = 0.6 * std::sin(1.9 * dx) * std::sin(2.3 * dy) * std::sin(1.7 * dz + 0.4);
        return std::sqrt(dx * dx + dy * dy + dz * dz) - (10.0 + noise);
    });
}

ClayBox box_around(int lo, int hi) {
    ClayBox b;
    for (int a = 0; a < 3; ++a) b.lo[a] = lo, b.hi[a] = hi;
    return b;
}

TEST(ClayField, RegionBuildEqualsWholeBoxBuildInsideTheBall) {
    const TriDexel m = noisy_sphere();
    ClayField whole, part;
    whole.box = part.box = box_around(12, 30);
    const float centre[3] = {20.3f, 19.6f, 25.2f};
    part.region.ball(centre, 6.4f);
    clay_build_phi(m, whole);
    clay_build_phi(m, part);
    std::size_t inside = 0;
    for (int k = 12; k <= 30; ++k)
        for (int j = 12; j <= 30; ++j)
            for (int i = 12; i <= 30; ++i) {
                const std::size_t x = part.box.index(i, j, k);
                EXPECT_EQ(part.s0[x], 0.0f);
                EXPECT_EQ(part.s1[x], 0.0f);
                if (part.region.contains(i, j, k)) {
                    ++inside;
                    EXPECT_TRUE(same_bits(part.phi[x], whole.phi[x])) << i << " " << j << " " << k;
                    EXPECT_TRUE(same_bits(whole.phi[x], clay_node_phi(m, i, j, k))) << i << " " << j << " " << k;
                } else {
                    EXPECT_TRUE(std::isnan(part.phi[x])) << i << " " << j << " " << k;
                }
            }
    EXPECT_GT(inside, 500u);  // the ball (about 1100 nodes) is clipped by the box
}

/// Every ray's chord equals the nodes `f.region` holds on it, exactly.
void expect_exact_chords(const TriDexel& m, ClayField& f) {
    clay_build_phi(m, f);
    for (int a = 0; a < 3; ++a)
        for (int v = 3; v <= 28; ++v)
            for (int u = 3; u <= 28; ++u) {
                const std::array<int, 2>& run = f.chord(a, u, v);
                int lo = 0, hi = -1;
                clay_region_chord(f, a, u, v, lo, hi);
                EXPECT_EQ(run[0] <= run[1], lo <= hi);
                if (lo <= hi) {
                    EXPECT_EQ(run[0], lo);
                    EXPECT_EQ(run[1], hi);
                }
                for (int d = 3; d <= 28; ++d) {
                    int n[3];
                    n[a] = d;
                    n[(a + 1) % 3] = u;
                    n[(a + 2) % 3] = v;
                    EXPECT_EQ(f.region.contains(n[0], n[1], n[2]), lo <= d && d <= hi) << a << " " << u << " " << v;
                }
            }
}

TEST(ClayField, ChordsAreExactlyTheRegionsNodesOnEachRay) {
    const TriDexel m = noisy_sphere();
    ClayField f;
    f.box = box_around(3, 28);
    const float centre[3] = {10.5f, 27.0f, 14.25f};  // partly outside the box
    f.region.ball(centre, 7.0f);
    expect_exact_chords(m, f);
    // Capsules: along an axis, slanted, and with whole-node ends and radius (ties on the boundary).
    const float caps[3][7] = {{12.3f, 15.0f, 16.1f, 20.9f, 15.0f, 16.1f, 5.5f},
                              {9.7f, 11.2f, 22.4f, 21.3f, 18.8f, 12.6f, 4.25f},
                              {10.0f, 12.0f, 14.0f, 18.0f, 12.0f, 20.0f, 5.0f}};
    for (const auto& c : caps) {
        ClayField g;
        g.box = box_around(3, 28);
        for (int a = 0; a < 3; ++a) g.region.c[a] = c[a], g.region.c1[a] = c[3 + a];
        g.region.r = c[6];
        expect_exact_chords(m, g);
    }
    // Random capsules, some with ends on nodes and whole radii (rays tangent to the region's shadow).
    std::uint32_t seed = 12345u;
    const auto next = [&seed](float lo, float hi) {
        seed = seed * 1664525u + 1013904223u;
        return lo + (hi - lo) * static_cast<float>(seed >> 8) / 16777216.0f;
    };
    for (int k = 0; k < 12; ++k) {
        ClayField g;
        g.box = box_around(3, 28);
        for (int a = 0; a < 3; ++a) g.region.c[a] = next(6.0f, 25.0f), g.region.c1[a] = g.region.c[a] + next(-4.0f, 4.0f);
        g.region.r = next(1.0f, 8.0f);
        if (k % 3 == 0)
            for (int a = 0; a < 3; ++a)
                g.region.c[a] = std::round(g.region.c[a]), g.region.c1[a] = std::round(g.region.c1[a]),
                g.region.r = std::round(g.region.r);
        expect_exact_chords(m, g);
    }
}

}  // namespace
}  // namespace tridex::compute
