// renderer/stereo/frame_timer.hpp - GPU timestamp queries around a stereo frame and its draw phases.
#pragma once

#include <cstddef>
#include <cstdint>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"
#include "renderer/stereo/eye_strategy.hpp"
#include "renderer/timing/frame_stats.hpp"
#include "renderer/stereo/stereo_frame.hpp"

namespace tridex::renderer {

/// A timestamp query pool for one stereo frame: the frame's top and bottom (queries 0, 1) and the phase
/// boundaries of each render pass instance (PhaseTimestamps from query 2). Tick differences are masked to
/// the queue family's timestampValidBits and converted with VkPhysicalDeviceLimits::timestampPeriod (ns per
/// tick). Empty (available() false) when the queue family reports timestampValidBits = 0 or the Context did
/// not enable timestamps. Move-only; the Context must outlive it.
class FrameTimer {
public:
    FrameTimer() = default;
    /// Creates the pool for `strategy` (2 render pass instances for pass-per-eye, else 1; 2 queries per
    /// in-pass timestamp under multiview). Throws tridex::Error on a Vulkan failure.
    static FrameTimer create(const gpu::Context& context, EyeStrategy strategy);

    bool available() const { return pool_.get() != VK_NULL_HANDLE; }
    /// Records the reset of every query and the frame's top-of-pipe timestamp (outside a render pass).
    void record_begin(VkCommandBuffer cmd) const;
    /// Where record_stereo_frame() writes the phase timestamps.
    PhaseTimestamps phases() const { return PhaseTimestamps{pool_.get(), 2u, stride_}; }
    /// Records the frame's bottom-of-pipe timestamp.
    void record_end(VkCommandBuffer cmd) const;
    /// After the frame's submission completed: sets stats.timing = kGpuTimestamps, timing_note, frame_ms and
    /// one PassTime per timed part and render pass instance ("opaque", "occlusion", "translucent", "overlay"; eye = pass for
    /// pass-per-eye, -1 otherwise), and stats.gpu_end_s when the device's timestamps are calibrated. Returns false (stats untouched) when the results are not available.
    bool read(const gpu::Context& context, FrameStats& stats) const;

private:
    gpu::UniqueQueryPool pool_;
    EyeStrategy strategy_ = EyeStrategy::kPassPerEye;
    std::uint32_t passes_ = 1, stride_ = 1, count_ = 0;
    std::uint64_t mask_ = 0;
    double period_ns_ = 1.0;
};

}  // namespace tridex::renderer
