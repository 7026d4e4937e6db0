// bench/bench_render.hpp - `tridex bench --render`: offscreen stereo frame time of the contoured workpiece
// drawn as per-tile meshes, with and without per-tile levels of detail and per-eye tile culling.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace tridex::bench {

/// One benchmark row: `frames` stereo frames at one resolution, image size, view, LOD and culling setting.
struct RenderBenchRow {
    int n = 0;                   ///< lattice cells along the workpiece's longest side
    int width = 0, height = 0;   ///< per-eye image size, px
    std::string view;            ///< "whole" (the demo's head pose) or "close-up" (part outside the frusta)
    bool culling = true;         ///< per-eye tile culling on
    bool lod = false;            ///< per-tile levels of detail on (SceneView::lod, 1 pixel)
    bool ao = true;              ///< ambient occlusion on (SceneView::occlusion_strength 1) or off (0)
    double frame_ms_median = 0;  ///< wall time of OffscreenStereoRenderer::draw() (two frames in flight), ms
    double frame_ms_p99 = 0;
    double gpu_frame_ms_median = -1;        ///< FrameStats::frame_ms (GPU timestamps), ms; < 0 unavailable
    std::map<std::string, double> passes;   ///< median ms per pass name ("opaque", ...), both eyes summed
    /// Median over frames of the GPU frame time outside the timed passes, ms (< 0 unavailable). On lavapipe
    /// this is mostly vertex processing: llvmpipe stamps a timestamp when its rasteriser reaches it, after the
    /// draws recorded after it have been transformed and binned, so a pass's vertex work lands before its
    /// first boundary.
    double gpu_outside_passes_ms = -1;
    std::size_t tiles_drawn_left = 0, tiles_drawn_right = 0;      ///< per eye, last frame
    std::size_t tiles_skipped_left = 0, tiles_skipped_right = 0;  ///< per eye, last frame
    std::size_t tiles = 0;       ///< non-empty tiles of the workpiece
    std::size_t triangles = 0;   ///< workpiece triangles (all tiles, full meshes)
    std::size_t triangles_drawn_left = 0, triangles_drawn_right = 0;  ///< tile triangles drawn per eye, last frame
    std::size_t groups_drawn_left = 0, groups_drawn_right = 0;  ///< groups of tiles drawn per eye, last frame
    /// Draws recorded in the last frame and how many more there were before like draws merged into multi-draws
    /// (FrameStats::draws, draws_merged).
    std::size_t draws = 0, draws_merged = 0;
    /// Culling rows (LOD off): median frame ms without culling / with; 0 on the others.
    double speedup = 0;
    /// LOD rows: median frame ms with LOD off / on (both culled, same `ao`); 0 on the others.
    double lod_speedup = 0;
    /// LOD rows: fraction of pixels (both eyes, no overlay) whose object/background class differs from the
    /// full-resolution frame of the same view; -1 on the others.
    double silhouette_mismatch = -1;
    /// LOD rows: mean absolute difference per colour channel from that full-resolution frame, 0..255; -1 on the others.
    double mean_abs_diff = -1;
    std::size_t tile_buffers = 0;        ///< tile vertex + index buffers on the GPU (2 per non-empty tile and level)
    std::size_t tile_memory_blocks = 0;  ///< VkDeviceMemory allocations holding them (the renderer's tile pool)
};

/// What to measure.
struct RenderBenchOptions {
    std::string mesh;                                              ///< workpiece; empty = the bundled bunny
    std::vector<int> resolutions{256, 512};                        ///< N values
    std::vector<std::pair<int, int>> sizes{{1280, 720}, {1920, 1080}};  ///< per-eye width x height, px
    int frames = 10;                                               ///< timed frames per row (after 1 warm-up)
    /// Tiles per N whose level-of-detail build is timed alone on one thread (evenly spread over the tiles).
    std::size_t lod_timed_tiles = 200;
    /// Ambient occlusion settings to run, each a full set of rows (true = on, false = off); default both, so that
    /// its cost is measured in the same run (frames of all settings are interleaved).
    std::vector<bool> occlusion{true, false};
    std::string out = "out/bench";                                 ///< folder for render_bench.json
};

/// For each N: prepares the workpiece as the demo does (prepare_workpiece: 0.3 m stock centred 0.3 m in
/// front of the PowerWall), contours it and builds a compute::TileSurfaceCache with levels of detail
/// (reporting their build time per tile: all tiles on every core, and lod_timed_tiles alone on one thread);
/// for each image size and view, the settings (LOD on + culling, LOD off + culling, and with ambient occlusion on
/// also LOD off without culling; each for every entry of `occlusion`) are timed interleaved: in rounds, each
/// setting draws 2 settling frames and 2 timed offscreen stereo frames (OffscreenStereoRenderer::draw, two
/// frames in flight, PowerWall screen, eye separation 0.064 m, overlay on, no tool or workspace) until it has
/// `frames` timed frames, so that load changes on a shared machine hit all settings alike; then, for each LOD
/// row, one frame with and one without LOD without the overlay to compare (silhouette_mismatch, mean_abs_diff). Views: "whole" = the demo's head (0, 0.15, 0.65) m; "close-up" =
/// head (0.9, 0.7, 0.5) m, off to the upper right, so the workpiece's lower left lies outside the frusta.
/// Writes the first size's whole-view left eye with and without LOD as render_n<N>_lod_{on,off}.png.
/// Validation follows TRIDEX_VALIDATION (off unless set). Prints a table (medians per pass) and the LOD and
/// culling speed-ups, writes render_bench.json (a list of rows) into options.out and returns the rows.
/// Throws tridex::Error on a bad mesh, resolution or size, frames < 1, an unwritable folder, or no Vulkan device.
std::vector<RenderBenchRow> run_render_bench(const RenderBenchOptions& options);

}  // namespace tridex::bench
