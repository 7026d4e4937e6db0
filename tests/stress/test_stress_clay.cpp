// Stress: 10,000 random push and smooth segments (and a few subtracts) on a sphere at 64 cells. Every 1,000 segments
// the invariants hold on every ray (finite, sorted, disjoint, not touching), the contoured mesh is closed, and at the
// end the three sets' disagreement and the volume drift are printed and bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "core/primitives.hpp"
#include "stress_common.hpp"

namespace tridex::compute {
namespace {

TEST(StressClay, TenThousandRandomSegmentsKeepTheModelSound) {
    Lattice L;
    L.origin_m = Vec3(0.3, -0.2, 0.7);
    L.cell_m = 1e-3;
    L.cells = {64, 64, 64};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 31);
    const Vec3 c = L.to_world(Vec3(32.3, 31.8, 32.1));
    scan_convert(icosphere_mesh(c, 0.022, 4), m);
    Contourer contourer(m);  // updated every 1,000 segments: only the tiles the segments marked dirty are redone
    contourer.update(m);
    const double v0 = dexel_volume_m3(m);
    const std::size_t dis0 = clay_set_disagreement(m, clay_whole_box(L));
    std::uint64_t state = 0x9E3779B97F4A7C15ull;
    auto uniform = [&state] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
    };
    // The tool walks over the sphere: a random direction, the centre at the surface +- a cell, 0.05..0.6 cell steps.
    Vec3 dir(0.0, 0.0, 1.0);
    double removed = 0.0;
    std::size_t changed = 0;
    for (int i = 0; i < 10000; ++i) {
        if (i % 400 == 0) dir = glm::normalize(Vec3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5));
        const double R = (2.0 + 2.0 * uniform()) * L.cell_m;
        const Vec3 side = glm::normalize(glm::cross(dir, Vec3(0.3, 0.5, 0.8)));
        const Vec3 a = c + dir * (0.022 + R - 0.5e-3);
        const Vec3 b = a + side * ((0.05 + 0.55 * uniform()) * L.cell_m) + dir * ((uniform() - 0.6) * L.cell_m);
        Sweep s;
        const double pick = uniform();
        s.op = pick < 0.6 ? ToolOp::kPush : pick < 0.98 ? ToolOp::kSmooth : ToolOp::kSubtract;
        s.tool.kind = ToolKind::kBall;
        s.tool.radius_m = R;
        s.path_m = Segment{a, b};
        dir = glm::normalize(b - c);
        if (is_clay_op(s.op)) {
            changed += apply_clay(m, s).rays.rays_changed;
        } else {
            const double before = dexel_volume_m3(m);
            changed += apply_sweep(m, s).rays_changed;
            removed += before - dexel_volume_m3(m);
        }
        if ((i + 1) % 1000 == 0) {
            for (const RaySet& set : m.sets)
                for (const auto& ray : set.rays) {
                    const std::string why = test::ray_violation(ray);
                    ASSERT_TRUE(why.empty()) << "after " << i + 1 << " segments: " << why;
                }
            contourer.update(m);
            const EdgeStats e = edge_stats(contourer.mesh());
            ASSERT_EQ(e.boundary_edges, 0u) << "after " << i + 1 << " segments";
            ASSERT_EQ(e.nonmanifold_edges, 0u) << "after " << i + 1 << " segments";
        }
    }
    const double v1 = dexel_volume_m3(m);
    const std::size_t dis1 = clay_set_disagreement(m, clay_whole_box(L));
    const double drift = (v1 + removed - v0) / v0;
    std::printf(
        "10,000 clay segments: %zu ray changes, volume drift (subtracts excluded) %.4f%%, set disagreement %zu -> "
        "%zu nodes of %d^3\n",
        changed, 100.0 * drift, dis0, dis1, L.cells[0]);
    EXPECT_GT(changed, 1000u);
    EXPECT_LT(std::fabs(drift), 0.02);
    EXPECT_LE(dis1, dis0 + 200);
}

}  // namespace
}  // namespace tridex::compute
