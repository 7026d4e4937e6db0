// tests/compute/test_gpu_contour_draw.cpp - the GPU contour drawn straight from its buffers with one
// vkCmdDrawIndexedIndirect per tile (renderer/contour_indirect_draw) gives the image of the CPU mesh drawn
// with vkCmdDrawIndexed through the same pipeline, after GPU sculpting and incremental re-contouring.
#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <random>

#include "compute/contour_dual.hpp"
#include "compute/gpu_contourer.hpp"
#include "compute/gpu_sculptor.hpp"
#include "compute/scan_convert.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"
#include "renderer/contour_indirect_draw.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

/// Pixels whose colours differ in any channel by more than `tol` (0..255).
std::size_t differing_pixels(const renderer::Image& a, const renderer::Image& b, int tol) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.rgba.size(); i += 4)
        for (int c = 0; c < 3; ++c)
            if (std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c])) > tol) {
                ++n;
                break;
            }
    return n;
}

std::size_t background_pixels(const renderer::Image& a) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.rgba.size(); i += 4) n += (a.rgba[i] == a.rgba[0] && a.rgba[i + 1] == a.rgba[1] && a.rgba[i + 2] == a.rgba[2]) ? 1 : 0;
    return n;
}

}  // namespace

TEST(GpuContourDraw, IndirectDrawOfTheGpuBuffersMatchesTheCpuMeshImage) {
    gpu::Context ctx = gpu::Context::create({});
    {
        Lattice L;
        L.origin_m = Vec3(0.1, -0.2, 0.05);
        L.cell_m = 1e-3;
        L.cells = {64, 64, 64};
        TriDexel mirror = TriDexel::empty(L, std::size_t{1} << 30);
        scan_convert(box_mesh(Aabb{L.to_world(Vec3(8.5)), L.to_world(Vec3(55.5))}), mirror);
        GpuSculptor sculptor(ctx, mirror);
        GpuContourer gpu(ctx, sculptor.slabs(), L);
        Contourer cpu(mirror);
        gpu.update_dirty(mirror.tiles);
        cpu.update(mirror);
        auto renderer = renderer::ContourIndirectRenderer::create(ctx, 320, 240);
        const glm::mat4 proj = glm::perspective(glm::radians(45.0f), 320.0f / 240.0f, 1.0f, 500.0f);
        const glm::mat4 view = glm::lookAt(glm::vec3(110.0f, 95.0f, 120.0f), glm::vec3(32.0f), glm::vec3(0.0f, 0.0f, 1.0f));
        const glm::mat4 clip_from_grid = proj * view;
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> pos(10.0, 54.0), unit(0.0, 1.0);
        for (int round = 0; round < 4; ++round) {
            std::vector<Sweep> strokes;
            for (int i = 0; i < 4; ++i) {
                Sweep s;
                s.op = i == 3 ? ToolOp::kPaint : (unit(rng) < 0.7 ? ToolOp::kSubtract : ToolOp::kUnion);
                s.material = static_cast<std::uint8_t>(1 + rng() % 6);
                s.tool = ToolShape{ToolKind::kBall, (3.0 + 4.0 * unit(rng)) * L.cell_m, 0.0};
                const Vec3 a(pos(rng), pos(rng), 55.5), b(pos(rng), pos(rng), 50.0 + 8.0 * unit(rng));
                s.path_m = Segment{L.to_world(a), L.to_world(b)};
                strokes.push_back(s);
            }
            sculptor.apply(strokes);
            gpu.update_dirty(mirror.tiles);
            cpu.update(mirror);

            const renderer::Image indirect = renderer.render_indirect(
                {gpu.vertex_buffer().handle(), gpu.index_buffer().handle(), gpu.draw_commands().handle(), gpu.tile_count()}, clip_from_grid);
            const TriMesh m = cpu.mesh();
            const std::vector<std::uint8_t> mats = cpu.mesh_materials();
            std::vector<renderer::ContourDrawVertex> verts(m.positions.size());
            for (std::size_t i = 0; i < verts.size(); ++i) {
                const Vec3 g = L.to_grid(m.positions[i]);
                verts[i] = {{float(g.x), float(g.y), float(g.z)}, mats[i]};
            }
            std::vector<std::uint32_t> idx;
            for (const auto& t : m.triangles) idx.insert(idx.end(), t.begin(), t.end());
            const renderer::Image direct = renderer.render_direct(verts, idx, clip_from_grid);
            const std::size_t total = std::size_t{320} * 240, diff = differing_pixels(indirect, direct, 2);
            const std::size_t covered = total - background_pixels(direct);
            std::cout << "[ gpu draw ] round " << round << ": " << m.triangles.size() << " triangles, " << covered
                      << " pixels covered, " << diff << " pixels differ by more than 2/255 (indirect vs CPU mesh)\n";
            EXPECT_GT(covered, total / 10);
            // Tolerance: 0.05 % of the pixels (CPU positions go world -> grid -> float, which can round one ulp
            // away from the kernel's float, moving an edge pixel).
            EXPECT_LE(diff, total / 2000) << "round " << round;
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}
