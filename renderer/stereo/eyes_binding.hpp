// renderer/stereo/eyes_binding.hpp - the per-frame EyesUniform buffer and its descriptor set.
#pragma once

#include <vulkan/vulkan.h>

#include "gpu/buffer.hpp"
#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"
#include "renderer/stereo/stereo_uniforms.hpp"

namespace tridex::renderer {

/// A host-visible uniform buffer holding one EyesUniform, a descriptor pool and one descriptor set
/// (layout `set_layout`, binding 0) pointing at it. Move-only; write() before recording a frame, and not
/// while an earlier submission that reads it is still running.
class EyesBinding {
public:
    /// Throws tridex::Error on a Vulkan failure.
    static EyesBinding create(const gpu::Context& context, VkDescriptorSetLayout set_layout);
    /// Copies `eyes` into the uniform buffer.
    void write(const EyesUniform& eyes) { buffer_.write(&eyes, sizeof eyes); }
    VkDescriptorSet set() const { return set_; }
    /// The uniform buffer (sizeof(EyesUniform) bytes), e.g. for another descriptor set that reads it.
    VkBuffer buffer() const { return buffer_.handle(); }

private:
    gpu::Buffer buffer_;
    gpu::UniqueDescriptorPool pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;  // freed with the pool
};

}  // namespace tridex::renderer
