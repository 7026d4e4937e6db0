// tests/compute/test_gpu_clay_grab.cpp - the grab (move) in Vulkan compute (compute/gpu/gpu_clay.hpp, MODE 4 of
// shaders/clay_field.comp) against the CPU reference: the node field (phi, s0, s1) bit for bit, and grab strokes (a
// whole sphere carried, a cap drawn out, one long sweep in steps) giving the same rays, ClayStats and `before` images
// bit for bit, in the mirror and in the slabs; validation silent.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "clay_test_models.hpp"
#include "compute/gpu/gpu_clay.hpp"
#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/tools/clay_grab.hpp"
#include "compute/tools/clay_push.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "gpu/context.hpp"

namespace tridex::compute {
namespace {

using clay_test::clay_sweep;
using clay_test::cube_lattice;
using clay_test::from_implicit;
using clay_test::sphere_model;
using clay_test::same_bits;

/// True when the two rays hold the same intervals, bit for bit.
bool same_ray(const std::vector<Interval>& x, const std::vector<Interval>& y) {
    if (x.size() != y.size()) return false;
    for (std::size_t k = 0; k < x.size(); ++k)
        if (!same_bits(x[k].enter, y[k].enter) || !same_bits(x[k].exit, y[k].exit) ||
            x[k].enter_material != y[k].enter_material || x[k].exit_material != y[k].exit_material)
            return false;
    return true;
}

/// Number of rays that differ between the two models (one lattice).
std::size_t rays_differing(const TriDexel& a, const TriDexel& b) {
    std::size_t n = 0;
    for (int s = 0; s < 3; ++s)
        for (std::size_t r = 0; r < a.sets[s].rays.size(); ++r) n += !same_ray(a.sets[s].rays[r], b.sets[s].rays[r]);
    return n;
}

TEST(GpuClayGrab, GrabFieldEqualsTheCpuReferenceBitForBit) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel m = sphere_model(48, 24.2, 23.7, 20.4, 9.0);
        GpuSculptor sculptor(ctx, m);
        GpuClay clay(ctx, sculptor);
        const float R = 3.0f;
        const ClayContact ct = clay_contact(m, 24.3f, 23.9f, 20.4f + 9.0f + R - 0.2f, R);
        ClayGrabParams p;
        for (int a = 0; a < 3; ++a) p.anchor[a] = ct.point[a];
        p.v[0] = 0.7f, p.v[1] = -0.45f, p.v[2] = 1.3f;
        p.core = kClayGrabCore * R;
        p.r = kClayGrabInfluence * R;
        ClayField fc;
        const float reach = p.r + 2.0f + 2.0f;
        fc.box = clay_support_box(p.anchor, p.anchor, reach, clay_whole_box(m.lattice));
        fc.region.ball(p.anchor, reach + 0.01f);
        ClayField fg = fc;
        clay_cpu_kernel().grab_field(m, fc, p);
        clay.grab_field(m, fg, p);
        ASSERT_EQ(fc.phi.size(), fg.phi.size());
        std::size_t moved = 0, weighted = 0;
        for (std::size_t i = 0; i < fc.phi.size(); ++i) {
            ASSERT_TRUE(same_bits(fc.phi[i], fg.phi[i])) << "phi at " << i;
            ASSERT_TRUE(same_bits(fc.s0[i], fg.s0[i])) << "s0 at " << i << ": " << fc.s0[i] << " vs " << fg.s0[i];
            ASSERT_TRUE(same_bits(fc.s1[i], fg.s1[i])) << "s1 at " << i;
            moved += fc.s0[i] != 0.0f;
            weighted += fc.s1[i] != 0.0f;
        }
        EXPECT_GT(moved, 200u);
        EXPECT_GT(weighted, 200u);
        EXPECT_EQ(clay.stats().fields, 1u);
        EXPECT_EQ(clay.stats().host_fields, 0u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuClayGrab, GrabStrokesMatchTheCpuBitForBit) {
    gpu::Context ctx = gpu::Context::create({});
    {
        // A large sphere with a small one beside it: carry the small one, then draw a cap out of the large one, then
        // one long sweep (in steps).
        const auto f = [](double x, double y, double z) {
            const double big = glm::length(Vec3(x, y, z) - Vec3(30.0, 24.0, 18.0)) - 10.0;
            const double small = glm::length(Vec3(x, y, z) - Vec3(10.3, 24.2, 30.4)) - 3.0;
            return std::min(big, small);
        };
        const TriDexel start = from_implicit(cube_lattice(48), f);
        TriDexel cpu = start, gpu_model = start;
        GpuSculptor sculptor(ctx, gpu_model);
        GpuClay clay(ctx, sculptor);
        std::size_t step = 0, changed = 0;
        const auto apply = [&](const Vec3& a, const Vec3& b, double R) {
            std::vector<RayImage> bc, bg;
            const ClayStats sc = apply_clay(cpu, clay_sweep(ToolOp::kGrab, a, b, R), &bc);
            const ClayStats sg = apply_clay(gpu_model, clay_sweep(ToolOp::kGrab, a, b, R), &bg, clay);
            ASSERT_EQ(sc.rays.rays_changed, sg.rays.rays_changed) << "step " << step;
            ASSERT_EQ(sc.beta, sg.beta) << "step " << step;
            ASSERT_EQ(sc.volume_change_cells, sg.volume_change_cells) << "step " << step;
            ASSERT_EQ(sc.max_displacement_cells, sg.max_displacement_cells) << "step " << step;
            ASSERT_EQ(bc.size(), bg.size()) << "step " << step;
            for (std::size_t i = 0; i < bc.size(); ++i) {
                ASSERT_EQ(bc[i].axis, bg[i].axis);
                ASSERT_EQ(bc[i].index, bg[i].index);
                ASSERT_TRUE(same_ray(bc[i].intervals, bg[i].intervals)) << "before image " << i << " step " << step;
            }
            changed += sc.rays.rays_changed;
            ++step;
        };
        Vec3 a(10.3, 24.2, 30.4 + 3.0 + 3.0);
        for (int k = 0; k < 10 && !testing::Test::HasFatalFailure(); ++k) {
            const Vec3 b = a + Vec3(0.4, 0.05, 0.3);
            apply(a, b, 3.0);
            a = b;
        }
        a = Vec3(30.2, 24.1, 18.0 + 10.0 + 2.5);
        for (int k = 0; k < 6 && !testing::Test::HasFatalFailure(); ++k) {
            const Vec3 b = a + Vec3(0.1, 0.0, 0.6);
            apply(a, b, 2.5);
            a = b;
        }
        if (!testing::Test::HasFatalFailure()) apply(a, a + Vec3(-3.0, 1.5, 2.5), 2.5);
        EXPECT_GT(changed, 500u);
        EXPECT_EQ(rays_differing(cpu, gpu_model), 0u);
        TriDexel down = TriDexel::empty(cpu.lattice, std::size_t{1} << 30);
        sculptor.slabs().download(down);
        EXPECT_EQ(rays_differing(cpu, down), 0u);
        EXPECT_GT(rays_differing(cpu, start), 500u);
        EXPECT_GT(clay.stats().fields, 16u);
        EXPECT_EQ(clay.stats().host_fields, 0u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::compute
