// gpu/unique_handle.hpp - move-only ownership of one device-level Vulkan object.
#pragma once

#include <utility>

#include <vulkan/vulkan.h>

namespace tridex::gpu {

/// Owns a non-dispatchable handle T created on `device` and destroys it with Destroy
/// (vkDestroyPipeline, vkDestroyRenderPass, ...) when it goes out of scope. Move-only.
/// A default-constructed or moved-from handle owns nothing.
template <typename T, void (*Destroy)(VkDevice, T, const VkAllocationCallbacks*)>
class UniqueHandle {
public:
    UniqueHandle() = default;
    /// Takes ownership of `handle` (may be VK_NULL_HANDLE) created on `device`.
    UniqueHandle(VkDevice device, T handle) : device_(device), handle_(handle) {}
    ~UniqueHandle() { reset(); }
    UniqueHandle(UniqueHandle&& o) noexcept
        : device_(o.device_), handle_(std::exchange(o.handle_, static_cast<T>(VK_NULL_HANDLE))) {}
    UniqueHandle& operator=(UniqueHandle&& o) noexcept {
        if (this != &o) {
            reset();
            device_ = o.device_;
            handle_ = std::exchange(o.handle_, static_cast<T>(VK_NULL_HANDLE));
        }
        return *this;
    }
    UniqueHandle(const UniqueHandle&) = delete;
    UniqueHandle& operator=(const UniqueHandle&) = delete;

    /// The owned handle (VK_NULL_HANDLE when empty).
    T get() const { return handle_; }
    /// Destroys the owned object now (no-op when empty).
    void reset() {
        if (handle_ != VK_NULL_HANDLE) Destroy(device_, handle_, nullptr);
        handle_ = VK_NULL_HANDLE;
    }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    T handle_ = VK_NULL_HANDLE;
};

using UniquePipeline = UniqueHandle<VkPipeline, vkDestroyPipeline>;
using UniquePipelineLayout = UniqueHandle<VkPipelineLayout, vkDestroyPipelineLayout>;
using UniqueRenderPass = UniqueHandle<VkRenderPass, vkDestroyRenderPass>;
using UniqueFramebuffer = UniqueHandle<VkFramebuffer, vkDestroyFramebuffer>;
using UniqueImageView = UniqueHandle<VkImageView, vkDestroyImageView>;
using UniqueDescriptorSetLayout = UniqueHandle<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using UniqueDescriptorPool = UniqueHandle<VkDescriptorPool, vkDestroyDescriptorPool>;
using UniqueShaderModule = UniqueHandle<VkShaderModule, vkDestroyShaderModule>;
using UniqueFence = UniqueHandle<VkFence, vkDestroyFence>;
using UniqueQueryPool = UniqueHandle<VkQueryPool, vkDestroyQueryPool>;

}  // namespace tridex::gpu
