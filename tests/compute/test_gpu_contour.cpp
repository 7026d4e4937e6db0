// tests/compute/test_gpu_contour.cpp - GPU contouring (GpuContourer, shaders/dexel_contour.comp) against
// the CPU Contourer: the same vertices (bit for bit as doubles; the drawn floats within 2^-24 relative),
// the same oriented triangles, a closed 2-manifold, on scan-converted meshes, random occupancy (split
// faces on the GPU; dense tiles on the host), inconsistent rays, and after incremental GPU sculpting.
#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <random>
#include <string>

#include "compute/gpu/gpu_contourer.hpp"
#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/mesh/mesh_io.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"
#include "test_contour_models.hpp"
#include "test_gpu_contour_compare.hpp"

using namespace tridex;
using namespace tridex::compute;
using namespace tridex::compute::testing;

namespace {

TriMesh shared_mesh(const std::string& file) {
    const char* dir = std::getenv("TRIDEX_SHARED_DATA");
    if (!dir) throw Error("TRIDEX_SHARED_DATA is not set");
    return load_closed_mesh(std::string(dir) + "/meshes/" + file);
}

TriDexel scan_model(const TriMesh& mesh, int resolution) {
    TriDexel m = TriDexel::empty(Lattice::around(mesh.bounds(), resolution), std::size_t{1} << 31);
    scan_convert(mesh, m);
    return m;
}


}  // namespace

TEST(GpuContour, ScanConvertedBoxSphereAndSharedMeshesGiveTheCpuMesh) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel box = scan_model(box_mesh(Aabb{Vec3(-0.02, 0.01, 0.0), Vec3(0.03, 0.04, 0.025)}), 48);
        expect_same_contour(ctx, box, "box N=48");
        TriDexel sphere = scan_model(icosphere_mesh(Vec3(0.1, -0.2, 0.3), 0.05, 4), 64);
        expect_same_contour(ctx, sphere, "icosphere N=64");
        for (const char* file : {"sphere.off", "bunny00.off", "elephant.off"}) {
            TriDexel m = scan_model(shared_mesh(file), 96);
            expect_same_contour(ctx, m, std::string(file) + " N=96");
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuContour, RandomOccupancyWithSplitFacesAndInconsistentRaysGiveTheCpuMesh) {
    gpu::Context ctx = gpu::Context::create({});
    {
        std::uint64_t host_tiles = 0, gpu_tiles = 0, gpu_split_faces = 0;
        for (const double density : {0.1, 0.5, 0.85}) {
            TriDexel m = random_voxels(40, density, 3u);  // 3 x 3 x 3 tiles, the last ones partial
            GpuContourStats s;
            expect_same_contour(ctx, m, "random voxels density " + std::to_string(density), &s);
            host_tiles += s.tiles_cpu;
            gpu_tiles += s.tiles_gpu;
            gpu_split_faces += s.split_faces_gpu;
        }
        EXPECT_GT(host_tiles, 0u);       // dense random tiles overflow the kernel's lists: the host path runs
        // Sparse random solids on a 5^3-tile lattice: every tile runs on the GPU.
        TriDexel sparse = random_voxels(80, 0.02, 5u);
        GpuContourStats s;
        expect_same_contour(ctx, sparse, "sparse random voxels", &s);
        gpu_tiles += s.tiles_gpu;
        EXPECT_GT(gpu_tiles, 0u);
        // Every ray with its own random intervals (up to 3 per ray, so some in the slabs' spill pool):
        // crossings fall back to the nearest end as on the CPU.
        const int cells = 34;
        TriDexel incons = empty_model(cube_lattice(cells));
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> pos(1.0, cells - 1.0);
        fill_rays(incons, [&](int, int u, int v) {
            std::vector<Interval> ray;
            if (u == 0 || v == 0 || u == cells || v == cells) return ray;
            std::vector<double> ends;
            for (int e = 0; e < 6; ++e) ends.push_back(pos(rng));
            std::sort(ends.begin(), ends.end());
            for (int e = 0; e + 1 < 6; e += 2)
                if (ends[e + 1] - ends[e] > 1e-3 && (ray.empty() || ends[e] > ray.back().exit + 1e-3))
                    ray.push_back({static_cast<float>(ends[e]), static_cast<float>(ends[e + 1]), static_cast<std::uint8_t>(e), 3});
            return ray;
        });
        expect_same_contour(ctx, incons, "inconsistent rays", &s);
        gpu_split_faces += s.split_faces_gpu;
        EXPECT_GT(gpu_split_faces, 0u);  // the kernel's face-split rule runs (the dense random tiles run on the host)
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuContour, TilesWhoseLoopsExceedTheDevicesCapGiveTheCpuMesh) {
    // Plates across X one node thick (x in [2k + 0.8, 2k + 1.2]) with slivers between them that hold no node
    // (6 per gap, 0.05 cells wide): every cell has four crossings, and each crossing's normal loops over the
    // ~84 intervals of four neighbour X rays, far beyond llvmpipe's 65535 loop iterations per SIMD group and
    // run of the kernel. Tiles the kernel cannot finish must come out as the CPU's (contoured on the host), not
    // with vertices and indices left unwritten.
    gpu::Context ctx = gpu::Context::create({});
    {
        const int cells = 32;
        TriDexel m = empty_model(cube_lattice(cells));
        fill_rays(m, [&](int a, int u, int v) {
            std::vector<Interval> ray;
            if (u < 1 || v < 1 || u > cells - 1 || v > cells - 1) return ray;
            if (a == 0) {
                for (int k = 1; 2 * k + 1 < cells; ++k) {
                    ray.push_back({static_cast<float>(2 * k + 0.8), static_cast<float>(2 * k + 1.2), 1, 1});
                    for (int j = 0; j < 6 && 2 * k + 2.8 < cells; ++j)
                        ray.push_back({static_cast<float>(2 * k + 1.3 + 0.2 * j), static_cast<float>(2 * k + 1.35 + 0.2 * j), 2, 2});
                }
                return ray;
            }
            const int x = a == 1 ? v : u;  // Y rays (u, v) = (z, x), Z rays (x, y)
            if (x % 2 == 1 && x >= 3 && x <= cells - 3) ray.push_back({1.0f, static_cast<float>(cells - 1), 1, 1});
            return ray;
        });
        GpuContourStats s;
        expect_same_contour(ctx, m, "plates with slivers", &s);
        if (ctx.device_name().find("llvmpipe") != std::string::npos) {
            EXPECT_GT(s.tiles_loop_capped, 0u);  // the probe found the cut tiles
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuContour, IncrementalUpdatesAfterGpuSculptingEqualTheCpuAndAFullRecontour) {
    gpu::Context ctx = gpu::Context::create({});
    {
        Lattice L = cube_lattice(64);
        TriDexel mirror = TriDexel::empty(L, std::size_t{1} << 30);
        scan_convert(box_mesh(Aabb{L.to_world(Vec3(8.5)), L.to_world(Vec3(55.5))}), mirror);
        GpuSculptorOptions opt;
        opt.initial_pool_chunks = 16;  // tiny spill pools: the sculptor replaces slab buffers (re-bound here)
        GpuSculptor sculptor(ctx, mirror, opt);
        GpuContourer gpu(ctx, sculptor.slabs(), L, 512, 2048);
        Contourer cpu(mirror);
        gpu.update_dirty(mirror.tiles);
        cpu.update(mirror);
        std::mt19937 rng(21);
        std::uniform_real_distribution<double> pos(6.0, 58.0), unit(0.0, 1.0);
        std::size_t redone = 0;
        for (int batch = 0; batch < 12; ++batch) {
            std::vector<Sweep> sweeps;
            for (int i = 0; i < 1 + static_cast<int>(rng() % 6); ++i) {
                Sweep s;
                const double pick = unit(rng);
                s.op = pick < 0.5 ? ToolOp::kSubtract : pick < 0.8 ? ToolOp::kUnion : ToolOp::kPaint;
                s.material = static_cast<std::uint8_t>(1 + rng() % 6);
                s.tool = SweepTool{unit(rng) < 0.3 ? ToolKind::kFlatEnd : ToolKind::kBall, (1.0 + 5.0 * unit(rng)) * L.cell_m, 4.0 * L.cell_m};
                s.axis = Vec3(unit(rng) - 0.5, unit(rng) - 0.5, 0.7);
                const Vec3 a = L.to_world(Vec3(pos(rng), pos(rng), pos(rng)));
                s.path_m = Segment{a, a + (Vec3(unit(rng), unit(rng), unit(rng)) - 0.5) * (12.0 * L.cell_m)};
                sweeps.push_back(s);
            }
            sculptor.apply(sweeps);
            redone += gpu.update_dirty(mirror.tiles);  // before the CPU contourer clears the dirty flags
            cpu.update(mirror);
            const MeshDiff d = compare_meshes(gpu, cpu);
            ASSERT_EQ(d.vertices_only_one_side, 0u) << "batch " << batch;
            ASSERT_EQ(d.triangles_only_one_side, 0u) << "batch " << batch;
        }
        EXPECT_LT(redone, 12u * gpu.tile_count());  // only dirty tiles were redone
        expect_closed_manifold(weld_exact(gpu.download()));
        // A fresh contourer over all tiles gives the same mesh as the incrementally updated one.
        GpuContourer full(ctx, sculptor.slabs(), L);
        std::vector<std::uint32_t> all(full.tile_count());
        for (std::uint32_t t = 0; t < all.size(); ++t) all[t] = t;
        full.update(all);
        const MeshDiff d = compare_meshes(full, cpu);
        EXPECT_EQ(d.triangles_only_one_side, 0u);
        EXPECT_EQ(d.vertices_only_one_side, 0u);
        std::cout << "[ gpu contour ] incremental: " << redone << " tile contours over 12 batches, "
                  << gpu.stats().region_retries << " region retries, " << gpu.stats().pool_grows << " pool grows, "
                  << gpu.stats().tiles_cpu << " host tiles; final mesh " << d.gpu_triangles << " triangles\n";
        EXPECT_GT(gpu.stats().pool_grows, 0u);
        EXPECT_GT(sculptor.stats().compactions, 0u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GpuContour, BadTileIndicesAreRefused) {
    gpu::Context ctx = gpu::Context::create({});
    {
        TriDexel m = TriDexel::empty(cube_lattice(20), std::size_t{1} << 28);
        const GpuDexelSlabs slabs = GpuDexelSlabs::upload(ctx, m);
        GpuContourer gpu(ctx, slabs, m.lattice);
        const std::uint32_t bad[] = {0u, 8u};  // 2 x 2 x 2 tiles
        EXPECT_THROW(gpu.update(bad), Error);
        EXPECT_THROW(gpu.tile_index_count(8), Error);
        const std::uint32_t ok[] = {0u, 7u, 7u};
        EXPECT_EQ(gpu.update(ok), 2u);
        EXPECT_EQ(gpu.tile_index_count(0), 0u);  // an empty model has no surface
        Lattice other = m.lattice;
        other.cells = {21, 20, 20};
        EXPECT_THROW(GpuContourer(ctx, slabs, other), Error);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}
