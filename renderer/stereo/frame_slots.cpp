// renderer/stereo/frame_slots.cpp - per-frame command buffers and fences, and what waits for them.
#include "renderer/stereo/frame_slots.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "gpu/check.hpp"
#include "gpu/command_pool.hpp"

namespace tridex::renderer {
namespace {

constexpr std::uint64_t kFenceTimeoutNs = 10'000'000'000ull;

}  // namespace

FrameSlots FrameSlots::create(const gpu::Context& context, int count) {
    if (count < 1 || count > 8)
        throw Error("renderer: frames in flight must be 1..8, got " + std::to_string(count));
    const VkDevice device = context.device();
    FrameSlots f;
    f.context_ = &context;
    f.slots_.resize(static_cast<std::size_t>(count));
    for (Slot& s : f.slots_) {
        s.pool = gpu::make_command_pool(context, VK_COMMAND_POOL_CREATE_TRANSIENT_BIT);
        const VkCommandPool pool = s.pool.get();
        VkCommandBufferAllocateInfo alloc{};
        alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
        alloc.commandPool = pool;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        gpu::check(vkAllocateCommandBuffers(device, &alloc, &s.cmd), "vkAllocateCommandBuffers");
        VkFenceCreateInfo fence_info{};
        fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
        fence_info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
        VkFence fence = VK_NULL_HANDLE;
        gpu::check(vkCreateFence(device, &fence_info, nullptr, &fence), "vkCreateFence");
        s.fence = gpu::UniqueFence(device, fence);
    }
    return f;
}

FrameSlots::~FrameSlots() {
    try {
        for (Slot& s : slots_) wait_slot(s);
    } catch (const Error& e) {
        std::fprintf(stderr, "renderer: %s\n", e.what());
        if (context_) context_->wait_idle();
    }
    retired_.clear();
}

void FrameSlots::wait_slot(Slot& s) {
    if (s.frame == 0 || s.frame <= finished_) return;
    const VkFence f = s.fence.get();
    if (gpu::check(vkWaitForFences(context_->device(), 1, &f, VK_TRUE, kFenceTimeoutNs), "vkWaitForFences") ==
        VK_TIMEOUT)
        throw Error("renderer: frame " + std::to_string(s.frame) + " did not finish within 10 s");
    finished_ = std::max(finished_, s.frame);  // one queue: earlier frames finished before it
}

void FrameSlots::collect() {
    std::erase_if(retired_, [&](const auto& r) { return r.first <= finished_; });
}

int FrameSlots::begin() {
    Slot& s = slots_[next_];
    wait_slot(s);
    collect();
    gpu::check(vkResetCommandPool(context_->device(), s.pool.get(), 0), "vkResetCommandPool");
    VkCommandBufferBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    gpu::check(vkBeginCommandBuffer(s.cmd, &begin), "vkBeginCommandBuffer");
    return static_cast<int>(next_);
}

std::uint64_t FrameSlots::submit(int slot) {
    Slot& s = slots_.at(static_cast<std::size_t>(slot));
    gpu::check(vkEndCommandBuffer(s.cmd), "vkEndCommandBuffer");
    const VkFence f = s.fence.get();
    gpu::check(vkResetFences(context_->device(), 1, &f), "vkResetFences");
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &s.cmd;
    context_->queue_submit(submit, s.fence.get());
    s.frame = ++submitted_;
    next_ = (static_cast<std::size_t>(slot) + 1) % slots_.size();
    return s.frame;
}

void FrameSlots::wait(std::uint64_t frame) {
    if (frame <= finished_) return;
    Slot* first = nullptr;  // the slot of the earliest frame at or after `frame`
    for (Slot& s : slots_)
        if (s.frame >= frame && (!first || s.frame < first->frame)) first = &s;
    if (first) wait_slot(*first);
    collect();
}

bool FrameSlots::finished(std::uint64_t frame) {
    if (frame <= finished_) return true;
    for (Slot& s : slots_)
        if (s.frame >= frame && s.frame > finished_ &&
            vkGetFenceStatus(context_->device(), s.fence.get()) == VK_SUCCESS)
            finished_ = std::max(finished_, s.frame);
    return frame <= finished_;
}

}  // namespace tridex::renderer
