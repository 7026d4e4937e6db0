// tests/compute/test_gpu_tdx_file.cpp - a model sculpted on the GPU, with intervals in the spill pool, saves and
// loads bit for bit: both the session's CPU mirror and the model downloaded from the GPU slabs.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/model/tdx_file.hpp"
#include "gpu/context.hpp"
#include "tdx_test_models.hpp"

using namespace tridex;
using namespace tridex::compute;

TEST(GpuTdxFile, SpilledGpuModelsRoundTripBitForBit) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel cpu = tdx_test::sculpted_sphere(40, 0, 1u);
        TriDexel mirror = cpu;  // the GPU path's CPU model, kept equal to the slabs by the sculptor
        GpuSculptorOptions opt;
        opt.initial_pool_chunks = 4;  // tiny: rays beyond two intervals spill, the pool compacts and grows
        GpuSculptor sculptor(ctx, mirror, opt);
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u(0.15, 0.85), unit(0.0, 1.0);
        const Lattice& L = cpu.lattice;
        std::vector<Sweep> program;
        for (int i = 0; i < 400; ++i) {
            Sweep s;
            s.op = unit(rng) < 0.6 ? ToolOp::kSubtract : unit(rng) < 0.5 ? ToolOp::kUnion : ToolOp::kPaint;
            s.material = static_cast<std::uint8_t>(1 + rng() % 6);
            s.tool = SweepTool{ToolKind::kBall, (0.8 + 2.5 * unit(rng)) * L.cell_m, 0.0};
            s.path_m = Segment{L.to_world(Vec3(u(rng), u(rng), u(rng)) * 40.0), L.to_world(Vec3(u(rng), u(rng), u(rng)) * 40.0)};
            program.push_back(s);
        }
        for (std::size_t done = 0; done < program.size(); done += 50) {
            const std::span<const Sweep> batch(program.data() + done, std::min<std::size_t>(50, program.size() - done));
            for (const Sweep& s : batch) apply_sweep(cpu, s);
            sculptor.apply(batch);
        }
        EXPECT_GT(sculptor.slabs().spilled_intervals(), 0u);
        TriDexel downloaded = TriDexel::empty(L, std::size_t{1} << 30);
        sculptor.slabs().download(downloaded);
        downloaded.tiles = cpu.tiles;  // download() fills the rays only
        tdx_test::expect_identical(cpu, mirror);  // the premise: GPU and CPU agree

        const std::filesystem::path dir = std::filesystem::temp_directory_path();
        const std::string a = (dir / ("gpu_mirror_" + std::to_string(::getpid()) + ".tdx")).string();
        const std::string b = (dir / ("gpu_slabs_" + std::to_string(::getpid()) + ".tdx")).string();
        save_tdx(a, mirror, Mat4(1.0), "{}");
        save_tdx(b, downloaded, Mat4(1.0), "{}");
        const TdxModel back_a = load_tdx(a, std::size_t{1} << 30), back_b = load_tdx(b, std::size_t{1} << 30);
        tdx_test::expect_identical(mirror, back_a.model);
        tdx_test::expect_identical(downloaded, back_b.model);
        tdx_test::expect_identical(cpu, back_b.model);  // and so the CPU reference's
        std::filesystem::remove(a);
        std::filesystem::remove(b);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}
