// gpu/barrier.hpp - image layout transitions recorded into a command buffer.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>

namespace tridex::gpu {

/// Records one image memory barrier on the colour aspect of `image` (mip 0, array layers 0 .. layers-1): layout
/// `from` -> `to`, making `src_access` writes at `src_stage` available to `dst_access` at `dst_stage`; no queue
/// family transfer. `cmd` must be recording.
void image_barrier(VkCommandBuffer cmd, VkImage image, std::uint32_t layers, VkImageLayout from, VkImageLayout to,
                   VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                   VkPipelineStageFlags dst_stage);

}  // namespace tridex::gpu
