// gpu/repeat_submit.hpp - one command buffer and one fence, recorded and submitted again and again.
#pragma once

#include <cstdint>
#include <functional>

#include <vulkan/vulkan.h>

#include "gpu/command_pool.hpp"
#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"

namespace tridex::gpu {


/// How RepeatSubmitter::run waits for its fence.
enum class FenceWait : std::uint8_t {
    kBlock,  ///< vkWaitForFences: the thread sleeps until the driver signals the fence
    kPoll,   ///< vkGetFenceStatus in a loop that yields the core between polls (sched_yield), for short submissions
};

/// A submission a caller repeats many times (a batch per call): owns its own command pool, one primary
/// command buffer and one fence, all made once, so a submission allocates and frees no Vulkan object. Each
/// run() resets and re-records the buffer, submits it with Context::queue_submit and waits for the fence.
/// Not thread-safe (one thread calls run()); other threads may submit to the same Context meanwhile. The
/// Context must outlive it.
class RepeatSubmitter {
public:
    /// Creates the pool, buffer and fence. Throws tridex::Error on a Vulkan failure.
    explicit RepeatSubmitter(const Context& context, FenceWait wait = FenceWait::kBlock);
    ~RepeatSubmitter();
    RepeatSubmitter(const RepeatSubmitter&) = delete;
    RepeatSubmitter& operator=(const RepeatSubmitter&) = delete;

    /// Records the command buffer with `record`, submits it and waits (at most 60 s) until the GPU has
    /// finished. Exceptions from `record` propagate (nothing is submitted). Throws tridex::Error on a Vulkan
    /// failure or on the timeout (after waiting for the device to go idle).
    void run(const std::function<void(VkCommandBuffer)>& record);

    /// How run() waits.
    FenceWait wait_mode() const { return wait_; }

private:
    const Context& context_;
    FenceWait wait_;
    UniqueCommandPool pool_;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;  // freed with pool_
    UniqueFence fence_;
};

}  // namespace tridex::gpu
