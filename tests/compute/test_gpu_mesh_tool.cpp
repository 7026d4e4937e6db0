// tests/compute/test_gpu_mesh_tool.cpp - mesh tools (ToolKind::kMesh) on the GPU (shaders/dexel_sweep.comp):
// random programs mixing ball, flat-end and mesh tools (convex and non-convex, several orientations) with
// all three operations give bit-identical rays on GPU and CPU, with the spill pool under pressure; a mesh
// tool larger than the workpiece; tools over the 128 MiB binding are refused before anything changes.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <vector>

#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/tools/mesh_tool.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

TriDexel box_model(int cells, double lo, double hi) {
    Lattice L;
    L.origin_m = Vec3(0.15, -0.35, 0.6);
    L.cell_m = 0.001;
    L.cells = {cells, cells, cells};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    if (hi > lo) scan_convert(box_mesh(Aabb{L.to_world(Vec3(lo)), L.to_world(Vec3(hi))}), m);
    return m;
}

/// Rays that differ bitwise (depths and materials).
std::size_t differing_rays(const TriDexel& a, const TriDexel& b) {
    std::size_t n = 0;
    for (int s = 0; s < 3; ++s)
        for (std::size_t i = 0; i < a.sets[s].rays.size(); ++i) {
            const auto &x = a.sets[s].rays[i], &y = b.sets[s].rays[i];
            bool same = x.size() == y.size();
            for (std::size_t k = 0; same && k < x.size(); ++k)
                same = std::memcmp(&x[k].enter, &y[k].enter, 4) == 0 && std::memcmp(&x[k].exit, &y[k].exit, 4) == 0 &&
                       x[k].enter_material == y[k].enter_material && x[k].exit_material == y[k].exit_material;
            n += !same;
        }
    return n;
}

/// Two boxes side by side along x with a gap (closed, two components): X rays through it meet two intervals.
TriMesh dumbbell(double c) {
    TriMesh m = box_mesh(Aabb{Vec3(-3.0, -1.5, -1.0) * c, Vec3(-0.6, 1.5, 2.0) * c});
    const TriMesh r = box_mesh(Aabb{Vec3(0.9, -1.0, -2.0) * c, Vec3(2.7, 1.2, 1.0) * c});
    for (auto t : r.triangles) {
        for (auto& i : t) i += static_cast<std::uint32_t>(m.positions.size());
        m.triangles.push_back(t);
    }
    m.positions.insert(m.positions.end(), r.positions.begin(), r.positions.end());
    return m;
}

/// Random strokes: ball, flat-end and three mesh tools (icosphere, box, dumbbell) in random or lattice-aligned
/// orientations, subtract / union / paint, positions sometimes on lattice nodes, some zero-length segments.
std::vector<Sweep> random_program(const Lattice& L, int segments, std::uint32_t seed) {
    const double c = L.cell_m;
    const std::shared_ptr<const MeshTool> tools[3] = {
        MeshTool::create(icosphere_mesh(Vec3(0.3, -0.2, 0.5) * c, 2.6 * c, 2)),
        MeshTool::create(box_mesh(Aabb{Vec3(-1.5, -2.0, 0.0) * c, Vec3(1.5, 2.0, 4.0) * c})),
        MeshTool::create(dumbbell(c), 2)};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(6.0, L.cells[0] - 6.0), unit(0.0, 1.0);
    const Vec3 axes[4] = {Vec3(0, 0, 1), Vec3(0.3, -0.5, 0.8), Vec3(-0.7, 0.1, -0.2), Vec3(1, 0, 0)};
    std::vector<Sweep> out;
    Vec3 p = L.to_world(Vec3(pos(rng), pos(rng), pos(rng)));
    Sweep s;
    while (static_cast<int>(out.size()) < segments) {
        if (out.empty() || unit(rng) < 0.1) {
            const double pick = unit(rng);
            s.op = pick < 0.45 ? ToolOp::kSubtract : pick < 0.8 ? ToolOp::kUnion : ToolOp::kPaint;
            s.material = static_cast<std::uint8_t>(1 + rng() % 6);
            const double kind = unit(rng);
            if (kind < 0.2) s.tool = SweepTool{ToolKind::kBall, (0.5 + 4.0 * unit(rng)) * c, 0.0};
            else if (kind < 0.35) s.tool = SweepTool{ToolKind::kFlatEnd, (0.5 + 3.0 * unit(rng)) * c, (2.0 + 5.0 * unit(rng)) * c};
            else s.tool = SweepTool{ToolKind::kMesh, 0.0, 0.0, tools[rng() % 3]};
            s.axis = axes[rng() % 4];
            p = L.to_world(Vec3(pos(rng), pos(rng), pos(rng)));
        }
        Vec3 g = L.to_grid(p) + Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5) * 3.0;
        if (unit(rng) < 0.25) g = glm::round(g);
        else if (unit(rng) < 0.25) g.y = std::round(g.y) + 0.5;
        g = glm::clamp(g, Vec3(2.0), Vec3(L.cells[0] - 2.0));
        const Vec3 q = L.to_world(g);
        s.path_m = Segment{p, unit(rng) < 0.05 ? p : q};
        out.push_back(s);
        p = q;
    }
    return out;
}

}  // namespace

TEST(GpuMeshTool, RandomProgramsMixingBallFlatEndAndMeshToolsMatchTheCpuBitForBit) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel cpu = box_model(56, 7.5, 48.5);
        TriDexel gpu_model = box_model(56, 7.5, 48.5);
        GpuSculptorOptions opt;
        opt.initial_pool_chunks = 16;  // tiny: compaction, growth and host retries
        GpuSculptor sculptor(ctx, gpu_model, opt);
        const std::vector<Sweep> program = random_program(cpu.lattice, 1500, 21u);
        std::size_t mesh_sweeps = 0;
        for (const Sweep& s : program) mesh_sweeps += s.tool.kind == ToolKind::kMesh;
        std::mt19937 rng(4);
        std::size_t done = 0, changed_cpu = 0, changed_gpu = 0;
        double cpu_s = 0.0, gpu_s = 0.0;
        while (done < program.size()) {
            const std::size_t n = std::min<std::size_t>(program.size() - done, 1 + rng() % 150);
            const std::span<const Sweep> batch(program.data() + done, n);
            const auto t0 = std::chrono::steady_clock::now();
            for (const Sweep& s : batch) changed_cpu += apply_sweep(cpu, s).rays_changed;
            const auto t1 = std::chrono::steady_clock::now();
            changed_gpu += sculptor.apply(batch).rays_changed;
            const auto t2 = std::chrono::steady_clock::now();
            cpu_s += std::chrono::duration<double>(t1 - t0).count();
            gpu_s += std::chrono::duration<double>(t2 - t1).count();
            done += n;
        }
        EXPECT_GT(mesh_sweeps, 500u);
        EXPECT_GT(changed_cpu, 10000u);
        EXPECT_EQ(differing_rays(cpu, gpu_model), 0u);
        TriDexel downloaded = TriDexel::empty(cpu.lattice, std::size_t{1} << 30);
        sculptor.slabs().download(downloaded);
        EXPECT_EQ(differing_rays(cpu, downloaded), 0u);
        EXPECT_GT(sculptor.slabs().spilled_intervals(), 0u);
        EXPECT_GT(sculptor.stats().compactions, 0u);
        EXPECT_GT(sculptor.stats().retried_rays, 0u);
        std::cout << "segments " << program.size() << " (mesh " << mesh_sweeps << "), batches " << sculptor.stats().batches
                  << ", rays retried on the host " << sculptor.stats().retried_rays << ", compactions "
                  << sculptor.stats().compactions << ", spilled intervals " << sculptor.slabs().spilled_intervals()
                  << ", rays changed cpu/gpu " << changed_cpu << "/" << changed_gpu << "; time CPU reference (1 thread, incl. the tool dexel builds, cached for the GPU) "
                  << cpu_s << " s, GPU (lavapipe) " << gpu_s << " s\n";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuMeshTool, ToolLargerThanTheWorkpieceAndZeroLengthSegmentsMatchTheCpu) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel cpu = box_model(24, 3.0, 21.0);
        TriDexel gpu_model = box_model(24, 3.0, 21.0);
        GpuSculptor sculptor(ctx, gpu_model);
        const double c = cpu.lattice.cell_m;
        const auto small = MeshTool::create(dumbbell(c));
        const auto huge = MeshTool::create(icosphere_mesh(Vec3(0.0), 40.0 * c, 3), 2);
        std::vector<Sweep> batch(3);
        batch[0].tool = SweepTool{ToolKind::kMesh, 0.0, 0.0, small};  // zero length: one stamp
        batch[0].axis = Vec3(0.2, 0.9, -0.3);
        batch[0].path_m = Segment{cpu.lattice.to_world(Vec3(12.0, 11.5, 12.3)), cpu.lattice.to_world(Vec3(12.0, 11.5, 12.3))};
        batch[1] = batch[0];
        batch[1].op = ToolOp::kPaint;
        batch[1].material = 5;
        batch[1].tool.mesh = huge;  // paints every surface point of the workpiece
        batch[1].path_m.b = cpu.lattice.to_world(Vec3(14.0, 9.0, 12.0));
        batch[2] = batch[1];
        batch[2].op = ToolOp::kSubtract;  // removes it all
        for (int step = 0; step < 3; ++step) {
            apply_sweep(cpu, batch[step]);
            sculptor.apply(std::span<const Sweep>(&batch[step], 1));
            EXPECT_EQ(differing_rays(cpu, gpu_model), 0u) << "after sweep " << step;
        }
        EXPECT_EQ(cpu.interval_count(), 0u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// A batch whose sweeps all run along one line, each taking a mesh tool through dozens of stamps, gives every ray
// tile under it more loop iterations than llvmpipe lets one SIMD group run in a shader (65,535, all loops summed;
// past it every loop stops after one pass, silently). No choice of workgroups helps when a single tile is over it:
// the kernel notices the spent budget (a probe loop cut to one pass) and lists the tile's rays, and the workgroup's
// later tiles (which it never reaches) keep no done mark; the host redoes both from the model as it was before the
// batch. With the host's workgroup planning, and with one workgroup taking every tile, the result is the CPU
// reference's, bit for bit.
TEST(GpuMeshTool, TilesOverTheDevicesLoopCapAreRedoneOnTheHost) {
    gpu::Context ctx = gpu::Context::create({});
    const bool llvmpipe = ctx.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    for (const bool one_group : {false, true}) {
        TriDexel cpu = box_model(40, 4.5, 35.5);
        TriDexel gpu_model = box_model(40, 4.5, 35.5);
        GpuSculptorOptions opt;
        if (one_group) {
            opt.workgroups = 1;
            opt.loop_budget = 0;
        }
        GpuSculptor sculptor(ctx, gpu_model, opt);
        const double c = cpu.lattice.cell_m;
        const auto bar = MeshTool::create(dumbbell(0.6 * c));
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> jitter(-1.5, 1.5);
        std::vector<Sweep> batch(400);
        for (std::size_t i = 0; i < batch.size(); ++i) {
            Sweep& s = batch[i];
            s.op = i % 3 == 2 ? ToolOp::kUnion : ToolOp::kSubtract;
            s.material = static_cast<std::uint8_t>(1 + i % 5);
            s.tool = SweepTool{ToolKind::kMesh, 0.0, 0.0, bar};
            s.axis = Vec3(jitter(rng), jitter(rng), 2.0);
            const double y = 20.0 + jitter(rng), z = 30.0 + jitter(rng);
            s.path_m = Segment{cpu.lattice.to_world(Vec3(3.0, y, z)), cpu.lattice.to_world(Vec3(37.0, y + jitter(rng), z))};
        }
        std::size_t changed_cpu = 0;
        for (const Sweep& s : batch) changed_cpu += apply_sweep(cpu, s).rays_changed;
        const std::size_t changed_gpu = sculptor.apply(batch).rays_changed;
        EXPECT_GT(changed_cpu, 500u);
        EXPECT_GT(changed_gpu, 500u);
        EXPECT_EQ(differing_rays(cpu, gpu_model), 0u) << (one_group ? "one workgroup" : "planned workgroups");
        TriDexel downloaded = TriDexel::empty(cpu.lattice, std::size_t{1} << 30);
        sculptor.slabs().download(downloaded);
        EXPECT_EQ(differing_rays(cpu, downloaded), 0u) << (one_group ? "one workgroup" : "planned workgroups");
        const GpuSculptStats& st = sculptor.stats();
        if (llvmpipe) {
            EXPECT_GT(st.loop_capped_rays, 100u);
            // One workgroup stops after the first tile over the cap: every later tile is the host's.
            if (one_group) {
                EXPECT_GT(st.loop_capped_rays, 4 * st.ray_tiles);
            }
        }
        std::cout << (one_group ? "one workgroup: " : "planned workgroups: ") << "ray tiles " << st.ray_tiles
                  << ", workgroups " << st.workgroups << ", rays retried " << st.retried_rays << ", of them loop-capped "
                  << st.loop_capped_rays << "\n";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuMeshTool, ToolsOverTheBindingLimitAreRefusedBeforeAnythingChanges) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel m = box_model(32, 4.0, 28.0);
        const std::size_t before = m.interval_count();
        GpuSculptor sculptor(ctx, m);
        // A ball of radius 20 cells at 16 tool rays per cell: ~13 MB of tool dexels per orientation;
        // twelve orientations in one batch need over 128 MiB.
        const auto big = MeshTool::create(icosphere_mesh(Vec3(0.0), 20.0 * m.lattice.cell_m, 2), 16);
        std::vector<Sweep> batch(12);
        for (std::size_t i = 0; i < batch.size(); ++i) {
            batch[i].tool = SweepTool{ToolKind::kMesh, 0.0, 0.0, big};
            batch[i].axis = Vec3(std::cos(0.4 * i), std::sin(0.4 * i), 0.5);
            batch[i].path_m = Segment{m.lattice.to_world(Vec3(16.0)), m.lattice.to_world(Vec3(16.0))};
        }
        try {
            sculptor.apply(batch);
            FAIL() << "expected a refusal";
        } catch (const Error& e) {
            const std::string msg = e.what();
            std::cout << msg << "\n";
            EXPECT_NE(msg.find("MiB"), std::string::npos) << msg;
            EXPECT_NE(msg.find("128"), std::string::npos) << msg;
        }
        EXPECT_EQ(m.interval_count(), before);
        EXPECT_EQ(sculptor.stats().batches, 0u);
        // One orientation fits and works.
        sculptor.apply(std::span<const Sweep>(batch.data(), 1));
        EXPECT_LT(m.interval_count(), before);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuMeshTool, FullOrientationTurnsTheToolWithItsRollOnGpuAndCpuAlike) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel cpu = box_model(40, 4.0, 36.0);
        TriDexel gpu_model = box_model(40, 4.0, 36.0);
        GpuSculptor sculptor(ctx, gpu_model);
        const double c = cpu.lattice.cell_m;
        // A blade: long along x, thin along z, its tip at the origin and its axis +y (core/tool_shape.hpp frame).
        const auto blade = MeshTool::create(box_mesh(Aabb{Vec3(-6.0, 0.0, -1.0) * c, Vec3(6.0, 8.0, 1.0) * c}));
        const Vec3 at = cpu.lattice.to_world(Vec3(20.3, 34.2, 20.1));  // 1.8 cells into the top face
        auto plunge = [&](const Quat& q) {
            Sweep s;
            s.tool = SweepTool{ToolKind::kMesh, 0.0, 0.0, blade};
            s.orientation = q;
            s.axis = Vec3(0.0);  // not used with an orientation
            s.path_m = Segment{at, at};
            return s;
        };
        // The same axis (+y) with a quarter-turn roll turns the blade's long side from x to z.
        const double half = 0.5 * std::acos(-1.0);
        const Sweep rolled = plunge(glm::angleAxis(half, Vec3(0.0, 1.0, 0.0)));
        TriDexel a = box_model(40, 4.0, 36.0);
        apply_sweep(a, plunge(Quat(1.0, 0.0, 0.0, 0.0)));
        TriDexel b = box_model(40, 4.0, 36.0);
        apply_sweep(b, rolled);
        auto extent_of_change = [&](const TriDexel& m, int axis) {  // Y rays (through x, z) that lost material
            const RaySet& y = m.sets[1];
            const RaySet& y0 = cpu.sets[1];
            int lo = 1 << 30, hi = -(1 << 30);
            for (int v = 0; v < y.nv; ++v)
                for (int u = 0; u < y.nu; ++u)
                    if (y.ray(u, v).size() != y0.ray(u, v).size() ||
                        (!y.ray(u, v).empty() && y.ray(u, v).back().exit != y0.ray(u, v).back().exit)) {
                        const int k = axis == 0 ? v : u;  // Y rays: u along z, v along x
                        lo = std::min(lo, k);
                        hi = std::max(hi, k);
                    }
            return hi - lo;
        };
        EXPECT_GE(extent_of_change(a, 0), 11);  // along x: 12 cells
        EXPECT_LE(extent_of_change(a, 2), 3);   // along z: 2 cells
        EXPECT_LE(extent_of_change(b, 0), 3);
        EXPECT_GE(extent_of_change(b, 2), 11);
        // Random orientations (roll included) along strokes: GPU and CPU bit-identical.
        std::mt19937 rng(9);
        std::normal_distribution<double> g;
        std::vector<Sweep> program;
        Vec3 p = cpu.lattice.to_world(Vec3(20.0, 33.0, 20.0));
        for (int i = 0; i < 60; ++i) {
            Sweep s = plunge(glm::normalize(Quat(g(rng), g(rng), g(rng), g(rng))));
            const Vec3 q = cpu.lattice.to_world(glm::clamp(cpu.lattice.to_grid(p) + Vec3(g(rng), g(rng), g(rng)) * 2.0,
                                                           Vec3(8.0), Vec3(32.0)));
            s.path_m = Segment{p, q};
            s.op = i % 5 == 4 ? ToolOp::kUnion : ToolOp::kSubtract;
            s.material = 3;
            program.push_back(s);
            p = q;
        }
        for (std::size_t i = 0; i < program.size(); i += 20) {
            const std::span<const Sweep> batch(program.data() + i, 20);
            for (const Sweep& s : batch) apply_sweep(cpu, s);
            sculptor.apply(batch);
        }
        EXPECT_EQ(differing_rays(cpu, gpu_model), 0u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}
