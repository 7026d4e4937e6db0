// gpu/compute_pipeline.hpp - the layout and pipeline of a compute shader that reads and writes storage buffers.
#pragma once

#include <cstdint>

#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"

namespace tridex::gpu {

/// A descriptor-set layout of storage (and optionally uniform) buffers and the pipeline layout built on it.
struct ComputeLayout {
    UniqueDescriptorSetLayout set_layout;   ///< bindings 0 .. storage_buffers-1, one buffer each
    UniquePipelineLayout pipeline_layout;   ///< that set (set 0) plus the push-constant range
};

/// The layout of a compute shader whose set 0 holds `storage_buffers` storage buffers at bindings
/// 0 .. storage_buffers-1 (compute stage) and which takes `push_bytes` bytes of push constants (0 = none).
/// Bindings whose bit is set in `uniform_bindings` (bit i = binding i) are uniform buffers instead
/// (llvmpipe loads those with vector gathers, storage buffers one lane at a time).
/// Bindings whose bit is set in `array_bindings` hold `array_size` descriptors (an array of buffers), the
/// others one.
/// Throws tridex::Error naming the Vulkan call when the device refuses.
ComputeLayout create_compute_layout(const Context& context, std::uint32_t storage_buffers, std::uint32_t push_bytes,
                                    std::uint32_t uniform_bindings = 0, std::uint32_t array_bindings = 0,
                                    std::uint32_t array_size = 1);

/// A compute pipeline running `module`'s `main` with `layout`, specialised by `spec` (nullptr = none).
/// Throws tridex::Error naming the Vulkan call when the device refuses.
UniquePipeline create_compute_pipeline(const Context& context, VkShaderModule module, VkPipelineLayout layout,
                                       const VkSpecializationInfo* spec = nullptr);

}  // namespace tridex::gpu
