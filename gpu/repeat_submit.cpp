// gpu/repeat_submit.cpp - RepeatSubmitter: record, submit, wait, with objects made once.
#include "gpu/repeat_submit.hpp"

#include <chrono>
#include <thread>

#include "core/error.hpp"
#include "gpu/check.hpp"

namespace tridex::gpu {
namespace {
constexpr std::uint64_t kTimeoutNs = 60'000'000'000ull;
}  // namespace

RepeatSubmitter::RepeatSubmitter(const Context& context, FenceWait wait) : context_(context), wait_(wait) {
    const VkDevice dev = context.device();
    pool_ = make_command_pool(context, VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT);
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = pool_.get();
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    check(vkAllocateCommandBuffers(dev, &alloc, &cmd_), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fence{};
    fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    VkFence f = VK_NULL_HANDLE;
    check(vkCreateFence(dev, &fence, nullptr, &f), "vkCreateFence");
    fence_ = UniqueFence(dev, f);
}

RepeatSubmitter::~RepeatSubmitter() = default;  // run() never returns with the buffer pending

void RepeatSubmitter::run(const std::function<void(VkCommandBuffer)>& record) {
    const VkDevice dev = context_.device();
    check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd_, &begin), "vkBeginCommandBuffer");
    try {
        record(cmd_);
    } catch (...) {
        vkEndCommandBuffer(cmd_);
        throw;
    }
    check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd_;
    const VkFence fence = fence_.get();
    context_.queue_submit(submit, fence);
    VkResult r = VK_NOT_READY;
    if (wait_ == FenceWait::kPoll) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::nanoseconds(kTimeoutNs);
        while ((r = check(vkGetFenceStatus(dev, fence), "vkGetFenceStatus")) == VK_NOT_READY) {
            if (std::chrono::steady_clock::now() > deadline) {
                r = VK_TIMEOUT;
                break;
            }
            std::this_thread::yield();
        }
    } else {
        r = check(vkWaitForFences(dev, 1, &fence, VK_TRUE, kTimeoutNs), "vkWaitForFences");
    }
    if (r == VK_TIMEOUT) {
        context_.wait_idle();  // the buffer must not be reset or freed while pending
        check(vkResetFences(dev, 1, &fence), "vkResetFences");
        throw Error("gpu: a submitted command buffer did not finish within 60 s");
    }
    check(vkResetFences(dev, 1, &fence), "vkResetFences");
}

}  // namespace tridex::gpu
