// The stereo renderer drawing the GPU contour (GpuContourShare buffers, one indirect draw per tile, flat
// shading) against the CPU tile-mesh path (CPU Contourer tiles, per-vertex normals) for the same carved,
// painted and added-to model and the same off-axis camera: same silhouette and depth order (coverage masks
// agree), colours within a stated tolerance (the two shade differently: facet vs smooth normals), and
// validation stays silent. The measured differences are printed.
#include <gtest/gtest.h>

#include <cstdio>
#include <algorithm>
#include <atomic>
#include <exception>
#include <cmath>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "app/commands/demo/demo.hpp"
#include "compute/runtime/gpu_contour_share.hpp"
#include "app/session/batch/session.hpp"
#include "app/scene/stroke.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/gpu/gpu_sculptor.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/scene/material_palette.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {
namespace {

// The renderer's clear colour (renderer/stereo/stereo_renderer.cpp kClear) as RGBA8: background pixels.
bool background(const renderer::Image& im, std::size_t p) {
    const std::uint8_t* c = &im.rgba[p * 4];
    return c[0] < 40 && c[1] < 40 && c[2] < 40;
}

struct Diff {
    std::size_t coverage_mismatch = 0, covered = 0, within = 0;
    double mean_abs = 0.0;  // mean |difference| per channel over pixels both images cover
};

Diff diff_images(const renderer::Image& a, const renderer::Image& b, int tolerance) {
    Diff d;
    const std::size_t n = static_cast<std::size_t>(a.width) * a.height;
    double sum = 0.0;
    for (std::size_t p = 0; p < n; ++p) {
        const bool ba = background(a, p), bb = background(b, p);
        if (ba != bb) ++d.coverage_mismatch;
        if (ba || bb) continue;
        ++d.covered;
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
            const int e = std::abs(int(a.rgba[p * 4 + c]) - int(b.rgba[p * 4 + c]));
            sum += e;
            worst = std::max(worst, e);
        }
        if (worst <= tolerance) ++d.within;
    }
    d.mean_abs = d.covered ? sum / (3.0 * d.covered) : 0.0;
    return d;
}

// Pixels whose colour is close to `rgb` (material colour check).
std::size_t count_near(const renderer::Image& im, const glm::vec4& linear, int tolerance) {
    std::size_t k = 0;
    for (std::size_t p = 0; p < im.rgba.size() / 4; ++p) {
        // The lit colour is base * (0.2 + 0.75 d) + specular: compare hue by channel ratios to the base.
        const float r = im.rgba[p * 4], g = im.rgba[p * 4 + 1], b = im.rgba[p * 4 + 2];
        const float s = r + g + b;
        if (s < 60.0f) continue;
        const float ls = linear.r + linear.g + linear.b;
        const float e = std::abs(r / s - linear.r / ls) + std::abs(g / s - linear.g / ls) + std::abs(b / s - linear.b / ls);
        if (e * 255.0f < static_cast<float>(tolerance)) ++k;
    }
    return k;
}

TEST(GpuContourDraw, IndirectDrawMatchesTheCpuTileMeshes) {
    gpu::ContextOptions opt;
    opt.validation = true;
    gpu::Context ctx = gpu::Context::create(opt);
    Workpiece wp = prepare_workpiece(default_mesh_path(), 64, 0.12, Vec3(0.0, 0.0, 0.05));

    // Carve the planned stroke, paint a band above it (material 3) and add a blob (material 2), on the GPU.
    StrokeParams sp;
    sp.length_m = 0.06;
    sp.depth_m = 0.004;
    sp.tool_radius_m = 0.006;
    const StrokePlan plan = plan_stroke(wp.model, sp);
    std::vector<compute::Sweep> batch;
    for (std::size_t i = 1; i < plan.world_m.size(); ++i) {
        compute::Sweep s;
        s.op = ToolOp::kSubtract;
        s.tool = compute::SweepTool{compute::ToolKind::kBall, 0.006, 0.0};
        s.path_m = Segment{plan.world_m[i - 1], plan.world_m[i]};
        batch.push_back(s);
    }
    compute::Sweep paint;
    paint.op = ToolOp::kPaint;
    paint.tool = compute::SweepTool{compute::ToolKind::kBall, 0.012, 0.0};
    paint.path_m = Segment{plan.centre_m + Vec3(-0.03, 0.015, 0.0), plan.centre_m + Vec3(0.03, 0.015, 0.0)};
    paint.material = 3;
    batch.push_back(paint);
    compute::Sweep add;
    add.op = ToolOp::kUnion;
    add.tool = compute::SweepTool{compute::ToolKind::kBall, 0.008, 0.0};
    add.path_m = Segment{plan.centre_m + Vec3(0.0, -0.02, 0.006), plan.centre_m + Vec3(0.01, -0.02, 0.006)};
    add.material = 2;
    batch.push_back(add);

    compute::GpuSculptor sculptor(ctx, wp.model);
    const compute::BooleanStats b = sculptor.apply(batch);
    ASSERT_GT(b.rays_changed, 0u);

    GpuContourShare share(ctx, sculptor.slabs(), wp.model);
    ASSERT_GT(share.update_all(), 0u);
    std::fill(wp.model.tiles.dirty.begin(), wp.model.tiles.dirty.end(), std::uint8_t{1});
    compute::Contourer contourer(wp.model);
    contourer.update(wp.model);
    compute::TileSurfaceCache cache;
    cache.refresh(contourer);
    std::vector<renderer::TileMesh> tiles;
    for (const compute::TileSurface& t : cache.tiles()) {
        renderer::TileMesh tm;
        tm.mesh = &t.mesh;
        tm.bounds_m = t.bounds_m;
        tm.version = t.version;
        tm.id = t.id;
        tm.materials = &t.materials;
        tiles.push_back(tm);
    }

    renderer::OffscreenStereoRenderer rend = renderer::OffscreenStereoRenderer::create(ctx, 320, 240);
    const renderer::Screen screen = renderer::Screen::desktop_monitor();
    Pose head;
    head.position = Vec3(0.0, 0.05, 0.45);
    const double sep = 0.065;

    renderer::SceneView cpu_view;
    cpu_view.tiles = tiles;
    cpu_view.show_workspace = false;
    cpu_view.occlusion_strength = 0.0;  // coverage is told by colour: occlusion may darken cuts to the clear colour
    const renderer::StereoImages cpu = rend.render(cpu_view, screen, head, sep);

    renderer::IndirectWorkpiece iw;
    renderer::StereoImages gpu;
    {
        auto lock = share.lock_frame(iw);
        renderer::SceneView gpu_view;
        gpu_view.indirect_workpiece = &iw;
        gpu_view.show_workspace = false;
        gpu_view.occlusion_strength = 0.0;
        gpu = rend.render(gpu_view, screen, head, sep);
    }
    EXPECT_EQ(iw.tiles.size(), cache.tiles().size());  // the same non-empty tiles
    EXPECT_EQ(iw.triangles, cache.triangle_count());    // GPU and CPU contours have the same triangles
    const auto& st = gpu.stats.tiles;
    EXPECT_EQ(st[0].drawn + st[0].skipped, iw.tiles.size());
    EXPECT_EQ(cpu.stats.tiles[0].drawn, st[0].drawn);  // the same tiles culled per eye
    EXPECT_EQ(cpu.stats.tiles[1].drawn, st[1].drawn);

    const int tolerance = 48;
    for (int eye = 0; eye < 2; ++eye) {
        const renderer::Image& g = eye == 0 ? gpu.left : gpu.right;
        const renderer::Image& c = eye == 0 ? cpu.left : cpu.right;
        const Diff d = diff_images(g, c, tolerance);
        const double covered_fraction = static_cast<double>(d.covered) / (g.width * g.height);
        const double mismatch = static_cast<double>(d.coverage_mismatch) / std::max<std::size_t>(1, d.covered);
        const double within = static_cast<double>(d.within) / std::max<std::size_t>(1, d.covered);
        std::printf("[gpu-contour draw] eye %d: %.1f%% of pixels covered, coverage mismatch %zu px (%.3f%% of covered), "
                    "mean |diff| %.2f /255, %.2f%% within %d\n",
                    eye, 100.0 * covered_fraction, d.coverage_mismatch, 100.0 * mismatch, d.mean_abs, 100.0 * within,
                    tolerance);
        EXPECT_GT(covered_fraction, 0.05) << eye;  // the workpiece is in view
        EXPECT_LT(mismatch, 0.005) << eye;         // same silhouette (float rounding of world positions only)
        EXPECT_LT(d.mean_abs, 12.0) << eye;        // flat vs smooth shading of the same facets
        EXPECT_GT(within, 0.95) << eye;
        // The painted and added materials show in both (palette colours through the vertex materials).
        const auto& pal = renderer::material_palette();
        for (int m : {2, 3}) {
            const std::size_t ng = count_near(g, pal[m], 12), nc = count_near(c, pal[m], 12);
            std::printf("[gpu-contour draw] eye %d material %d: %zu px gpu, %zu px cpu\n", eye, m, ng, nc);
            EXPECT_GT(ng, 50u) << "material " << m;
            EXPECT_GT(nc, 50u) << "material " << m;
        }
        EXPECT_GT(renderer::compare_images(g, c, 0).max_channel_diff, 0);  // they do shade differently
    }
    // Eyes differ (stereo) on both paths.
    EXPECT_GT(renderer::compare_images(gpu.left, gpu.right, 0).max_channel_diff, 0);
    // The other eye strategies draw the indirect tiles the same way (instanced-layer: one indirect draw per eye
    // with the eye in the push constant; multiview: one draw for both views), where the device passes them.
    for (renderer::EyeStrategy strategy : {renderer::EyeStrategy::kInstancedLayer, renderer::EyeStrategy::kMultiview}) {
        renderer::OffscreenStereoRenderer other = renderer::OffscreenStereoRenderer::create(ctx, 320, 240, strategy);
        if (other.strategy() != strategy) {
            std::printf("[gpu-contour draw] %s: not used here (%s)\n", std::string(renderer::to_string(strategy)).c_str(),
                        other.strategy_note().c_str());
            continue;
        }
        renderer::StereoImages o;
        {
            auto lock = share.lock_frame(iw);
            renderer::SceneView v;
            v.indirect_workpiece = &iw;
            v.show_workspace = false;
            v.occlusion_strength = 0.0;  // as the pass-per-eye picture above
            o = other.render(v, screen, head, sep);
        }
        const int dl = renderer::compare_images(o.left, gpu.left, 0).max_channel_diff;
        const int dr = renderer::compare_images(o.right, gpu.right, 0).max_channel_diff;
        std::printf("[gpu-contour draw] %s vs pass-per-eye: max channel diff left %d right %d\n",
                    std::string(renderer::to_string(strategy)).c_str(), dl, dr);
        EXPECT_LE(dl, 2) << renderer::to_string(strategy);
        EXPECT_LE(dr, 2) << renderer::to_string(strategy);
    }
    EXPECT_EQ(share.stats().tiles_cpu, 0u);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}


// The session's synchronisation: a sculpt thread carves on the GPU and re-contours dirty tiles into a share
// with tiny pools (so they grow and the buffers are replaced mid-session) while this thread draws frames
// from the share as fast as it can. Validation must stay silent and the last frame must show the final
// model as the CPU contour of the same model does.
TEST(GpuContourDraw, FramesDrawnWhileTheSculptThreadRecontoursWithGrowingPools) {
    gpu::ContextOptions opt;
    opt.validation = true;
    gpu::Context ctx = gpu::Context::create(opt);
    Workpiece wp = prepare_workpiece(default_mesh_path(), 48, 0.12, Vec3(0.0, 0.0, 0.05));
    StrokeParams sp;
    sp.length_m = 0.08;
    sp.depth_m = 0.006;
    sp.tool_radius_m = 0.006;
    const StrokePlan plan = plan_stroke(wp.model, sp);
    compute::GpuSculptor sculptor(ctx, wp.model);
    GpuContourShare share(ctx, sculptor.slabs(), wp.model, 512, 1024);
    share.update_all();
    wp.model.clear_dirty();
    const std::uint64_t grows_initial = share.stats().pool_grows;

    std::atomic<bool> done{false};
    std::exception_ptr failure;
    std::size_t steps = 0;
    std::thread sculpt([&] {
        try {
            // The stroke in 8 pieces per waypoint interval; every third sweep carves a small void inside the
            // workpiece instead (new, hidden surface: the pools must grow).
            const Vec3 inside = wp.model.lattice.bounds().centre();
            std::size_t k = 0;
            for (std::size_t i = 1; i < plan.world_m.size(); ++i) {
                for (int j = 0; j < 8; ++j, ++k) {
                    const Vec3 d = plan.world_m[i] - plan.world_m[i - 1];
                    compute::Sweep s;
                    s.tool = compute::SweepTool{compute::ToolKind::kBall, 0.006, 0.0};
                    s.path_m = Segment{plan.world_m[i - 1] + d * (j / 8.0), plan.world_m[i - 1] + d * ((j + 1) / 8.0)};
                    if (k % 3 == 2) {
                        const double v = static_cast<double>(k / 3);  // voids on a 5 x 4 x 3 grid, 12 mm apart
                        const Vec3 c = inside + 0.012 * Vec3(std::fmod(v, 5.0) - 2.0, std::fmod(std::floor(v / 5.0), 4.0) - 1.5,
                                                             std::fmod(std::floor(v / 20.0), 3.0) - 1.0);
                        s.tool.radius_m = 0.005;
                        s.path_m = Segment{c, c + Vec3(0.001, 0.0, 0.0)};
                    }
                    const compute::Sweep batch[1] = {s};
                    if (sculptor.apply(batch).rays_changed == 0) continue;
                    share.update_dirty(wp.model.tiles);
                    wp.model.clear_dirty();
                    ++steps;
                }
            }
        } catch (...) {
            failure = std::current_exception();
        }
        done = true;
    });
    renderer::OffscreenStereoRenderer rend = renderer::OffscreenStereoRenderer::create(ctx, 160, 120);
    const renderer::Screen screen = renderer::Screen::desktop_monitor();
    Pose head;
    head.position = Vec3(0.0, 0.05, 0.45);
    std::size_t frames = 0;
    renderer::IndirectWorkpiece iw;
    std::vector<VkBuffer> vertex_buffers;  // distinct vertex buffers drawn (pool growth replaces them)
    while (!done) {
        auto lock = share.lock_frame(iw);
        if (std::find(vertex_buffers.begin(), vertex_buffers.end(), iw.vertices) == vertex_buffers.end())
            vertex_buffers.push_back(iw.vertices);
        renderer::SceneView view;
        view.indirect_workpiece = &iw;
        view.show_workspace = false;
        rend.draw(view, screen, head, 0.065);
        ++frames;
    }
    sculpt.join();
    if (failure) std::rethrow_exception(failure);
    const compute::GpuContourStats st = share.stats();
    std::printf("[gpu-contour sync] %zu sculpt steps, %zu frames drawn meanwhile, pool grows %llu (initial %llu), "
                "%zu vertex buffers drawn, lock waits %.1f ms total, %.1f ms max\n",
                steps, frames, static_cast<unsigned long long>(st.pool_grows),
                static_cast<unsigned long long>(grows_initial), vertex_buffers.size(), share.lock_wait_ms_total(),
                share.lock_wait_ms_max());
    EXPECT_GT(steps, 20u);
    EXPECT_GT(frames, 2u);
    EXPECT_GT(st.pool_grows, grows_initial);  // the buffers were replaced during the session

    // The last state: GPU contour drawn vs the CPU contour of the same (mirror) model.
    std::fill(wp.model.tiles.dirty.begin(), wp.model.tiles.dirty.end(), std::uint8_t{1});
    compute::Contourer contourer(wp.model);
    contourer.update(wp.model);
    compute::TileSurfaceCache cache;
    cache.refresh(contourer);
    std::vector<renderer::TileMesh> tiles;
    for (const compute::TileSurface& t : cache.tiles())
        tiles.push_back(renderer::TileMesh{&t.mesh, t.bounds_m, t.version, &t.materials, t.id});
    renderer::SceneView cpu_view;
    cpu_view.tiles = tiles;
    cpu_view.show_workspace = false;
    cpu_view.occlusion_strength = 0.0;  // coverage is told by colour: occlusion may darken cuts to the clear colour
    const renderer::StereoImages cpu = rend.render(cpu_view, screen, head, 0.065);
    renderer::StereoImages gpu;
    {
        auto lock = share.lock_frame(iw);
        renderer::SceneView view;
        view.indirect_workpiece = &iw;
        view.show_workspace = false;
        view.occlusion_strength = 0.0;
        gpu = rend.render(view, screen, head, 0.065);
    }
    EXPECT_EQ(iw.triangles, cache.triangle_count());
    for (int eye = 0; eye < 2; ++eye) {
        const Diff d = diff_images(eye ? gpu.right : gpu.left, eye ? cpu.right : cpu.left, 48);
        std::printf("[gpu-contour sync] final eye %d: coverage mismatch %zu of %zu px, mean |diff| %.2f\n", eye,
                    d.coverage_mismatch, d.covered, d.mean_abs);
        EXPECT_LT(static_cast<double>(d.coverage_mismatch), 0.005 * d.covered + 1.0);
        EXPECT_LT(d.mean_abs, 12.0);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::app
