// renderer/stereo/frame_timer.cpp - timestamp pool, recording and read-back.
#include "renderer/stereo/frame_timer.hpp"

#include <cstdio>
#include <vector>

#include "gpu/check.hpp"
#include "gpu/device_clock.hpp"

namespace tridex::renderer {

FrameTimer FrameTimer::create(const gpu::Context& context, EyeStrategy strategy) {
    FrameTimer t;
    t.strategy_ = strategy;
    std::uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(context.physical_device(), &families, nullptr);
    std::vector<VkQueueFamilyProperties> props(families);
    vkGetPhysicalDeviceQueueFamilyProperties(context.physical_device(), &families, props.data());
    const std::uint32_t valid_bits = props.at(context.queue_family()).timestampValidBits;
    if (!context.features().timestamps || valid_bits == 0) return t;
    t.mask_ = valid_bits >= 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << valid_bits) - 1);
    t.period_ns_ = context.properties().limits.timestampPeriod;
    t.passes_ = strategy == EyeStrategy::kPassPerEye ? 2u : 1u;
    t.stride_ = strategy == EyeStrategy::kMultiview ? 2u : 1u;
    t.count_ = 2u + t.passes_ * (kTimedPhaseCount + 1) * t.stride_;
    VkQueryPoolCreateInfo q{};
    q.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    q.queryType = VK_QUERY_TYPE_TIMESTAMP;
    q.queryCount = t.count_;
    VkQueryPool pool = VK_NULL_HANDLE;
    gpu::check(vkCreateQueryPool(context.device(), &q, nullptr, &pool), "vkCreateQueryPool");
    t.pool_ = gpu::UniqueQueryPool(context.device(), pool);
    return t;
}

void FrameTimer::record_begin(VkCommandBuffer cmd) const {
    if (!available()) return;
    vkCmdResetQueryPool(cmd, pool_.get(), 0, count_);
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool_.get(), 0);
}

void FrameTimer::record_end(VkCommandBuffer cmd) const {
    if (available()) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_.get(), 1);
}

bool FrameTimer::read(const gpu::Context& context, FrameStats& stats) const {
    if (!available()) return false;
    std::vector<std::uint64_t> t(count_, 0);
    const VkResult r = vkGetQueryPoolResults(context.device(), pool_.get(), 0, count_, t.size() * sizeof(t[0]),
                                             t.data(), sizeof(t[0]), VK_QUERY_RESULT_64_BIT);
    if (r != VK_SUCCESS) return false;
    const auto ms = [&](std::uint32_t a, std::uint32_t b) {
        const std::uint64_t ticks = ((t[b] & mask_) - (t[a] & mask_)) & mask_;
        return static_cast<double>(ticks) * period_ns_ * 1e-6;
    };
    const PhaseTimestamps ph = phases();
    stats.timing = TimingSource::kGpuTimestamps;
    char note[96];
    std::snprintf(note, sizeof note, "GPU timestamps (%.3g ns per tick)", period_ns_);
    stats.timing_note = note;
    stats.frame_ms = ms(0, 1);
    stats.gpu_end_s = gpu::device_ticks_to_steady_s(context, t[1] & mask_, mask_).value_or(stats.gpu_end_s);
    stats.passes.clear();
    for (std::uint32_t p = 0; p < passes_; ++p)
        for (int k = 0; k < kTimedPhaseCount; ++k)
            stats.passes.push_back(PassTime{timed_phase_name(k), passes_ == 2 ? static_cast<int>(p) : -1,
                                            ms(ph.query(p, k), ph.query(p, k + 1))});
    return true;
}

}  // namespace tridex::renderer
