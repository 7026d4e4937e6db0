// renderer/stereo/ambient_occlusion.hpp - screen-space volumetric obscurance of a stereo target's opaque phase.
#pragma once

#include <cstdint>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"
#include "renderer/stereo/stereo_target.hpp"

namespace tridex::renderer {

/// The compute pass that shades a stereo target's colour layers by how enclosed each opaque pixel is, read from
/// its depth layers (shaders/stereo_ao.comp; Loos and Sloan, "Volumetric Obscurance", I3D 2010): concave cuts
/// (a groove's floor, the foot of a ridge) darken, convex edges and crests brighten, flat faces keep their
/// colour. The sphere radius (m) and strength come from EyesUniform::occlusion, the eyes' inverse projections
/// from EyesUniform::view_from_clip / pixels_per_metre. Bound to one StereoTarget and one EyesUniform buffer.
/// Move-only; the Context, the target and the buffer must outlive it.
class AmbientOcclusion {
public:
    AmbientOcclusion() = default;
    /// Builds the pipeline and a descriptor set over `target` (depth sampled, colour as storage image) and the
    /// uniform buffer `eyes` (one EyesUniform). Throws tridex::Error on a Vulkan failure.
    static AmbientOcclusion create(const gpu::Context& context, const StereoTarget& target, VkBuffer eyes);

    /// Records the dispatch over layers first_layer .. first_layer + layer_count - 1 (0..2; one layer is bound
    /// through single-layer views, so the other may be in any layout). Those colour layers
    /// must be in GENERAL and the depth layers in DEPTH_STENCIL_READ_ONLY_OPTIMAL with the depth writes made
    /// visible to compute reads; the caller makes the colour writes visible to what reads them next (the
    /// stereo render passes' external dependencies do both).
    void record(VkCommandBuffer cmd, std::uint32_t first_layer, std::uint32_t layer_count) const;

    bool valid() const { return pipeline_.get() != VK_NULL_HANDLE; }  ///< false when default-constructed

private:
    using UniqueSampler = gpu::UniqueHandle<VkSampler, vkDestroySampler>;
    int width_ = 0, height_ = 0;
    gpu::UniqueDescriptorSetLayout set_layout_;
    gpu::UniquePipelineLayout layout_;
    gpu::UniquePipeline pipeline_;
    UniqueSampler sampler_;
    gpu::UniqueDescriptorPool pool_;
    VkDescriptorSet sets_[3] = {};  // both layers, layer 0 only, layer 1 only; freed with the pool
};

}  // namespace tridex::renderer
