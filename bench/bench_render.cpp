// bench/bench_render.cpp - timing offscreen stereo frames of the tiled workpiece, culling on and off.
#include "bench/bench_render.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/demo.hpp"
#include "app/session.hpp"
#include "app/stats.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "app/json_file.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/camera/display_config.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kStockM = 0.3;
const Vec3 kWorkpieceCentre{0.0, 0.0, 0.3};
constexpr double kEyeSeparationM = renderer::kDefaultEyeSeparationM;
constexpr const char* kPasses[] = {"opaque", "translucent", "overlay"};

struct BenchView {
    const char* name;
    Vec3 head_m;
};
const BenchView kViews[] = {{"whole", Vec3(0.0, 0.15, 0.65)}, {"close-up", Vec3(0.9, 0.7, 0.5)}};

nlohmann::json row_json(const RenderBenchRow& r) {
    nlohmann::json passes = nlohmann::json::object();
    for (const auto& [name, ms] : r.passes) passes[name] = ms;
    return {{"n", r.n}, {"width", r.width}, {"height", r.height}, {"view", r.view}, {"culling", r.culling},
            {"frame_ms_median", r.frame_ms_median}, {"frame_ms_p99", r.frame_ms_p99},
            {"gpu_frame_ms_median", r.gpu_frame_ms_median}, {"passes", passes},
            {"tiles_drawn_left", r.tiles_drawn_left}, {"tiles_drawn_right", r.tiles_drawn_right},
            {"tiles_skipped_left", r.tiles_skipped_left}, {"tiles_skipped_right", r.tiles_skipped_right},
            {"tiles", r.tiles}, {"triangles", r.triangles}, {"speedup", r.speedup},
            {"tile_buffers", r.tile_buffers}, {"tile_memory_blocks", r.tile_memory_blocks}};
}

}  // namespace

std::vector<RenderBenchRow> run_render_bench(const RenderBenchOptions& o) {
    if (o.frames < 1) throw Error("--frames: must be at least 1, got " + std::to_string(o.frames));
    for (const auto& [w, h] : o.sizes) check_image_size(w, h);
    const std::string mesh = o.mesh.empty() ? default_mesh_path() : o.mesh;
    gpu::Context ctx = gpu::Context::create({});
    std::vector<RenderBenchRow> rows;
    std::string timing_note;
    std::printf("%5s %10s %9s %4s %9s %9s %8s %8s %8s %8s %13s %13s\n", "N", "size", "view", "cull", "frame_ms",
                "p99_ms", "gpu_ms", "opaque", "transl", "overlay", "tiles L d/s", "tiles R d/s");
    for (int n : o.resolutions) {
        Workpiece wp = prepare_workpiece(mesh, n, kStockM, kWorkpieceCentre);
        compute::Contourer contourer(wp.model);
        contourer.update(wp.model);
        compute::TileSurfaceCache cache;
        cache.refresh(contourer);
        std::vector<renderer::TileMesh> list;
        list.reserve(cache.tiles().size());
        for (const compute::TileSurface& s : cache.tiles())
            list.push_back(renderer::TileMesh{&s.mesh, s.bounds_m, s.version, nullptr, s.id});
        const std::size_t triangles = cache.triangle_count();
        for (const auto& [w, h] : o.sizes) {
            renderer::OffscreenStereoRenderer r = renderer::OffscreenStereoRenderer::create(ctx, w, h);
            renderer::SceneView scene;
            scene.show_workspace = false;
            scene.show_overlay = true;
            scene.tiles = list;
            scene.occlusion_strength = o.occlusion ? 1.0 : 0.0;
            for (const BenchView& v : kViews) {
                Pose head;
                head.position = v.head_m;
                for (int cull = 1; cull >= 0; --cull) {
                    scene.cull_tiles = cull == 1;
                    r.draw(scene, renderer::Screen::powerwall(), head, kEyeSeparationM);  // warm-up: uploads
                    std::vector<double> wall, gpu;
                    std::map<std::string, std::vector<double>> pass_ms;
                    renderer::FrameStats last;
                    for (int f = 0; f < o.frames; ++f) {
                        const auto t0 = Clock::now();
                        // Two frames in flight: draw() waits only for the frame before the last, so this is
                        // the frame interval of a steady stream of frames (its timings: the latest finished).
                        last = r.draw(scene, renderer::Screen::powerwall(), head, kEyeSeparationM);
                        wall.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
                        if (last.frame_ms < 0.0) continue;
                        gpu.push_back(last.frame_ms);
                        for (const renderer::PassTime& p : last.passes) pass_ms[p.pass];  // every name seen
                        for (auto& [name, values] : pass_ms) values.push_back(last.pass_ms(name));
                    }
                    last = r.finish();
                    if (gpu.empty() && last.frame_ms >= 0.0) {  // no frame had finished during the loop
                        gpu.push_back(last.frame_ms);
                        for (const renderer::PassTime& p : last.passes) pass_ms[p.pass].push_back(last.pass_ms(p.pass));
                    }
                    timing_note = last.timing_note;
                    RenderBenchRow row;
                    row.n = n;
                    row.width = w;
                    row.height = h;
                    row.view = v.name;
                    row.culling = cull == 1;
                    const Summary s = summarize(wall);
                    row.frame_ms_median = s.median;
                    row.frame_ms_p99 = s.p99;
                    row.gpu_frame_ms_median = last.timing == renderer::TimingSource::kGpuTimestamps && !gpu.empty()
                                                  ? summarize(gpu).median
                                                  : -1.0;
                    for (const auto& [name, values] : pass_ms) row.passes[name] = summarize(values).median;
                    row.tiles_drawn_left = last.tiles[0].drawn;
                    row.tiles_drawn_right = last.tiles[1].drawn;
                    row.tiles_skipped_left = last.tiles[0].skipped;
                    row.tiles_skipped_right = last.tiles[1].skipped;
                    row.tiles = list.size();
                    row.triangles = triangles;
                    row.tile_buffers = r.tile_buffers();
                    row.tile_memory_blocks = r.tile_memory_blocks();
                    rows.push_back(row);
                    auto pass = [&](const char* name) {
                        const auto it = row.passes.find(name);
                        return it == row.passes.end() ? -1.0 : it->second;
                    };
                    char size[32], left[32], right[32];
                    std::snprintf(size, sizeof size, "%dx%d", w, h);
                    std::snprintf(left, sizeof left, "%zu/%zu", row.tiles_drawn_left, row.tiles_skipped_left);
                    std::snprintf(right, sizeof right, "%zu/%zu", row.tiles_drawn_right, row.tiles_skipped_right);
                    std::printf("%5d %10s %9s %4s %9.2f %9.2f %8.2f %8.2f %8.2f %8.2f %13s %13s\n", n, size, v.name,
                                cull ? "on" : "off", row.frame_ms_median, row.frame_ms_p99, row.gpu_frame_ms_median,
                                pass(kPasses[0]), pass(kPasses[1]), pass(kPasses[2]), left, right);
                }
                // The two rows just added: culling on, then off.
                RenderBenchRow& on = rows[rows.size() - 2];
                const RenderBenchRow& off = rows.back();
                on.speedup = on.frame_ms_median > 0.0 ? off.frame_ms_median / on.frame_ms_median : 0.0;
            }
        }
        std::printf("N=%d: %zu triangles in %zu non-empty tiles; their %zu GPU buffers in %zu memory allocations\n", n,
                    triangles, list.size(), rows.back().tile_buffers, rows.back().tile_memory_blocks);
    }
    for (const RenderBenchRow& r : rows)
        if (r.culling)
            std::printf("culling speed-up N=%d %dx%d %s: %.2fx (frame %.2f ms with, %.2f ms without)\n", r.n, r.width,
                        r.height, r.view.c_str(), r.speedup, r.frame_ms_median, r.frame_ms_median * r.speedup);
    std::printf("frame_ms: wall clock around draw() (two frames in flight); gpu_ms and passes: %s; ambient occlusion "
                "%s; validation %s; %d frames per row (+1 warm-up)\n",
                timing_note.empty() ? "-" : timing_note.c_str(), o.occlusion ? "on" : "off",
                ctx.validation_enabled() ? "on" : "off", o.frames);
    nlohmann::json j = nlohmann::json::array();
    for (const RenderBenchRow& r : rows) j.push_back(row_json(r));
    const std::string path = (std::filesystem::path(o.out) / "render_bench.json").string();
    write_json_file(path, j);
    std::printf("wrote %s\n", path.c_str());
    return rows;
}

}  // namespace tridex::app
