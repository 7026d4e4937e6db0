// bench/bench_render_gpu.cpp - the GPU contour's frames with and without its read-back levels of detail.
#include "bench/bench_render_gpu.hpp"

#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

#include "app/session/view/gpu_tile_split.hpp"
#include "app/session/view/tile_view.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/runtime/gpu_contour_share.hpp"
#include "core/error.hpp"
#include "core/summary.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::bench {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

GpuContourLodTiming time_gpu_contour_lod(gpu::Context& ctx, app::Workpiece& wp, int w, int h, const Pose& head,
                                         double sep_m, int frames) {
    GpuContourLodTiming t;
    std::unique_ptr<compute::GpuSculptor> sculptor;
    std::unique_ptr<app::GpuContourShare> share;
    try {
        sculptor = std::make_unique<compute::GpuSculptor>(ctx, wp.model);
        share = std::make_unique<app::GpuContourShare>(ctx, sculptor->slabs(), wp.model);
    } catch (const Error& e) {
        t.why = e.what();
        return t;
    }
    share->update_all();
    wp.model.clear_dirty();
    auto t0 = Clock::now();
    share->read_back_tiles();
    t.read_back_ms = ms_since(t0);
    compute::TileSurfaceCache cache;
    compute::TileLodOptions lo;
    lo.cell_m = wp.model.lattice.cell_m;
    cache.enable_lod(lo);
    t0 = Clock::now();
    share->refresh_tiles(cache);
    t.build_ms = ms_since(t0);
    t.tiles = cache.tiles().size();
    std::vector<std::shared_ptr<const compute::TileSurface>> tiles;
    std::vector<std::shared_ptr<const compute::TileGroupSurface>> groups;
    for (const compute::TileSurface& s : cache.tiles())
        tiles.push_back(std::make_shared<const compute::TileSurface>(s));
    for (const compute::TileGroupSurface& g : cache.groups())
        groups.push_back(std::make_shared<const compute::TileGroupSurface>(g));

    // One renderer per way of drawing, so that neither drops the other's uploaded tiles.
    renderer::OffscreenStereoRenderer full_r = renderer::OffscreenStereoRenderer::create(ctx, w, h);
    renderer::OffscreenStereoRenderer levels_r = renderer::OffscreenStereoRenderer::create(ctx, w, h);
    const renderer::Screen screen = renderer::Screen::powerwall();
    app::GpuTileSplit split;
    app::TileView view;
    // One frame as a session draws it: the buffers locked for the frame, with levels the current tiles split off.
    const auto frame = [&](bool levels, bool images, renderer::StereoImages* out) {
        renderer::IndirectWorkpiece iw;
        auto lock = share->lock_frame(iw);
        renderer::SceneView v;
        v.show_workspace = false;
        v.indirect_workpiece = &iw;
        if (levels) {
            app::split_gpu_tiles(tiles, groups, iw, split);
            app::tile_view_of(split.tiles, split.groups, true, view);
            v.tiles = view.tiles;
            v.tile_groups = view.groups;
            v.tiles_from_indirect = true;
        }
        renderer::OffscreenStereoRenderer& r = levels ? levels_r : full_r;
        if (images) {
            *out = r.render(v, screen, head, sep_m);
            return out->stats;
        }
        return r.draw(v, screen, head, sep_m);  // waits for the frame: the buffers are locked only until it returns
    };
    renderer::StereoImages full_im, levels_im;
    frame(false, true, &full_im);  // warm-up: pipelines, the levels' uploads
    frame(true, true, &levels_im);
    std::vector<double> full, with;
    for (int f = 0; f < frames; ++f) {
        t0 = Clock::now();
        const renderer::FrameStats a = frame(false, false, nullptr);
        full.push_back(ms_since(t0));
        t0 = Clock::now();
        const renderer::FrameStats b = frame(true, false, nullptr);
        with.push_back(ms_since(t0));
        t.full_triangles = a.tile_triangles[0];
        t.levels_triangles = b.tile_triangles[0];
        t.groups_drawn = b.groups_drawn[0];
    }
    const Summary sf = summarize(full), sw = summarize(with);
    t.full_ms = sf.median;
    t.full_p99_ms = sf.p99;
    t.levels_ms = sw.median;
    t.levels_p99_ms = sw.p99;
    // The background is the clear colour in a corner of the buffers-only image.
    const std::uint8_t* bg = full_im.left.rgba.data();
    std::size_t pixels = 0, mismatched = 0;
    for (const auto& [a, b] : {std::pair{&levels_im.left, &full_im.left}, std::pair{&levels_im.right, &full_im.right}})
        for (std::size_t p = 0; p < a->rgba.size() / 4; ++p) {
            ++pixels;
            const bool ba = std::equal(bg, bg + 3, a->rgba.data() + 4 * p),
                       bb = std::equal(bg, bg + 3, b->rgba.data() + 4 * p);
            mismatched += ba != bb ? 1 : 0;
        }
    t.silhouette_mismatch = pixels ? static_cast<double>(mismatched) / static_cast<double>(pixels) : 0.0;
    t.ran = true;
    return t;
}

}  // namespace tridex::bench
