// tests/compute/test_gpu_contour_bench.cpp - tiles contoured per second, GPU (lavapipe) vs CPU (one
// thread, Contourer), at N = 256: the full surface of a scan-converted sphere, then the dirty tiles of
// ball strokes. Prints the numbers (not timed assertions); checks the meshes agree in size.
#include <gtest/gtest.h>

#include <chrono>
#include <iostream>

#include "compute/contour/contour_dual.hpp"
#include "compute/gpu/gpu_contourer.hpp"
#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<std::uint32_t> dirty_list(const TileGrid& g) {
    std::vector<std::uint32_t> out;
    for (std::size_t t = 0; t < g.count(); ++t)
        if (g.dirty[t]) out.push_back(static_cast<std::uint32_t>(t));
    return out;
}

}  // namespace

TEST(GpuContourBench, TilesContouredPerSecondAtN256) {
    gpu::Context ctx = gpu::Context::create({});
    {
        const TriMesh sphere = icosphere_mesh(Vec3(0.0), 0.05, 5);
        TriDexel model = TriDexel::empty(Lattice::around(sphere.bounds(), 256), std::size_t{1} << 31);
        scan_convert(sphere, model);
        GpuSculptor sculptor(ctx, model);
        const std::vector<std::uint32_t> surface = dirty_list(model.tiles);
        ASSERT_GT(surface.size(), 100u);

        GpuContourer gpu(ctx, sculptor.slabs(), model.lattice);
        auto t0 = std::chrono::steady_clock::now();
        gpu.update(surface);  // first contour: every region is sized (one retry round)
        const double gpu_first = seconds_since(t0);
        t0 = std::chrono::steady_clock::now();
        gpu.update(surface);  // regions fit: one dispatch
        const double gpu_full = seconds_since(t0);
        Contourer cpu(model);
        t0 = std::chrono::steady_clock::now();
        cpu.update(model);
        const double cpu_full = seconds_since(t0);
        std::size_t gpu_indices = 0;
        for (std::uint32_t t = 0; t < gpu.tile_count(); ++t) gpu_indices += gpu.tile_index_count(t);
        EXPECT_EQ(gpu_indices, 3 * cpu.stats().triangles);

        // Strokes: a ball of radius 8 cells along 24-cell segments across the surface, one per batch.
        const Lattice& L = model.lattice;
        std::size_t stroke_tiles = 0;
        double gpu_strokes = 0.0, cpu_strokes = 0.0;
        for (int i = 0; i < 8; ++i) {
            Sweep s;
            s.op = i % 2 ? ToolOp::kUnion : ToolOp::kSubtract;
            s.tool = SweepTool{ToolKind::kBall, 8.0 * L.cell_m, 0.0};
            const double ang = 0.7 * i;
            const Vec3 a = Vec3(std::cos(ang), std::sin(ang), 0.3) * 0.048;
            s.path_m = Segment{a, a + Vec3(-std::sin(ang), std::cos(ang), 0.2) * (24.0 * L.cell_m)};
            sculptor.apply(std::span<const Sweep>(&s, 1));
            const std::vector<std::uint32_t> dirty = dirty_list(model.tiles);
            stroke_tiles += dirty.size();
            t0 = std::chrono::steady_clock::now();
            gpu.update(dirty);
            gpu_strokes += seconds_since(t0);
            t0 = std::chrono::steady_clock::now();
            cpu.update(model);
            cpu_strokes += seconds_since(t0);
        }
        gpu_indices = 0;
        for (std::uint32_t t = 0; t < gpu.tile_count(); ++t) gpu_indices += gpu.tile_index_count(t);
        EXPECT_EQ(gpu_indices, 3 * cpu.stats().triangles);
        const double n = static_cast<double>(surface.size());
        std::cout << "[ bench ] N=256 sphere, " << surface.size() << " surface tiles, " << cpu.stats().triangles
                  << " triangles (" << ctx.device_name() << ")\n"
                  << "[ bench ] full contour: gpu " << n / gpu_full << " tiles_contoured_per_s (" << gpu_full * 1e3
                  << " ms; first call with region sizing " << gpu_first * 1e3 << " ms), cpu-1t " << n / cpu_full
                  << " tiles_contoured_per_s (" << cpu_full * 1e3 << " ms)\n"
                  << "[ bench ] 8 strokes, " << stroke_tiles << " dirty tiles: gpu " << stroke_tiles / gpu_strokes
                  << " tiles_contoured_per_s (" << gpu_strokes * 1e3 / 8 << " ms per stroke), cpu-1t "
                  << stroke_tiles / cpu_strokes << " tiles_contoured_per_s (" << cpu_strokes * 1e3 / 8
                  << " ms per stroke); host-contoured tiles " << gpu.stats().tiles_cpu << "\n";
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}
