// renderer/stereo/eyes_binding.cpp - uniform buffer + descriptor set for the two eyes.
#include "renderer/stereo/eyes_binding.hpp"

#include "gpu/check.hpp"

namespace tridex::renderer {

EyesBinding EyesBinding::create(const gpu::Context& context, VkDescriptorSetLayout set_layout) {
    const VkDevice device = context.device();
    EyesBinding b;
    b.buffer_ = gpu::Buffer::create(context, sizeof(EyesUniform), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                    gpu::MemoryDomain::kHost);
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1};
    VkDescriptorPoolCreateInfo pool_info{};
    pool_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &size;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    gpu::check(vkCreateDescriptorPool(device, &pool_info, nullptr, &pool), "vkCreateDescriptorPool");
    b.pool_ = gpu::UniqueDescriptorPool(device, pool);

    VkDescriptorSetAllocateInfo alloc{};

    alloc.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &set_layout;
    gpu::check(vkAllocateDescriptorSets(device, &alloc, &b.set_), "vkAllocateDescriptorSets");

    const VkDescriptorBufferInfo buffer_info{b.buffer_.handle(), 0, sizeof(EyesUniform)};
    VkWriteDescriptorSet write{};
    write.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    write.dstSet = b.set_;
    write.dstBinding = 0;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    write.pBufferInfo = &buffer_info;
    vkUpdateDescriptorSets(device, 1, &write, 0, nullptr);
    EyesUniform zero{};
    b.write(zero);
    return b;
}

}  // namespace tridex::renderer
