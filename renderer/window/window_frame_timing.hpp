// renderer/window/window_frame_timing.hpp - the timings a presenting window collects, and histograms as JSON.
#pragma once

#include <nlohmann/json.hpp>

#include "core/duration_histogram.hpp"

namespace tridex::renderer {

/// A histogram as JSON: {"bin_width_ms", "count", "overflow", "rejected", "min_ms", "max_ms", "mean_ms", "p50_ms",
/// "p95_ms", "p99_ms", "bins": [[lower_edge_ms, count], ...] for the non-empty bins only}.
nlohmann::json histogram_json(const DurationHistogram& h);

/// The timings a presenting window collects, one sample per presented frame (each in its own histogram).
struct FrameTimings {
    DurationHistogram render_gpu_ms;  ///< GPU time of the stereo render (OffscreenStereoRenderer::last_gpu_ms)
    DurationHistogram blit_gpu_ms;    ///< GPU time of the present pass (blits/upload into the swapchain image)
    DurationHistogram interval_ms;    ///< CPU time between successive presents (the display period under vsync)

    /// {"render_gpu_ms": ..., "blit_gpu_ms": ..., "interval_ms": ...} (histogram_json each).
    nlohmann::json to_json() const;
};

}  // namespace tridex::renderer
