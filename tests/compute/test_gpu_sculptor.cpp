// tests/compute/test_gpu_sculptor.cpp - GPU Booleans (shaders/dexel_sweep.comp) against the CPU reference:
// random stroke programs with every tool and operation give bit-identical rays; the spill pool compacts
// and grows; rays beyond the kernel's 16 intervals are redone on the host; validation stays silent.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "compute/gpu/gpu_sculptor.hpp"
#include "sweep_programs.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"

using namespace tridex;
using namespace tridex::compute;

using namespace tridex::compute::test;

TEST(GpuSculptor, RandomProgramsOfEveryToolAndOperationMatchTheCpuReferenceBitForBit) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel cpu = box_model(64, 8.5, 55.5);
        TriDexel gpu_model = box_model(64, 8.5, 55.5);
        GpuSculptorOptions opt;
        opt.initial_pool_chunks = 16;  // tiny: forces compaction and growth
        opt.fence_wait = gpu::FenceWait::kPoll;  // the other tests wait with kBlock
        GpuSculptor sculptor(ctx, gpu_model, opt);
        const std::vector<Sweep> program = random_program(cpu.lattice, 3000, 7u);
        std::mt19937 rng(11);
        std::size_t done = 0, changed_cpu = 0, changed_gpu = 0;
        while (done < program.size()) {
            const std::size_t n = std::min<std::size_t>(program.size() - done, 1 + rng() % 200);
            const std::span<const Sweep> batch(program.data() + done, n);
            for (const Sweep& s : batch) changed_cpu += apply_sweep(cpu, s).rays_changed;
            changed_gpu += sculptor.apply(batch).rays_changed;
            done += n;
        }
        EXPECT_GT(changed_cpu, 10000u);
        const Diff mirror = compare(cpu, gpu_model);
        TriDexel downloaded = TriDexel::empty(cpu.lattice, std::size_t{1} << 30);
        sculptor.slabs().download(downloaded);
        const Diff gpu_side = compare(cpu, downloaded);
        EXPECT_EQ(mirror.rays, 0u) << "max depth difference " << mirror.max_cells << " cells";
        EXPECT_EQ(gpu_side.rays, 0u) << "max depth difference " << gpu_side.max_cells << " cells";
        EXPECT_GT(sculptor.slabs().spilled_intervals(), 0u);
        EXPECT_GT(sculptor.stats().compactions, 0u);
        EXPECT_GT(sculptor.stats().retried_rays, 0u);
        EXPECT_EQ(sculptor.stats().dispatches, sculptor.stats().batches);  // all three ray sets in one dispatch
        if (ctx.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) {  // a few workgroups per driver thread
            EXPECT_LT(sculptor.stats().workgroups, sculptor.stats().ray_tiles);
        }
        EXPECT_GT(sculptor.stats().prepare_s, 0.0);
        EXPECT_GT(sculptor.stats().submit_s, 0.0);
        EXPECT_GT(sculptor.stats().finish_s, 0.0);
        std::cout << "segments " << program.size() << ", batches " << sculptor.stats().batches << ", ray tiles "
                  << sculptor.stats().ray_tiles << ", rays retried on the host " << sculptor.stats().retried_rays
                  << ", compactions " << sculptor.stats().compactions << ", spilled intervals "
                  << sculptor.slabs().spilled_intervals() << ", rays changed cpu/gpu " << changed_cpu << "/" << changed_gpu << "\n";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// One dispatch reaches all three ray sets, each with its own shape: on a lattice of 40 x 24 x 56 cells (X rays
// 25 x 57, Y rays 57 x 41, Z rays 41 x 25) random programs in batches, some of whose sweeps lie beyond the
// lattice's x end (so they reach X rays only) and some of whose batches reach X rays only, give the CPU
// reference's rays bit for bit.
TEST(GpuSculptor, NonCubicLatticesAndBatchesReachingOneRaySetMatchTheCpu) {
    gpu::Context ctx = gpu::Context::create({});
    {
        Lattice L;
        L.origin_m = Vec3(-0.4, 0.25, 0.9);
        L.cell_m = 0.001;
        L.cells = {40, 24, 56};
        TriDexel cpu = TriDexel::empty(L, std::size_t{1} << 30);
        scan_convert(box_mesh(Aabb{L.to_world(Vec3(3.5, 2.5, 4.5)), L.to_world(Vec3(36.5, 21.5, 51.5))}), cpu);
        TriDexel gpu_model = cpu;
        GpuSculptor sculptor(ctx, gpu_model);
        // A program inside a 24-cell cube, moved to three corners of the lattice.
        Lattice cube = L;
        cube.cells = {24, 24, 24};
        std::vector<Sweep> program = random_program(cube, 1200, 31u);
        const Vec3 shifts[3] = {Vec3(0.0), Vec3(16.0, 0.0, 0.0), Vec3(16.0, 0.0, 32.0)};
        for (std::size_t i = 0; i < program.size(); ++i) {
            const Vec3 d = shifts[i / 400] * L.cell_m;
            program[i].path_m = Segment{program[i].path_m.a + d, program[i].path_m.b + d};
        }
        // Balls beyond the lattice's x end (x = 46 cells, 3 cells radius): only X rays lie under them.
        auto beyond_x = [&](double y, double z, ToolOp op) {
            Sweep s;
            s.op = op;
            s.material = 3;
            s.tool = SweepTool{ToolKind::kBall, 0.003, 0.0};
            s.path_m = Segment{L.to_world(Vec3(46.0, y, z)), L.to_world(Vec3(47.0, y + 2.0, z + 5.0))};
            return s;
        };
        for (std::size_t i = 50; i < program.size(); i += 97)
            program.insert(program.begin() + static_cast<std::ptrdiff_t>(i), beyond_x(4.0 + i % 16, 6.0 + i % 40, ToolOp::kUnion));
        std::mt19937 rng(5);
        std::size_t done = 0, changed_cpu = 0, changed_gpu = 0;
        while (done < program.size()) {
            const std::size_t n = std::min<std::size_t>(program.size() - done, 1 + rng() % 120);
            const std::span<const Sweep> batch(program.data() + done, n);
            for (const Sweep& s : batch) changed_cpu += apply_sweep(cpu, s).rays_changed;
            changed_gpu += sculptor.apply(batch).rays_changed;
            done += n;
        }
        EXPECT_GT(changed_cpu, 5000u);
        EXPECT_GT(changed_gpu, 5000u);  // per batch: a ray changed by several of its sweeps counts once
        // A batch reaching X rays only: its tiles are all of set 0, and nothing changes (beyond the material).
        const GpuSculptStats before = sculptor.stats();
        const std::vector<Sweep> x_only = {beyond_x(10.0, 20.0, ToolOp::kSubtract), beyond_x(15.0, 40.0, ToolOp::kUnion)};
        for (const Sweep& s : x_only) changed_cpu += apply_sweep(cpu, s).rays_changed;
        EXPECT_EQ(sculptor.apply(x_only).rays_changed, 0u);
        EXPECT_EQ(sculptor.stats().dispatches, before.dispatches + 1);
        EXPECT_GT(sculptor.stats().ray_tiles, before.ray_tiles);
        EXPECT_EQ(sculptor.stats().dispatches, sculptor.stats().batches);
        const Diff mirror = compare(cpu, gpu_model);
        EXPECT_EQ(mirror.rays, 0u) << "max depth difference " << mirror.max_cells << " cells";
        TriDexel downloaded = TriDexel::empty(L, std::size_t{1} << 30);
        sculptor.slabs().download(downloaded);
        const Diff gpu_side = compare(cpu, downloaded);
        EXPECT_EQ(gpu_side.rays, 0u) << "max depth difference " << gpu_side.max_cells << " cells";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// A batch longer than the kernel's uniform buffer of sweeps (682) runs as several submissions, in order,
// and still gives the CPU reference's rays bit for bit: with the default workgroups, and with one asked for,
// where the tiles' hundreds of sweeps each exceed what one workgroup's loops may run on llvmpipe (more are
// dispatched then).
TEST(GpuSculptor, BatchesLongerThanOneSweepBufferRunInOrderAndMatchTheCpu) {
    gpu::Context ctx = gpu::Context::create({});
    for (const std::uint32_t groups : {0u, 1u}) {
        TriDexel cpu = box_model(48, 6.5, 41.5);
        TriDexel gpu_model = box_model(48, 6.5, 41.5);
        GpuSculptorOptions opt;
        opt.workgroups = groups;
        GpuSculptor sculptor(ctx, gpu_model, opt);
        const std::vector<Sweep> program = random_program(cpu.lattice, 1500, 23u);
        std::size_t changed_cpu = 0;
        for (const Sweep& s : program) changed_cpu += apply_sweep(cpu, s).rays_changed;
        const BooleanStats st = sculptor.apply(program);
        EXPECT_GT(changed_cpu, 1000u);
        EXPECT_GT(st.rays_changed, 1000u);
        EXPECT_EQ(sculptor.stats().batches, 3u);  // 682 + 682 + 136 sweeps
        EXPECT_EQ(sculptor.stats().sweeps, 1500u);
        if (groups == 1u) {
            EXPECT_GT(sculptor.stats().workgroups, 3u);
        }
        const Diff d = compare(cpu, gpu_model);
        EXPECT_EQ(d.rays, 0u) << groups << " workgroups asked for: max depth difference " << d.max_cells << " cells";
        TriDexel downloaded = TriDexel::empty(cpu.lattice, std::size_t{1} << 30);
        sculptor.slabs().download(downloaded);
        EXPECT_EQ(compare(cpu, downloaded).rays, 0u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// The kernel's workgroups take a batch's ray tiles in turn (w, w + workgroups, ...): with one workgroup, and with
// three, asked for the hundreds of tiles of each batch, random programs of every tool and operation still give the
// CPU reference's rays bit for bit; each batch dispatches at least that many workgroups (more where llvmpipe's loop
// budget needs them), each taking many tiles.
TEST(GpuSculptor, FewWorkgroupsTakingManyTilesInTurnMatchTheCpu) {
    gpu::Context ctx = gpu::Context::create({});
    for (const std::uint32_t groups : {1u, 3u}) {
        TriDexel cpu = box_model(48, 6.5, 41.5);
        TriDexel gpu_model = box_model(48, 6.5, 41.5);
        GpuSculptorOptions opt;
        opt.workgroups = groups;
        GpuSculptor sculptor(ctx, gpu_model, opt);
        const std::vector<Sweep> program = random_program(cpu.lattice, 800, 41u + groups);
        std::size_t changed_cpu = 0, changed_gpu = 0;
        for (std::size_t done = 0; done < program.size(); done += 40) {
            const std::span<const Sweep> batch(program.data() + done, std::min<std::size_t>(40, program.size() - done));
            for (const Sweep& s : batch) changed_cpu += apply_sweep(cpu, s).rays_changed;
            changed_gpu += sculptor.apply(batch).rays_changed;
        }
        const GpuSculptStats& st = sculptor.stats();
        EXPECT_GT(changed_cpu, 1000u) << groups << " workgroups";
        EXPECT_GT(changed_gpu, 1000u) << groups << " workgroups";
        EXPECT_GE(st.workgroups, groups * st.batches);
        EXPECT_GT(st.ray_tiles, 20 * st.workgroups);  // each workgroup took many tiles
        std::cout << groups << " workgroups asked for: batches " << st.batches << ", workgroups " << st.workgroups
                  << ", ray tiles " << st.ray_tiles << "\n";
        const Diff mirror = compare(cpu, gpu_model);
        EXPECT_EQ(mirror.rays, 0u) << groups << " workgroups: max depth difference " << mirror.max_cells << " cells";
        TriDexel downloaded = TriDexel::empty(cpu.lattice, std::size_t{1} << 30);
        sculptor.slabs().download(downloaded);
        const Diff gpu_side = compare(cpu, downloaded);
        EXPECT_EQ(gpu_side.rays, 0u) << groups << " workgroups: max depth difference " << gpu_side.max_cells << " cells";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// A union stroke across the lattice's corner adds material only inside the lattice's depth range
// [0, cells] on every ray (CPU and GPU alike): nothing the contour cannot show or the volume should not count.
TEST(GpuSculptor, UnionIsClippedToTheLattice) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel cpu = box_model(32, 0.0, 0.0);  // empty
        TriDexel gpu_model = box_model(32, 0.0, 0.0);
        GpuSculptor sculptor(ctx, gpu_model);
        std::vector<Sweep> strokes;
        for (int k = 0; k < 4; ++k) {
            Sweep s;
            s.op = ToolOp::kUnion;
            s.material = 3;
            s.tool = k % 2 ? SweepTool{ToolKind::kFlatEnd, 0.006, 0.02} : SweepTool{ToolKind::kBall, 0.006, 0.0};
            s.axis = glm::normalize(Vec3(1.0, -0.5, 0.7));
            const Vec3 a = cpu.lattice.to_world(Vec3(-3.0 + k, 2.0, 30.0)), b = cpu.lattice.to_world(Vec3(12.0, 35.0 - k, 1.0));
            s.path_m = Segment{a, b};
            strokes.push_back(s);
        }
        for (const Sweep& s : strokes) apply_sweep(cpu, s);
        sculptor.apply(strokes);
        std::size_t intervals = 0, clipped = 0;
        for (int a = 0; a < 3; ++a)
            for (const auto& ray : cpu.sets[a].rays)
                for (const Interval& iv : ray) {
                    ++intervals;
                    EXPECT_GE(iv.enter, 0.0f);
                    EXPECT_LE(iv.exit, static_cast<float>(cpu.lattice.cells[a]));
                    clipped += iv.enter == 0.0f || iv.exit == static_cast<float>(cpu.lattice.cells[a]) ? 1 : 0;
                }
        EXPECT_GT(intervals, 100u);
        EXPECT_GT(clipped, 10u);  // the strokes do reach past the lattice
        const Diff d = compare(cpu, gpu_model);
        EXPECT_EQ(d.rays, 0u) << "max depth difference " << d.max_cells << " cells";
        std::cout << intervals << " intervals, " << clipped << " clipped at the lattice's ends\n";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuSculptor, RaysBeyondTheKernelsIntervalLimitAreRedoneOnTheHostAndTooManyThrow) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel cpu = box_model(200, 0.0, 0.0);  // empty
        TriDexel gpu_model = box_model(200, 0.0, 0.0);
        GpuSculptor sculptor(ctx, gpu_model);
        // 90 small balls strung along the X ray through node (y, z) = (100, 100): 90 intervals on it.
        std::vector<Sweep> batch;
        for (int i = 0; i < 90; ++i) {
            Sweep s;
            s.op = ToolOp::kUnion;
            s.material = 4;
            s.tool = SweepTool{ToolKind::kBall, 0.6 * cpu.lattice.cell_m, 0.0};
            const Vec3 c = cpu.lattice.to_world(Vec3(5.0 + 2.0 * i, 100.0, 100.0));
            s.path_m = Segment{c, c};
            batch.push_back(s);
        }
        for (const Sweep& s : batch) apply_sweep(cpu, s);
        sculptor.apply(batch);
        EXPECT_EQ(cpu.sets[0].ray(100, 100).size(), 90u);
        EXPECT_EQ(compare(cpu, gpu_model).rays, 0u);
        EXPECT_GE(sculptor.stats().retried_rays, 1u);
        // A later batch touching that ray again also goes through the host, and still matches.
        std::vector<Sweep> cut(batch.begin(), batch.begin() + 3);
        for (Sweep& s : cut) s.op = ToolOp::kSubtract;
        for (const Sweep& s : cut) apply_sweep(cpu, s);
        sculptor.apply(cut);
        EXPECT_EQ(compare(cpu, gpu_model).rays, 0u);
        // More than the layout's 120 intervals on one ray is refused with a clear error.
        std::vector<Sweep> many;
        for (int i = 0; i < 60; ++i) {  // thinner balls in the gaps: 147 intervals on the ray
            Sweep s = batch[0];
            s.tool.radius_m = 0.3 * cpu.lattice.cell_m;
            s.path_m.a = s.path_m.b = cpu.lattice.to_world(Vec3(6.0 + 2.0 * i, 100.0, 100.0));
            many.push_back(s);
        }
        try {
            sculptor.apply(many);
            FAIL() << "expected an error for a ray over 120 intervals";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("120"), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuSculptor, InvalidSweepsAreRefusedBeforeAnythingChanges) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel m = box_model(32, 4.5, 27.5);
        const std::size_t n = m.interval_count();
        GpuSculptor sculptor(ctx, m);
        std::vector<Sweep> batch(2);
        batch[0].tool = SweepTool{ToolKind::kBall, 0.003, 0.0};
        batch[0].path_m = Segment{m.lattice.to_world(Vec3(16.0)), m.lattice.to_world(Vec3(18.0))};
        batch[1] = batch[0];
        batch[1].tool.radius_m = NAN;
        EXPECT_THROW(sculptor.apply(batch), Error);
        EXPECT_EQ(m.interval_count(), n);
        TriDexel d = TriDexel::empty(m.lattice, std::size_t{1} << 30);
        sculptor.slabs().download(d);
        EXPECT_EQ(d.interval_count(), n);
        EXPECT_EQ(sculptor.stats().batches, 0u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuSculptor, ResolutionsThatDoNotFitTheDeviceAreRefusedUpFrontWithTheNumbers) {
    gpu::Context ctx = gpu::Context::create({});
    Lattice L;
    L.cell_m = 1e-4;
    L.cells = {1024, 1024, 1024};
    const std::array<std::uint32_t, 3> pool{4096, 4096, 4096};
    const std::size_t bytes = GpuDexelSlabs::check_fits(ctx, L, pool);
    // 24 B per ray (meta, two inline intervals, their materials) on 3 x 1025^2 rays, plus three pools.
    EXPECT_EQ(bytes, 3u * 1025u * 1025u * 24u + 3u * 4096u * 8u * 12u);
    EXPECT_LT(3.0 * 1025 * 1025 * 20 / (1024.0 * 1024.0), 64.0);  // interval storage at N = 1024 fits 64 MiB
    L.cells = {3000, 3000, 3000};  // 9 M rays per set: 144 MB of inline depths, over lavapipe's 128 MiB binding
    try {
        GpuDexelSlabs::check_fits(ctx, L, pool);
        FAIL() << "expected a refusal";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("3000x3000x3000"), std::string::npos) << m;
        EXPECT_NE(m.find("MiB"), std::string::npos) << m;
        EXPECT_NE(m.find("--cpu"), std::string::npos) << m;
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}
