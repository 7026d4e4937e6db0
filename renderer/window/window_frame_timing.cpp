// renderer/window/window_frame_timing.cpp - the window's frame timings as JSON.
#include "renderer/window/window_frame_timing.hpp"

namespace tridex::renderer {

nlohmann::json histogram_json(const DurationHistogram& h) {
    nlohmann::json bins = nlohmann::json::array();
    for (std::size_t k = 0; k < h.bins().size(); ++k)
        if (h.bins()[k]) bins.push_back({h.bin_lower_ms(k), h.bins()[k]});
    return {{"bin_width_ms", h.bin_width_ms()},
            {"count", h.count()},
            {"overflow", h.overflow()},
            {"rejected", h.rejected()},
            {"min_ms", h.min_ms()},
            {"max_ms", h.max_ms()},
            {"mean_ms", h.mean_ms()},
            {"p50_ms", h.percentile_ms(0.5)},
            {"p95_ms", h.percentile_ms(0.95)},
            {"p99_ms", h.percentile_ms(0.99)},
            {"bins", bins}};
}

nlohmann::json FrameTimings::to_json() const {
    return {{"render_gpu_ms", histogram_json(render_gpu_ms)},
            {"blit_gpu_ms", histogram_json(blit_gpu_ms)},
            {"interval_ms", histogram_json(interval_ms)}};
}

}  // namespace tridex::renderer
