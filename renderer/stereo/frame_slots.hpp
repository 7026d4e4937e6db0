// renderer/stereo/frame_slots.hpp - frames in flight: per-frame command buffers and fences, deferred destruction.
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"

namespace tridex::renderer {

/// A ring of `count` frame slots, each with its own command pool, primary command buffer and fence, so the CPU
/// records frame n + 1 while the GPU still runs frame n (Granite-style frame contexts). Frames are numbered from 1
/// in submission order. begin() takes the next slot, waiting only for the frame that last used it (count frames
/// ago); objects handed to retire() are destroyed once every frame submitted before the call has finished.
/// Move-only; the Context must outlive it; one thread at a time. The destructor waits for the slots' frames.
class FrameSlots {
public:
    FrameSlots() = default;
    /// Creates `count` (1..8) slots. Throws tridex::Error on a bad count or a Vulkan failure.
    static FrameSlots create(const gpu::Context& context, int count);
    ~FrameSlots();
    FrameSlots(FrameSlots&&) noexcept = default;
    FrameSlots& operator=(FrameSlots&&) noexcept = default;

    int count() const { return static_cast<int>(slots_.size()); }
    /// Takes the next slot for a new frame: waits (at most 10 s; then throws tridex::Error) for the frame that last
    /// used it, destroys retired objects the GPU is done with, resets its command buffer and begins recording it
    /// (one-time submit). Returns the slot index (0..count-1). The slot stays the next one until submit(): a frame
    /// abandoned after begin() (an error while recording) is simply begun again.
    int begin();
    /// The command buffer of `slot` (recording between begin() and submit()).
    VkCommandBuffer command_buffer(int slot) const { return slots_.at(static_cast<std::size_t>(slot)).cmd; }
    /// Ends recording of the slot begin() returned and submits it with the slot's fence. Returns the new frame's
    /// number. Throws tridex::Error on a Vulkan failure.
    std::uint64_t submit(int slot);
    /// Waits (at most 10 s) until frame `frame` (a number submit() returned, or any earlier one) has finished.
    void wait(std::uint64_t frame);
    /// Waits for every submitted frame.
    void wait_all() { wait(submitted_); }
    /// True when frame `frame` has finished (frames are finished in order; polls the fences without waiting).
    bool finished(std::uint64_t frame);
    /// Number of the last frame submitted (0 = none).
    std::uint64_t submitted() const { return submitted_; }
    /// The frame number `slot` last submitted (0 = never used).
    std::uint64_t frame_of(int slot) const { return slots_.at(static_cast<std::size_t>(slot)).frame; }
    /// Keeps `object` alive until every frame submitted so far has finished, then destroys it (in a later begin(),
    /// wait() or the destructor). For GPU resources replaced while earlier frames may still read them.
    template <typename T>
    void retire(T&& object) {
        retired_.emplace_back(submitted_, std::make_shared<std::decay_t<T>>(std::forward<T>(object)));
    }
    /// Objects waiting in retire() (for tests and statistics).
    std::size_t retired_pending() const { return retired_.size(); }

private:
    struct Slot {
        gpu::UniqueHandle<VkCommandPool, vkDestroyCommandPool> pool;
        VkCommandBuffer cmd = VK_NULL_HANDLE;  // freed with the pool
        gpu::UniqueFence fence;
        std::uint64_t frame = 0;
    };
    void wait_slot(Slot& s);
    void collect();
    const gpu::Context* context_ = nullptr;
    std::vector<Slot> slots_;
    std::size_t next_ = 0;
    std::uint64_t submitted_ = 0, finished_ = 0;
    std::vector<std::pair<std::uint64_t, std::shared_ptr<void>>> retired_;  // (last frame that may use it, object)
};

}  // namespace tridex::renderer
