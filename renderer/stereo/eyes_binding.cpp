// renderer/stereo/eyes_binding.cpp - uniform buffer + descriptor set for the two eyes.
#include "renderer/stereo/eyes_binding.hpp"

#include "gpu/check.hpp"
#include "gpu/descriptor_sets.hpp"

namespace tridex::renderer {

EyesBinding EyesBinding::create(const gpu::Context& context, VkDescriptorSetLayout set_layout) {
    const VkDevice device = context.device();
    EyesBinding b;
    b.buffer_ = gpu::Buffer::create(context, sizeof(EyesUniform), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                    gpu::MemoryDomain::kHost);
    b.pool_ = gpu::allocate_descriptor_sets(device, {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1}}, set_layout, 1, &b.set_);

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
