// gpu/descriptor_sets.hpp - a descriptor pool sized for a fixed number of sets of one layout, and those sets.
#pragma once

#include <cstdint>
#include <initializer_list>

#include <vulkan/vulkan.h>

#include "gpu/unique_handle.hpp"

namespace tridex::gpu {

/// Creates a descriptor pool of `count` sets (maxSets = count) with the descriptor counts `sizes` (for all the sets
/// together) and allocates `count` sets of `layout` from it into `sets` (an array of `count` handles, overwritten).
/// The sets live as long as the returned pool. Throws tridex::Error naming the Vulkan call when the device refuses.
UniqueDescriptorPool allocate_descriptor_sets(VkDevice device, std::initializer_list<VkDescriptorPoolSize> sizes,
                                              VkDescriptorSetLayout layout, std::uint32_t count, VkDescriptorSet* sets);

}  // namespace tridex::gpu
