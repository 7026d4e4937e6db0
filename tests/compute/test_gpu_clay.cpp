// tests/compute/test_gpu_clay.cpp - the clay tools in Vulkan compute (compute/gpu/gpu_clay.hpp) against the CPU
// reference: the node field (phi, s0, s1) bit for bit, and push, pull and smooth on a flat face, a sphere and random
// strokes (long motions in pieces, tools at the lattice's boundary) giving the same rays, ClayStats and `before`
// images bit for bit, in the mirror and in the slabs; rays over the kernel's interval limit redone on the host;
// validation silent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <span>
#include <vector>

#include "clay_test_models.hpp"
#include "compute/gpu/gpu_clay.hpp"
#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/tools/clay_push.hpp"
#include "compute/tools/clay_resample.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"

namespace tridex::compute {
namespace {

using clay_test::clay_sweep;
using clay_test::cube_lattice;
using clay_test::from_implicit;
using clay_test::sphere_model;
using clay_test::same_bits;

void expect_same_ray(const std::vector<Interval>& x, const std::vector<Interval>& y, const char* what, int set,
                     std::size_t index) {
    ASSERT_EQ(x.size(), y.size()) << what << " set " << set << " ray " << index;
    for (std::size_t k = 0; k < x.size(); ++k) {
        ASSERT_TRUE(same_bits(x[k].enter, y[k].enter)) << what << " set " << set << " ray " << index << " enter " << k;
        ASSERT_TRUE(same_bits(x[k].exit, y[k].exit)) << what << " set " << set << " ray " << index << " exit " << k;
        ASSERT_EQ(x[k].enter_material, y[k].enter_material) << what;
        ASSERT_EQ(x[k].exit_material, y[k].exit_material) << what;
    }
}

void expect_same_model(const TriDexel& a, const TriDexel& b, const char* what) {
    for (int s = 0; s < 3; ++s)
        for (std::size_t r = 0; r < a.sets[s].rays.size(); ++r) {
            expect_same_ray(a.sets[s].rays[r], b.sets[s].rays[r], what, s, r);
            if (testing::Test::HasFatalFailure()) return;
        }
}

/// The CPU reference model and the same model on the GPU (sculptor and clay kernel), applied sweep by sweep and
/// compared after every sweep (stats, `before` images) and at the end (mirror and slabs).
struct Pair {
    gpu::Context& ctx;
    TriDexel cpu;
    TriDexel gpu_model;
    GpuSculptor sculptor;
    GpuClay clay;
    std::size_t changed = 0;

    Pair(gpu::Context& c, const TriDexel& start, const GpuSculptorOptions& so = {}, const GpuClayOptions& co = {})
        : ctx(c), cpu(start), gpu_model(start), sculptor(c, gpu_model, so), clay(c, sculptor, co) {}

    void apply(const Sweep& s, std::size_t step) {
        std::vector<RayImage> bc, bg;
        const ClayStats sc = apply_clay(cpu, s, &bc);
        const ClayStats sg = apply_clay(gpu_model, s, &bg, clay);
        ASSERT_EQ(sc.rays.rays_visited, sg.rays.rays_visited) << "step " << step;
        ASSERT_EQ(sc.rays.rays_changed, sg.rays.rays_changed) << "step " << step;
        ASSERT_EQ(sc.beta, sg.beta) << "step " << step;
        ASSERT_EQ(sc.volume_change_cells, sg.volume_change_cells) << "step " << step;
        ASSERT_EQ(sc.max_displacement_cells, sg.max_displacement_cells) << "step " << step;
        ASSERT_EQ(bc.size(), bg.size()) << "step " << step;
        for (std::size_t i = 0; i < bc.size(); ++i) {
            ASSERT_EQ(bc[i].axis, bg[i].axis);
            ASSERT_EQ(bc[i].index, bg[i].index);
            expect_same_ray(bc[i].intervals, bg[i].intervals, "before image", bc[i].axis, bc[i].index);
            if (testing::Test::HasFatalFailure()) return;
        }
        changed += sc.rays.rays_changed;
    }

    /// A batch through apply_clay_batch on both (grouped pushes), compared as apply does.
    void apply_batch(std::span<const Sweep> batch, std::size_t step) {
        std::vector<RayImage> bc, bg;
        const BooleanStats sc = apply_clay_batch(cpu, batch, &bc);
        const BooleanStats sg = apply_clay_batch(gpu_model, batch, &bg, clay);
        ASSERT_EQ(sc.rays_visited, sg.rays_visited) << "batch " << step;
        ASSERT_EQ(sc.rays_changed, sg.rays_changed) << "batch " << step;
        ASSERT_EQ(bc.size(), bg.size()) << "batch " << step;
        for (std::size_t i = 0; i < bc.size(); ++i) {
            ASSERT_EQ(bc[i].axis, bg[i].axis);
            ASSERT_EQ(bc[i].index, bg[i].index);
            expect_same_ray(bc[i].intervals, bg[i].intervals, "before image", bc[i].axis, bc[i].index);
            if (testing::Test::HasFatalFailure()) return;
        }
        changed += sc.rays_changed;
    }

    void expect_equal() {
        expect_same_model(cpu, gpu_model, "mirror");
        TriDexel down = TriDexel::empty(cpu.lattice, std::size_t{1} << 30);
        sculptor.slabs().download(down);
        expect_same_model(cpu, down, "slabs");
        EXPECT_EQ(ctx.validation_messages(), 0u);
    }
};

TEST(GpuClay, NodeFieldEqualsTheCpuReferenceBitForBit) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel m = sphere_model(40, 20.2, 19.7, 20.4, 12.0);
        GpuSculptor sculptor(ctx, m);
        GpuClay clay(ctx, sculptor);
        const float R = 3.0f;
        const ClayContact ct = clay_contact(m, 20.3f, 19.9f, 20.4f + 12.0f + R - 0.8f, R);
        ASSERT_GT(ct.delta, 0.5f);
        // A push field: two stamps, box and region as a push builds them.
        const ClayStamp stamps[2] = {{{ct.point[0], ct.point[1], ct.point[2]}, {ct.normal[0], ct.normal[1], ct.normal[2]}, 0.8f},
                                     {{ct.point[0] + 0.5f, ct.point[1], ct.point[2]}, {ct.normal[0], ct.normal[1], ct.normal[2]}, 2.6f}};  // over the rim cap
        ClayStampParams p;
        p.r = kClayInfluence * R;
        p.w = kClayRimWidth * p.r;
        p.reach2 = (p.r + p.w) * (p.r + p.w) * 1.0001f;
        ClayField fc, fg;
        const float lo[3] = {ct.point[0], ct.point[1], ct.point[2]};
        const float hi[3] = {ct.point[0] + 0.5f, ct.point[1], ct.point[2]};
        fc.box = clay_support_box(lo, hi, p.r + p.w, clay_whole_box(m.lattice));
        for (int a = 0; a < 3; ++a) fc.region.c[a] = lo[a], fc.region.c1[a] = hi[a];  // a capsule over the stamps
        fc.region.r = p.r + p.w + 2.0f;
        fg = fc;
        clay_cpu_kernel().stamp_field(m, fc, stamps, p);
        clay.stamp_field(m, fg, stamps, p);
        ASSERT_EQ(fc.phi.size(), fg.phi.size());
        std::size_t moved = 0, region = 0;
        for (std::size_t i = 0; i < fc.phi.size(); ++i) {
            ASSERT_TRUE(same_bits(fc.phi[i], fg.phi[i])) << "phi at " << i << ": " << fc.phi[i] << " vs " << fg.phi[i];
            ASSERT_TRUE(same_bits(fc.s0[i], fg.s0[i])) << "s0 at " << i;
            ASSERT_TRUE(same_bits(fc.s1[i], fg.s1[i])) << "s1 at " << i;
            moved += fc.s0[i] != 0.0f || fc.s1[i] != 0.0f;
            region += !std::isnan(fc.phi[i]);
        }
        EXPECT_GT(moved, 50u);
        EXPECT_LT(region, fc.phi.size());  // the box holds nodes off the region (NaN on both)
        for (int a = 0; a < 3; ++a) EXPECT_EQ(fc.chords[a], fg.chords[a]);
        // The push field's moved rays re-sampled at several beta, with and without the fixed rays: the GPU's rays,
        // change flags and length changes equal the CPU reference's bit for bit.
        std::vector<ClayMovedNode> nodes;
        clay_moved_nodes(fc, nodes);
        std::vector<ClayMovedRay> rays;
        clay_moved_rays(m, fc, nodes, rays);
        ASSERT_GT(rays.size(), 50u);
        for (const float beta : {-1.3f, 0.0f, 0.41f, 2.7f})
            for (const bool with_fixed : {true, false}) {
                ClayResampled c[2], g[2];
                for (ClayResampled* r : {&c[0], &c[1], &g[0], &g[1]}) {
                    r->rays.resize(rays.size());
                    r->changed.assign(rays.size(), 0);
                    r->dlen.assign(rays.size(), 0.0);
                }
                clay_resample_on_cpu(m, fc, rays, beta, with_fixed ? &c[0] : nullptr, c[1]);
                clay.resample_rays(m, fg, rays, beta, with_fixed ? &g[0] : nullptr, g[1]);
                for (int k = 0; k < 2; ++k)
                    for (std::size_t i = 0; i < rays.size(); ++i) {
                        ASSERT_EQ(c[k].changed[i], g[k].changed[i]) << "beta " << beta << " ray " << i;
                        ASSERT_EQ(c[k].dlen[i], g[k].dlen[i]) << "beta " << beta << " ray " << i;
                        expect_same_ray(c[k].rays[i], g[k].rays[i], "re-sampled", rays[i].set, rays[i].index);
                        if (testing::Test::HasFatalFailure()) return;
                    }
            }
        // A smooth field at the same contact.
        ClaySmoothParams sp;
        for (int a = 0; a < 3; ++a) sp.point[a] = ct.point[a], sp.normal[a] = ct.normal[a];
        sp.r = kClayInfluence * R;
        ClayField gc = fc, gg = fc;
        clay_cpu_kernel().smooth_field(m, gc, std::span<const ClaySmoothParams>(&sp, 1));
        clay.smooth_field(m, gg, std::span<const ClaySmoothParams>(&sp, 1));
        moved = 0;
        for (std::size_t i = 0; i < gc.phi.size(); ++i) {
            ASSERT_TRUE(same_bits(gc.phi[i], gg.phi[i])) << "phi at " << i;
            ASSERT_TRUE(same_bits(gc.s0[i], gg.s0[i])) << "smooth s0 at " << i << ": " << gc.s0[i] << " vs " << gg.s0[i];
            ASSERT_TRUE(same_bits(gc.s1[i], gg.s1[i])) << "smooth s1 at " << i;
            moved += gc.s1[i] != 0.0f;
        }
        EXPECT_GT(moved, 50u);
        // Three acts in a row (an odd and an even number of steps through s0's two halves): each steps the field
        // the acts before it left, so the second differs from one act's result.
        std::vector<ClaySmoothParams> acts(3, sp);
        acts[1].point[0] += 0.3f;
        acts[2].point[1] -= 0.3f;
        for (const std::size_t n : {std::size_t{2}, std::size_t{3}}) {
            ClayField hc = fc, hg = fc;
            clay_cpu_kernel().smooth_field(m, hc, std::span<const ClaySmoothParams>(acts).first(n));
            clay.smooth_field(m, hg, std::span<const ClaySmoothParams>(acts).first(n));
            std::size_t differ = 0;
            for (std::size_t i = 0; i < hc.phi.size(); ++i) {
                ASSERT_TRUE(same_bits(hc.s0[i], hg.s0[i])) << n << " acts: s0 at " << i << ": " << hc.s0[i] << " vs " << hg.s0[i];
                ASSERT_TRUE(same_bits(hc.s1[i], hg.s1[i])) << n << " acts: s1 at " << i;
                differ += !same_bits(hc.s0[i], gc.s0[i]);
            }
            EXPECT_GT(differ, 50u) << n << " acts";
        }
        EXPECT_EQ(clay.stats().fields, 4u);
        EXPECT_EQ(clay.stats().host_fields, 0u);
        // Another model than the sculptor's mirror is refused.
        TriDexel other = m;
        ClayField fo = fc;
        EXPECT_THROW(clay.stamp_field(other, fo, stamps, p), Error);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuClay, PushPullAndSmoothOnAFlatFaceMatchTheCpu) {
    gpu::Context ctx = gpu::Context::create({});
    {
        const double z0 = 20.3;
        const TriDexel start = from_implicit(cube_lattice(40), [z0](double x, double y, double z) {
            return std::max({4.4 - x, x - 35.6, 4.4 - y, y - 35.6, 4.4 - z, z - z0});
        });
        Pair p(ctx, start);
        const double R = 3.0;
        std::size_t step = 0;
        // Press in, stroke across, pull back out, smooth over it.
        Vec3 a(20.2, 20.3, z0 + R - 0.9);
        p.apply(clay_sweep(ToolOp::kPush, a, a, R), step++);
        for (int k = 0; k < 12 && !testing::Test::HasFatalFailure(); ++k) {
            const Vec3 b = a + Vec3(0.7, 0.15, -0.05);
            p.apply(clay_sweep(ToolOp::kPush, a, b, R), step++);
            a = b;
        }
        for (int k = 0; k < 8 && !testing::Test::HasFatalFailure(); ++k) {
            const Vec3 b = a + Vec3(-0.3, 0.0, 0.4);
            p.apply(clay_sweep(ToolOp::kPull, a, b, R), step++);
            a = b;
        }
        a = Vec3(14.1, 18.0, z0 + R - 0.2);
        for (int k = 0; k < 30 && !testing::Test::HasFatalFailure(); ++k) {
            const Vec3 b = a + Vec3(0.45, 0.1, 0.0);
            p.apply(clay_sweep(ToolOp::kSmooth, a, b, R), step++);
            a = b;
        }
        EXPECT_GT(p.changed, 500u);
        p.expect_equal();
        EXPECT_GT(p.clay.stats().fields, 20u);
        EXPECT_GT(p.clay.stats().rays_resampled, 500u);
        EXPECT_EQ(p.clay.stats().host_fields, 0u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

/// A random stroke: a ball of radius R wandering over a sphere's surface (penetration -0.5..1.5 cells), steps of
/// 0.2..1.5 cells with a jump of 4..7 cells now and then (applied in kClayPieceCells pieces), each segment push, pull
/// or smooth at random.
std::vector<Sweep> random_sphere_stroke(const double c[3], double rho, double R, int segments, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    double th = 0.3, ph = 0.5;  // polar and azimuthal angle of the tool on the sphere
    auto at = [&](double pen) {
        const double rr = rho + R - pen;
        return Vec3(c[0] + rr * std::sin(th) * std::cos(ph), c[1] + rr * std::sin(th) * std::sin(ph), c[2] + rr * std::cos(th));
    };
    std::vector<Sweep> out;
    double pen = 0.5;
    Vec3 a = at(pen);
    for (int k = 0; k < segments; ++k) {
        const double step = (k % 23 == 22) ? 4.0 + 3.0 * U(rng) : 0.2 + 1.3 * U(rng);
        const double dir = 2.0 * M_PI * U(rng);
        th = std::clamp(th + step / rho * std::cos(dir), 0.1, 2.0);
        ph += step / rho * std::sin(dir);
        pen = std::clamp(pen + 0.6 * (U(rng) - 0.5), -0.5, 1.5);
        const Vec3 b = at(pen);
        const double r = U(rng);
        const ToolOp op = r < 0.45 ? ToolOp::kPush : r < 0.7 ? ToolOp::kPull : ToolOp::kSmooth;
        out.push_back(clay_sweep(op, a, b, R));
        a = b;
    }
    return out;
}

TEST(GpuClay, RandomStrokesOnASphereMatchTheCpuBitForBit) {
    gpu::Context ctx = gpu::Context::create({});
    {
        const double c[3] = {24.3, 23.8, 24.1}, rho = 14.0;
        Pair p(ctx, sphere_model(48, c[0], c[1], c[2], rho));
        const std::vector<Sweep> stroke = random_sphere_stroke(c, rho, 3.0, 320, 7u);
        for (std::size_t k = 0; k < stroke.size() && !testing::Test::HasFatalFailure(); ++k) p.apply(stroke[k], k);
        EXPECT_GT(p.changed, 3000u);
        p.expect_equal();
        std::cout << "fields " << p.clay.stats().fields << ", field nodes " << p.clay.stats().field_nodes
                  << ", resamplings " << p.clay.stats().resamplings << ", rays re-sampled on the GPU "
                  << p.clay.stats().rays_resampled << ", on the host " << p.clay.stats().rays_on_host << "\n";
        EXPECT_GT(p.clay.stats().fields, 100u);  // a pull that lost its grip, or a smooth within a half cell, does not act
        EXPECT_GE(p.clay.stats().resamplings, p.clay.stats().fields);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuClay, GroupedPushBatchesOnASphereMatchTheCpuBitForBit) {
    gpu::Context ctx = gpu::Context::create({});
    {
        const double c[3] = {24.3, 23.8, 24.1}, rho = 14.0;
        Pair p(ctx, sphere_model(48, c[0], c[1], c[2], rho));
        std::vector<Sweep> stroke = random_sphere_stroke(c, rho, 3.0, 120, 11u);
        for (Sweep& s : stroke) s.op = ToolOp::kPush;
        const std::size_t fields0 = p.clay.stats().fields;
        for (std::size_t k = 0; k < stroke.size() && !testing::Test::HasFatalFailure(); k += 8)
            p.apply_batch(std::span<const Sweep>(stroke).subspan(k, std::min<std::size_t>(8, stroke.size() - k)), k);
        EXPECT_GT(p.changed, 1000u);
        p.expect_equal();
        // Grouped: fewer fields than sweeps.
        EXPECT_LT(p.clay.stats().fields - fields0, stroke.size() / 2);
        EXPECT_GT(p.clay.stats().fields - fields0, 5u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuClay, ClayWritesThatFillTheSpillPoolCompactItAndMatchTheCpu) {
    gpu::Context ctx = gpu::Context::create({});
    {
        // A block with a slot down its middle: every X ray through the slotted part holds two intervals, all inline.
        // A push groove along Y beside the slot splits the X rays just under the face into three, each then needing a
        // pool chunk; the pool starts exactly as large as the model needs, so it fills, compacts and grows.
        const TriDexel start = from_implicit(cube_lattice(40), [](double x, double y, double z) {
            const double block = std::max({4.4 - x, x - 35.6, 4.4 - y, y - 35.6, 6.2 - z, z - 26.3});
            const double slot = std::max({19.2 - x, x - 20.8, 12.1 - z});
            return std::max(block, -slot);
        });
        GpuSculptorOptions so;
        so.initial_pool_chunks = 16;
        Pair p(ctx, start, so);
        const double R = 3.0, z0 = 26.3;
        Vec3 a(11.7, 8.3, z0 + R - 0.9);
        std::vector<Sweep> stroke;
        for (int k = 0; k < 24; ++k) {
            const Vec3 b = a + Vec3(0.02, 0.8, 0.0);
            stroke.push_back(clay_sweep(ToolOp::kPush, a, b, R));
            a = b;
        }
        for (std::size_t k = 0; k < 12 && !testing::Test::HasFatalFailure(); ++k) p.apply(stroke[k], k);
        p.apply_batch(std::span<const Sweep>(stroke).subspan(12), 12);
        a = Vec3(12.1, 10.0, z0 + R - 0.2);
        for (int k = 0; k < 12 && !testing::Test::HasFatalFailure(); ++k) {
            const Vec3 b = a + Vec3(0.0, 0.45, 0.0);
            p.apply(clay_sweep(ToolOp::kSmooth, a, b, R), 100 + k);
            a = b;
        }
        p.expect_equal();
        std::cout << "rays changed " << p.changed << ", compactions " << p.sculptor.stats().compactions
                  << ", spilled intervals " << p.sculptor.slabs().spilled_intervals() << "\n";
        EXPECT_GT(p.changed, 300u);
        EXPECT_GT(p.sculptor.stats().compactions, 0u);
        EXPECT_GT(p.sculptor.slabs().spilled_intervals(), 0u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuClay, StrokesAtTheLatticeBoundaryMatchTheCpu) {
    gpu::Context ctx = gpu::Context::create({});
    {
        // A slab filling the lattice in x and y (its sides on the lattice's boundary), the tool running along x = 1.
        const double z0 = 12.4;
        Pair p(ctx, from_implicit(cube_lattice(32), [z0](double, double, double z) { return std::max(2.3 - z, z - z0); }));
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        const double R = 2.5;
        Vec3 a(1.2, 0.8, z0 + R - 0.7);
        for (int k = 0; k < 200 && !testing::Test::HasFatalFailure(); ++k) {
            Vec3 b = a + Vec3(0.3 * (U(rng) - 0.3), 0.9 * U(rng), 0.3 * (U(rng) - 0.5));
            if (b.y > 31.0) b.y = 0.5;  // back to the other edge: a long motion, in pieces
            b.x = std::clamp(b.x, -0.5, 3.0);
            b.z = std::clamp(b.z, z0 + R - 1.4, z0 + R + 0.4);
            const ToolOp op = k % 5 == 4 ? ToolOp::kSmooth : k % 5 == 3 ? ToolOp::kPull : ToolOp::kPush;
            p.apply(clay_sweep(op, a, b, R), static_cast<std::size_t>(k));
            a = b;
        }
        EXPECT_GT(p.changed, 1000u);
        p.expect_equal();
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuClay, RaysOverTheKernelsLimitAreRedoneOnTheHost) {
    gpu::Context ctx = gpu::Context::create({});
    {
        // Two plates: every Z ray through them holds two intervals; the kernel may write one per ray here.
        const double z0 = 20.3;
        const TriDexel start = from_implicit(cube_lattice(32), [z0](double x, double y, double z) {
            const double plates = std::min(std::max(4.3 - z, z - 9.6), std::max(13.2 - z, z - z0));
            return std::max({3.4 - x, x - 28.6, 3.4 - y, y - 28.6, plates});
        });
        GpuClayOptions co;
        co.max_kernel_intervals = 1;
        Pair p(ctx, start, {}, co);
        const double R = 2.5;
        Vec3 a(12.2, 15.1, z0 + R - 0.8);
        for (int k = 0; k < 40 && !testing::Test::HasFatalFailure(); ++k) {
            const Vec3 b = a + Vec3(0.35, 0.05, k < 20 ? -0.02 : 0.03);
            p.apply(clay_sweep(k < 20 ? ToolOp::kPush : k < 30 ? ToolOp::kSmooth : ToolOp::kPull, a, b, R),
                    static_cast<std::size_t>(k));
            a = b;
        }
        EXPECT_GT(p.changed, 200u);
        p.expect_equal();
        EXPECT_GT(p.clay.stats().rays_on_host, 0u);
        EXPECT_GT(p.clay.stats().rays_resampled, p.clay.stats().rays_on_host);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
    EXPECT_THROW(
        {
            gpu::Context c2 = gpu::Context::create({});
            TriDexel m = sphere_model(16, 8.0, 8.0, 8.0, 5.0);
            GpuSculptor s(c2, m);
            GpuClayOptions bad;
            bad.max_kernel_intervals = 0;
            GpuClay clay(c2, s, bad);
        },
        Error);
}

TEST(GpuClay, BoxesOverTheGpuLimitRunOnTheCpuReferenceWithTheSameResult) {
    gpu::Context ctx = gpu::Context::create({});
    {
        const double c[3] = {16.2, 15.9, 16.1}, rho = 9.0;
        GpuClayOptions co;
        co.max_field_nodes = 4000;  // a 3-cell ball's push box holds more; its smooth box about as many
        Pair p(ctx, sphere_model(32, c[0], c[1], c[2], rho), {}, co);
        const std::vector<Sweep> stroke = random_sphere_stroke(c, rho, 3.0, 60, 11u);
        for (std::size_t k = 0; k < stroke.size() && !testing::Test::HasFatalFailure(); ++k) p.apply(stroke[k], k);
        EXPECT_GT(p.changed, 300u);
        p.expect_equal();
        EXPECT_GT(p.clay.stats().host_fields, 0u);
        EXPECT_GT(p.clay.stats().fields, 0u);  // the smaller boxes still ran on the GPU
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::compute
