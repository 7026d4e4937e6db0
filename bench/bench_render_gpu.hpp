// bench/bench_render_gpu.hpp - frames of the GPU contour drawn from its buffers alone and with the levels of detail
// read back from it.
#pragma once

#include <cstddef>
#include <string>

#include "app/session/batch/session.hpp"
#include "core/pose.hpp"
#include "gpu/context.hpp"

namespace tridex::bench {

/// What time_gpu_contour_lod measured.
struct GpuContourLodTiming {
    bool ran = false;  ///< false: the device cannot contour on the GPU (`why` says so)
    std::string why;
    std::size_t tiles = 0;                ///< non-empty tiles of the contour
    double read_back_ms = 0;              ///< copying every tile out of the buffers (GpuContourShare::read_back_tiles)
    double build_ms = 0;                  ///< the read-back tiles' levels and groups, built on every core
    double full_ms = 0, full_p99_ms = 0;  ///< frame wall time, buffers only (indirect draws), ms
    double levels_ms = 0, levels_p99_ms = 0;               ///< frame wall time with the read-back levels, ms
    std::size_t full_triangles = 0, levels_triangles = 0;  ///< tile triangles drawn by the left eye
    std::size_t groups_drawn = 0;                          ///< groups drawn by the left eye with levels
    double silhouette_mismatch = 0;                        ///< fraction of pixels whose object/background differs
};

/// Contours `wp` on the GPU (GpuSculptor slabs, GpuContourShare), reads every tile back, builds their levels of
/// detail, then draws `frames` stereo frames of w x h px per eye (PowerWall screen, `head`, eye separation `sep_m`)
/// from the buffers alone and as many with the current tiles drawn from their levels (split_gpu_tiles), interleaved,
/// and compares one frame of each. Throws tridex::Error on a Vulkan failure other than a missing feature.
GpuContourLodTiming time_gpu_contour_lod(gpu::Context& ctx, app::Workpiece& wp, int w, int h, const Pose& head,
                                         double sep_m, int frames);

}  // namespace tridex::bench
