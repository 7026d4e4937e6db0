// gpu/command_pool.cpp - owned command pools on the context's queue family.
#include "gpu/command_pool.hpp"

#include "gpu/check.hpp"

namespace tridex::gpu {

UniqueCommandPool make_command_pool(const Context& context, VkCommandPoolCreateFlags flags) {
    VkCommandPoolCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    info.flags = flags;
    info.queueFamilyIndex = context.queue_family();
    VkCommandPool pool = VK_NULL_HANDLE;
    check(vkCreateCommandPool(context.device(), &info, nullptr, &pool), "vkCreateCommandPool");
    return UniqueCommandPool(context.device(), pool);
}

}  // namespace tridex::gpu
