// bench/bench_render.cpp - timing offscreen stereo frames of the tiled workpiece, LOD and culling on and off.
#include "bench/bench_render.hpp"
#include "bench/bench_registry.hpp"
#include "bench/bench_render_gpu.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <filesystem>
#include <fstream>
#include <map>
#include <span>
#include <string>
#include <nlohmann/json.hpp>

#include "app/commands/demo/demo.hpp"
#include "app/session/batch/session.hpp"
#include "core/summary.hpp"
#include "app/session/view/tile_view.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "app/support/json_file.hpp"
#include "app/support/progress.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/camera/display_config.hpp"
#include "renderer/image/image.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions, stats and JSON files

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kStockM = 0.3;
const Vec3 kWorkpieceCentre{0.0, 0.0, 0.3};
constexpr double kEyeSeparationM = renderer::kDefaultEyeSeparationM;
constexpr const char* kPasses[] = {"opaque", "occlusion", "translucent", "overlay"};

struct BenchView {
    const char* name;
    Vec3 head_m;
};
const BenchView kViews[] = {{"whole", Vec3(0.0, 0.15, 0.65)}, {"close-up", Vec3(0.9, 0.7, 0.5)}};

nlohmann::json row_json(const RenderBenchRow& r) {
    nlohmann::json passes = nlohmann::json::object();
    for (const auto& [name, ms] : r.passes) passes[name] = ms;
    return {{"n", r.n}, {"width", r.width}, {"height", r.height}, {"view", r.view}, {"culling", r.culling},
            {"lod", r.lod ? "on" : "off"}, {"ao", r.ao ? "on" : "off"}, {"frame_ms_median", r.frame_ms_median}, {"frame_ms_p99", r.frame_ms_p99},
            {"gpu_frame_ms_median", r.gpu_frame_ms_median}, {"gpu_outside_passes_ms", r.gpu_outside_passes_ms},
            {"passes", passes},
            {"tiles_drawn_left", r.tiles_drawn_left}, {"tiles_drawn_right", r.tiles_drawn_right},
            {"tiles_skipped_left", r.tiles_skipped_left}, {"tiles_skipped_right", r.tiles_skipped_right},
            {"tiles", r.tiles}, {"triangles", r.triangles},
            {"triangles_drawn", {r.triangles_drawn_left, r.triangles_drawn_right}},
            {"groups_drawn", {r.groups_drawn_left, r.groups_drawn_right}},
            {"draws", r.draws}, {"draws_merged", r.draws_merged},
            {"speedup", r.speedup}, {"lod_speedup", r.lod_speedup},
            {"silhouette_mismatch", r.silhouette_mismatch}, {"mean_abs_diff", r.mean_abs_diff},
            {"tile_buffers", r.tile_buffers}, {"tile_memory_blocks", r.tile_memory_blocks}};
}

// Object/background classes and colour differences of two renders of the same frame (both eyes).
struct ImageDiff {
    double silhouette_mismatch = 0.0;
    double mean_abs_diff = 0.0;
};

ImageDiff image_diff(const renderer::StereoImages& a, const renderer::StereoImages& b, const std::uint8_t* background) {
    std::size_t pixels = 0, mismatched = 0;
    double abs_sum = 0.0;
    const auto one = [&](const renderer::Image& x, const renderer::Image& y) {
        for (std::size_t p = 0; p + 3 < x.rgba.size() && p + 3 < y.rgba.size(); p += 4) {
            const bool bx = std::equal(background, background + 3, x.rgba.data() + p);
            const bool by = std::equal(background, background + 3, y.rgba.data() + p);
            mismatched += bx != by ? 1 : 0;
            for (int c = 0; c < 3; ++c) abs_sum += std::abs(int(x.rgba[p + c]) - int(y.rgba[p + c]));
            ++pixels;
        }
    };
    one(a.left, b.left);
    one(a.right, b.right);
    ImageDiff d;
    if (pixels > 0) {
        d.silhouette_mismatch = static_cast<double>(mismatched) / static_cast<double>(pixels);
        d.mean_abs_diff = abs_sum / (3.0 * static_cast<double>(pixels));
    }
    return d;
}

struct Setting {
    bool lod, cull, ao;
    const char* name;
};

// Each LOD row's LOD-off partner (same ambient occlusion) is the next setting, and each "cull" row with ambient
// occlusion on is followed by its unculled partner.
std::vector<Setting> bench_settings(const std::vector<bool>& occlusion) {
    std::vector<Setting> s;
    for (const bool ao : occlusion) {
        s.push_back({true, true, ao, "lod+cull"});
        s.push_back({false, true, ao, "cull"});
        if (ao) s.push_back({false, false, ao, "none"});
    }
    return s;
}

// What one setting's timed frames gave.
struct Samples {
    std::vector<double> wall, gpu, outside;
    std::map<std::string, std::vector<double>> pass_ms;
    renderer::FrameStats last;
};

// The scene settings of `st`: tile culling, LOD, ambient occlusion.
void apply_setting(renderer::SceneView& scene, const Setting& st) {
    scene.cull_tiles = st.cull;
    scene.lod = st.lod;
    scene.occlusion_strength = st.ao ? 1.0 : 0.0;
}

// The cost of the levels of detail of `cache` (workpiece of N = n cells) built with `lod_options`: its whole build, and
// one tile at a time on one thread (up to about `timed_tiles` tiles spread over the list: what a dirty tile costs the
// thread that builds its levels), with the levels per tile and per group and the coarsest levels' triangles. Prints the line and
// returns it.
std::string lod_build_line(const compute::TileSurfaceCache& cache, const compute::TileLodOptions& lod_options, int n,
                           std::size_t timed_tiles) {
    std::vector<double> one_ms;
    std::size_t levels = 0, lod_triangles = 0;
    const auto& all = cache.tiles();
    const std::size_t step = std::max<std::size_t>(1, all.size() / std::max<std::size_t>(1, timed_tiles));
    for (std::size_t i = 0; i < all.size(); i += step) {
        const auto t0 = Clock::now();
        // As TileSurfaceCache::build_lods and the LOD worker build a tile's levels: with its whole-surface normals
        // (TileSurface::normals).
        const auto built = compute::build_lod_levels(all[i].mesh, all[i].materials, all[i].normals, 0.0, lod_options);
        one_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
    for (const compute::TileSurface& s : all) {
        levels += s.lods.size();
        if (!s.lods.empty()) lod_triangles += s.lods.back().mesh.triangles.size();
        else lod_triangles += s.mesh.triangles.size();
    }
    // Groups: the coarsest level of each top-most group that has levels covers its tiles.
    std::size_t group_levels = 0, top_triangles = 0;
    int top_depth = 0;
    for (const compute::TileGroupSurface& g : cache.groups()) {
        group_levels += g.lods.size();
        top_depth = std::max(top_depth, g.depth);
    }
    for (const compute::TileGroupSurface& g : cache.groups())
        if (g.depth == top_depth) top_triangles += g.lods.empty() ? 0 : g.lods.back().mesh.triangles.size();
    const Summary lod_s = summarize(one_ms);
    char line[480];
    std::snprintf(line, sizeof line,
                  "LOD build N=%d: %zu tiles and %zu groups in %.0f ms on %u cores; one thread, %zu tiles: median "
                  "%.3f ms, p99 %.3f ms per tile; %.2f levels per tile, %.2f per group; coarsest tile levels %zu, "
                  "coarsest depth-%d group levels %zu of %zu triangles",
                  n, cache.lod_tiles_built(), cache.lod_groups_built(), cache.lod_build_ms(),
                  std::max(1u, std::thread::hardware_concurrency()), one_ms.size(), lod_s.median, lod_s.p99,
                  static_cast<double>(levels) / std::max<std::size_t>(1, all.size()),
                  static_cast<double>(group_levels) / std::max<std::size_t>(1, cache.groups().size()), lod_triangles,
                  top_depth, top_triangles, cache.triangle_count());
    std::printf("%s\n", line);
    return line;
}

// The timed frames of every setting seen from `head`, `frames` per setting: a warm-up frame per setting (uploads of
// every level), then interleaved rounds, per setting kSettle frames that fill the two frame slots and kTimed frames
// whose draw() waits for a frame of the same setting (the frame interval of a steady stream). `timing_note` takes the
// renderer's note on its GPU timings.
std::vector<Samples> time_settings(renderer::OffscreenStereoRenderer& r, renderer::SceneView& scene, const Pose& head,
                                   const std::vector<Setting>& settings, int frames, std::string& timing_note) {
    for (const Setting& st : settings) {
        apply_setting(scene, st);
        r.draw(scene, renderer::Screen::powerwall(), head, kEyeSeparationM);
    }
    r.finish();
    r.take_finished_frames();
    constexpr int kSettle = 2, kTimed = 2;
    std::vector<Samples> got(settings.size());
    while (static_cast<int>(got[0].wall.size()) < frames) {
        for (std::size_t k = 0; k < settings.size(); ++k) {
            apply_setting(scene, settings[k]);
            for (int f = 0; f < kSettle + kTimed; ++f) {
                const auto t0 = Clock::now();
                got[k].last = r.draw(scene, renderer::Screen::powerwall(), head, kEyeSeparationM);
                const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
                if (f >= kSettle) got[k].wall.push_back(ms);
            }
            r.finish();
            const std::vector<renderer::FrameStats> done = r.take_finished_frames();
            for (std::size_t i = done.size() >= kTimed ? done.size() - kTimed : 0; i < done.size(); ++i) {
                const renderer::FrameStats& fs = done[i];
                timing_note = fs.timing_note;
                if (fs.timing != renderer::TimingSource::kGpuTimestamps || fs.frame_ms < 0.0) continue;
                got[k].gpu.push_back(fs.frame_ms);
                double in_passes = 0.0;
                for (const renderer::PassTime& p : fs.passes) in_passes += p.ms;
                got[k].outside.push_back(fs.frame_ms - in_passes);
                std::map<std::string, double> frame_passes;  // summed over the eyes; a pass the frame skipped is absent
                for (const renderer::PassTime& p : fs.passes) frame_passes[p.pass] += p.ms;
                for (const auto& [name, ms] : frame_passes) got[k].pass_ms[name].push_back(ms);
            }
        }
    }
    return got;
}

// The table row of setting `st` from its samples `g` (the row's n, size and view already set in `row`), with the
// renderer's tile buffers; `tiles` and `triangles`: the workpiece's non-empty tiles and their triangles.
void fill_row(const Setting& st, const Samples& g, const renderer::OffscreenStereoRenderer& r, std::size_t tiles,
              std::size_t triangles, RenderBenchRow& row) {
    row.culling = st.cull;
    row.lod = st.lod;
    row.ao = st.ao;
    const Summary s = summarize(g.wall);
    row.frame_ms_median = s.median;
    row.frame_ms_p99 = s.p99;
    row.gpu_frame_ms_median = g.gpu.empty() ? -1.0 : summarize(g.gpu).median;
    row.gpu_outside_passes_ms = g.outside.empty() ? -1.0 : summarize(g.outside).median;
    for (const auto& [name, values] : g.pass_ms) row.passes[name] = summarize(values).median;
    row.tiles_drawn_left = g.last.tiles[0].drawn;
    row.tiles_drawn_right = g.last.tiles[1].drawn;
    row.tiles_skipped_left = g.last.tiles[0].skipped;
    row.tiles_skipped_right = g.last.tiles[1].skipped;
    row.triangles_drawn_left = g.last.tile_triangles[0];
    row.triangles_drawn_right = g.last.tile_triangles[1];
    row.groups_drawn_left = g.last.groups_drawn[0];
    row.groups_drawn_right = g.last.groups_drawn[1];
    row.draws = g.last.draws;
    row.draws_merged = g.last.draws_merged;
    row.tiles = tiles;
    row.triangles = triangles;
    row.tile_buffers = r.tile_buffers();
    row.tile_memory_blocks = r.tile_memory_blocks();
}

// Prints one row of the table (the header printed by run_render_bench).
void print_row(const RenderBenchRow& row, const char* setting) {
    char size[32], left[32], right[32], passes[3][32];
    const char* const pass_names[3] = {kPasses[0], kPasses[1], kPasses[3]};
    for (int k = 0; k < 3; ++k) {  // "-" for a pass no timed frame ran (the occlusion when it is off)
        const auto it = row.passes.find(pass_names[k]);
        if (it == row.passes.end())
            std::snprintf(passes[k], sizeof passes[k], "-");
        else
            std::snprintf(passes[k], sizeof passes[k], "%.2f", it->second);
    }
    std::snprintf(size, sizeof size, "%dx%d", row.width, row.height);
    std::snprintf(left, sizeof left, "%zu/%zu", row.tiles_drawn_left, row.tiles_skipped_left);
    std::snprintf(right, sizeof right, "%zu/%zu", row.tiles_drawn_right, row.tiles_skipped_right);
    std::printf("%5d %10s %9s %8s %3s %9.2f %9.2f %8.2f %8s %9s %8s %13s %13s %10zu %8zu %8.2f\n", row.n, size,
                row.view.c_str(), setting, row.ao ? "on" : "off", row.frame_ms_median, row.frame_ms_p99,
                row.gpu_frame_ms_median, passes[0], passes[1], passes[2], left, right, row.triangles_drawn_left,
                row.groups_drawn_left, row.gpu_outside_passes_ms);
}

// One view's rows (one per setting, in order): each LOD row's and each culled row's speed-up over its partner (the
// next row), and for each LOD row the same frame rendered with and without LOD (no overlay: it shows the frame time)
// compared against the `background` colour; with `write_pngs`, those frames' left images are written to directory
// `out` as render_n<N>_lod_{on,off}[_ao_off].png.
void compare_view_rows(renderer::OffscreenStereoRenderer& r, renderer::SceneView& scene, const Pose& head,
                       std::span<RenderBenchRow> rows, const std::uint8_t* background, bool write_pngs,
                       const std::string& out) {
    for (std::size_t k = 0; k < rows.size(); ++k) {
        RenderBenchRow& row = rows[k];
        const RenderBenchRow* next = k + 1 < rows.size() ? &rows[k + 1] : nullptr;
        if (row.lod && next && next->frame_ms_median > 0.0 && row.frame_ms_median > 0.0)
            row.lod_speedup = next->frame_ms_median / row.frame_ms_median;
        if (!row.lod && row.culling && next && !next->culling && row.frame_ms_median > 0.0)
            row.speedup = next->frame_ms_median / row.frame_ms_median;
        if (!row.lod) continue;
        scene.show_overlay = false;
        scene.cull_tiles = true;
        scene.occlusion_strength = row.ao ? 1.0 : 0.0;
        scene.lod = true;
        const renderer::StereoImages with = r.render(scene, renderer::Screen::powerwall(), head, kEyeSeparationM);
        scene.lod = false;
        const renderer::StereoImages without = r.render(scene, renderer::Screen::powerwall(), head, kEyeSeparationM);
        scene.show_overlay = true;
        const ImageDiff d = image_diff(with, without, background);
        row.silhouette_mismatch = d.silhouette_mismatch;
        row.mean_abs_diff = d.mean_abs_diff;
        if (write_pngs) {
            const std::filesystem::path dir(out);
            const std::string stem = "render_n" + std::to_string(row.n) + "_lod_";
            const std::string ao = row.ao ? "" : "_ao_off";
            renderer::write_png((dir / (stem + "on" + ao + ".png")).string(), with.left);
            renderer::write_png((dir / (stem + "off" + ao + ".png")).string(), without.left);
        }
    }
}

// The rows of one image size w x h (the size_index-th of o.sizes) for the tiled workpiece `view` of N = n cells with
// `triangles` triangles: per view of kViews, every setting timed (time_settings) and compared (compare_view_rows).
void bench_size(gpu::Context& ctx, const RenderBenchOptions& o, std::size_t size_index, int n, const TileView& view,
                std::size_t triangles, const std::vector<Setting>& settings, std::vector<RenderBenchRow>& rows,
                std::string& timing_note) {
    const auto [w, h] = o.sizes[size_index];
    renderer::OffscreenStereoRenderer r = renderer::OffscreenStereoRenderer::create(ctx, w, h);
    renderer::SceneView scene;
    scene.show_workspace = false;
    // The background colour: a frame with nothing in it.
    scene.show_overlay = false;
    Pose any_head;
    any_head.position = kViews[0].head_m;
    const renderer::StereoImages empty = r.render(scene, renderer::Screen::powerwall(), any_head, kEyeSeparationM);
    const std::array<std::uint8_t, 3> background{empty.left.rgba[0], empty.left.rgba[1], empty.left.rgba[2]};
    scene.show_overlay = true;
    scene.tiles = view.tiles;
    scene.tile_groups = view.groups;
    for (const BenchView& v : kViews) {
        Pose head;
        head.position = v.head_m;
        const std::vector<Samples> got = time_settings(r, scene, head, settings, o.frames, timing_note);
        const std::size_t first_row = rows.size();
        for (std::size_t k = 0; k < settings.size(); ++k) {
            RenderBenchRow row;
            row.n = n;
            row.width = w;
            row.height = h;
            row.view = v.name;
            fill_row(settings[k], got[k], r, view.tiles.size(), triangles, row);
            rows.push_back(row);
            print_row(row, settings[k].name);
        }
        const bool png = size_index == 0 && std::string(v.name) == "whole";
        compare_view_rows(r, scene, head, std::span<RenderBenchRow>(rows).subspan(first_row), background.data(), png,
                          o.out);
    }
}

// The speed-up lines under the table, the LOD build lines, the timing note, and the rows as render_bench.json in
// `out` (its path printed).
void report_rows(const std::vector<RenderBenchRow>& rows, const std::vector<std::string>& lod_lines,
                 const std::string& timing_note, bool validation, int frames, const std::string& out) {
    for (const RenderBenchRow& r : rows)
        if (r.lod)
            std::printf("LOD N=%d %dx%d %s AO %s: %.2fx faster (frame %.2f ms with, %.2f ms without), triangles per eye "
                        "%zu / %zu of %zu, silhouette mismatch %.4f%%, mean abs diff %.3f\n",
                        r.n, r.width, r.height, r.view.c_str(), r.ao ? "on" : "off", r.lod_speedup, r.frame_ms_median,
                        r.frame_ms_median * r.lod_speedup, r.triangles_drawn_left, r.triangles_drawn_right, r.triangles,
                        100.0 * r.silhouette_mismatch, r.mean_abs_diff);
    for (const RenderBenchRow& r : rows)
        if (r.culling && !r.lod && r.speedup > 0.0)
            std::printf("culling speed-up N=%d %dx%d %s: %.2fx (frame %.2f ms with, %.2f ms without)\n", r.n, r.width,
                        r.height, r.view.c_str(), r.speedup, r.frame_ms_median, r.frame_ms_median * r.speedup);
    for (const std::string& l : lod_lines) std::printf("%s\n", l.c_str());
    std::printf("frame_ms: wall clock around draw() (two frames in flight; settings interleaved); gpu_ms and passes: "
                "%s; validation %s; %d timed frames per row\n",
                timing_note.empty() ? "-" : timing_note.c_str(), validation ? "on" : "off", frames);
    nlohmann::json j = nlohmann::json::array();
    for (const RenderBenchRow& r : rows) j.push_back(row_json(r));
    const std::string path = (std::filesystem::path(out) / "render_bench.json").string();
    write_json_file(path, j);
    std::printf("wrote %s\n", path.c_str());
}

// The GPU contour of `wp` (N = n) at the first image size, whole view: frames from its buffers alone and with the
// levels of detail read back from it (time_gpu_contour_lod). Prints the line and returns it.
std::string gpu_contour_lod_line(gpu::Context& ctx, Workpiece& wp, int n, std::pair<int, int> size, int frames) {
    Pose head;
    head.position = kViews[0].head_m;
    const GpuContourLodTiming g = time_gpu_contour_lod(ctx, wp, size.first, size.second, head, kEyeSeparationM, frames);
    char line[640];
    if (!g.ran)
        std::snprintf(line, sizeof line, "GPU-contour LOD N=%d: not run (%s)", n, g.why.c_str());
    else
        std::snprintf(line, sizeof line,
                      "GPU-contour LOD N=%d %dx%d whole: %.2fx faster (frame %.2f / %.2f ms median / p99 with the "
                      "read-back levels, %.2f / %.2f ms from the buffers alone), triangles L %zu of %zu, groups L %zu, "
                      "silhouette mismatch %.4f%%; reading back %zu tiles %.0f ms, their levels %.0f ms",
                      n, size.first, size.second, g.levels_ms > 0.0 ? g.full_ms / g.levels_ms : 0.0, g.levels_ms,
                      g.levels_p99_ms, g.full_ms, g.full_p99_ms, g.levels_triangles, g.full_triangles, g.groups_drawn,
                      100.0 * g.silhouette_mismatch, g.tiles, g.read_back_ms, g.build_ms);
    std::printf("%s\n", line);
    return line;
}

}  // namespace

std::vector<RenderBenchRow> run_render_bench(const RenderBenchOptions& o) {
    if (o.frames < 1) throw Error("--frames: must be at least 1, got " + std::to_string(o.frames));
    for (const auto& [w, h] : o.sizes) check_image_size(w, h);
    const std::string mesh = o.mesh.empty() ? default_mesh_path() : o.mesh;
    std::error_code made;
    std::filesystem::create_directories(o.out, made);
    if (made) throw Error("--out: cannot create " + o.out + ": " + made.message());
    gpu::Context ctx = gpu::Context::create({});
    std::vector<RenderBenchRow> rows;
    std::vector<std::string> lod_lines;
    std::string timing_note;
    if (o.occlusion.empty()) throw Error("bench --render: no ambient occlusion setting to run");
    const std::vector<Setting> settings = bench_settings(o.occlusion);
    std::printf("%5s %10s %9s %8s %3s %9s %9s %8s %8s %9s %8s %13s %13s %10s %8s %8s\n", "N", "size", "view", "setting",
                "ao", "frame_ms", "p99_ms", "gpu_ms", "opaque", "occlusion", "overlay", "tiles L d/s", "tiles R d/s",
                "tris L", "groups L", "outside");
    for (int n : o.resolutions) {
        Workpiece wp = prepare_workpiece(mesh, n, kStockM, kWorkpieceCentre);
        compute::Contourer contourer(wp.model);
        {
            app::ProgressReporter::Step step =
                app::progress().step("contouring the workpiece at " + std::to_string(n) + " cells");
            contourer.update(wp.model, step.fn());
        }
        compute::TileLodOptions lod_options;
        lod_options.cell_m = wp.model.lattice.cell_m;
        compute::TileSurfaceCache cache;
        cache.enable_lod(lod_options);
        cache.refresh(contourer);
        lod_lines.push_back(lod_build_line(cache, lod_options, n, o.lod_timed_tiles));
        TileView view;
        tile_view_of(cache.tiles(), cache.groups(), true, view);
        const std::size_t triangles = cache.triangle_count();
        for (std::size_t si = 0; si < o.sizes.size(); ++si)
            bench_size(ctx, o, si, n, view, triangles, settings, rows, timing_note);
        std::printf("N=%d: %zu triangles in %zu non-empty tiles; their %zu GPU buffers in %zu memory allocations\n", n,
                    triangles, view.tiles.size(), rows.back().tile_buffers, rows.back().tile_memory_blocks);
        lod_lines.push_back(gpu_contour_lod_line(ctx, wp, n, o.sizes[0], o.frames));
    }
    report_rows(rows, lod_lines, timing_note, ctx.validation_enabled(), o.frames, o.out);
    return rows;
}

namespace {

struct RenderBenchCli {
    RenderBenchOptions options;
    std::vector<int> n;
    std::vector<std::string> ao;
    std::vector<std::string> size;
};

BenchRun setup_render_bench(CLI::App& bench) {
    auto o = std::make_shared<RenderBenchCli>();
    bench.add_option("--render-n", o->n, "With --render: run only these N (16..1024), e.g. --render-n 256")
        ->delimiter(',')
        ->check(CLI::Range(16, 1024));
    bench.add_option("--render-ao", o->ao, "With --render: ambient occlusion settings to time, interleaved (default on,off)")
        ->delimiter(',')
        ->check(CLI::IsMember({"on", "off"}));
    bench.add_option("--render-size", o->size, "With --render: per-eye image sizes WxH (default 1280x720,1920x1080)")
        ->delimiter(',');
    bench.add_option("--frames", o->options.frames, "With --render: timed frames per row")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    return [o](const BenchCommon& c) {
        RenderBenchOptions r = o->options;
        r.out = c.out;
        r.mesh = c.mesh;
        if (!o->ao.empty()) {
            r.occlusion.clear();
            for (const std::string& a : o->ao) r.occlusion.push_back(a == "on");
        }
        if (!o->size.empty()) {
            r.sizes.clear();
            for (const std::string& z : o->size) r.sizes.push_back(parse_image_size(z, "--render-size"));
        }
        if (!o->n.empty()) r.resolutions = o->n;
        run_render_bench(r);
    };
}

const BenchmarkRegistration kRegistration{
    {"render",
     "Offscreen stereo frame time per pass at 1280x720 and 1920x1080, bunny at 256 and 512 cells, with and without "
     "per-tile levels of detail and tile culling; and the GPU contour with and without its read-back levels",
     60, setup_render_bench}};

}  // namespace

}  // namespace tridex::bench
