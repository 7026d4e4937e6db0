// gpu/descriptor_sets.cpp - a descriptor pool and its sets of one layout.
#include "gpu/descriptor_sets.hpp"

#include <vector>

#include "gpu/check.hpp"

namespace tridex::gpu {

UniqueDescriptorPool allocate_descriptor_sets(VkDevice device, std::initializer_list<VkDescriptorPoolSize> sizes,
                                              VkDescriptorSetLayout layout, std::uint32_t count, VkDescriptorSet* sets) {
    VkDescriptorPoolCreateInfo pi{};
    pi.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    pi.maxSets = count;
    pi.poolSizeCount = static_cast<std::uint32_t>(sizes.size());
    pi.pPoolSizes = sizes.begin();
    VkDescriptorPool raw = VK_NULL_HANDLE;
    check(vkCreateDescriptorPool(device, &pi, nullptr, &raw), "vkCreateDescriptorPool");
    UniqueDescriptorPool pool(device, raw);
    const std::vector<VkDescriptorSetLayout> layouts(count, layout);
    VkDescriptorSetAllocateInfo ai{};
    ai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    ai.descriptorPool = raw;
    ai.descriptorSetCount = count;
    ai.pSetLayouts = layouts.data();
    check(vkAllocateDescriptorSets(device, &ai, sets), "vkAllocateDescriptorSets");
    return pool;
}

}  // namespace tridex::gpu
