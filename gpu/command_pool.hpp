// gpu/command_pool.hpp - owned command pools on the context's queue family.
#pragma once

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"

namespace tridex::gpu {

/// An owned VkCommandPool.
using UniqueCommandPool = UniqueHandle<VkCommandPool, vkDestroyCommandPool>;

/// Creates a command pool with `flags` (VK_COMMAND_POOL_CREATE_*_BIT) on `context`'s queue family. Throws
/// tridex::Error naming vkCreateCommandPool and the result when Vulkan refuses.
UniqueCommandPool make_command_pool(const Context& context, VkCommandPoolCreateFlags flags);

}  // namespace tridex::gpu
