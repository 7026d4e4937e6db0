// renderer/stereo/ambient_occlusion.hpp - screen-space volumetric obscurance of a stereo target's opaque phase.
#pragma once

#include <cstdint>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "gpu/image_array.hpp"
#include "gpu/unique_handle.hpp"
#include "renderer/stereo/screen_region.hpp"
#include "renderer/stereo/stereo_target.hpp"

namespace tridex::renderer {

/// How finely AmbientOcclusion evaluates the obscurance: once per 2x2 pixel block (kHalf, the default) or per 4x4
/// block (kQuarter: about a quarter of the first dispatch's work, softer detail; the upsampling keeps silhouettes).
enum class OcclusionResolution { kHalf, kQuarter };

/// The compute passes that shade a stereo target's colour layers by how enclosed each opaque pixel is, read from
/// its depth layers (Loos and Sloan, "Volumetric Obscurance", I3D 2010): concave cuts (a groove's floor, the foot
/// of a ridge) darken, convex edges and crests brighten, flat faces keep their colour. Two dispatches per record():
/// shaders/stereo_ao.comp evaluates the obscurance once per 2x2 (or 4x4, OcclusionResolution) pixel block (8 line
/// samples in 4 symmetric pairs) into an image the pass owns, then shaders/stereo_ao_apply.comp scales every
/// covered pixel by a depth-aware bilinear blend of the four values around it. The sphere radius (m) and strength
/// come from EyesUniform::occlusion, the eyes' inverse projections from EyesUniform::view_from_clip /
/// pixels_per_metre. Bound to one StereoTarget at a time (retarget()) and one EyesUniform buffer; frames in flight
/// may share it (record() orders its own image's reuse after earlier dispatches). Move-only; the Context, the target
/// and the buffer must outlive it.
class AmbientOcclusion {
public:
    AmbientOcclusion() = default;
    /// Builds the pipelines, the half-resolution image (RGBA16F, ceil(width / 2) x ceil(height / 2), 2 layers) and
    /// descriptor sets over `target` (depth sampled, colour as storage image), that image and the uniform buffer
    /// `eyes` (one EyesUniform). Throws tridex::Error on a Vulkan failure.
    static AmbientOcclusion create(const gpu::Context& context, const StereoTarget& target, VkBuffer eyes);
    /// Binds it to `target` instead (a resized one, which must outlive it): a new half-resolution image of its size,
    /// and the descriptor sets rewritten; the pipelines are kept (building them is most of create()'s cost). No
    /// recorded dispatch of it may still be pending. Throws tridex::Error for one not made by create() (valid()) or
    /// on a Vulkan failure, and stays bound to the old target then.
    void retarget(const gpu::Context& context, const StereoTarget& target);

    /// Records the two dispatches over layers first_layer .. first_layer + layer_count - 1 (0..2; one layer is bound
    /// through single-layer views, so the other may be in any layout). Those colour layers
    /// must be in GENERAL and the depth layers in DEPTH_STENCIL_READ_ONLY_OPTIMAL with the depth writes made
    /// visible to compute reads; the caller makes the colour writes visible to what reads them next (the
    /// stereo render passes' external dependencies do both). Only pixels inside `region` (clamped to the image)
    /// are shaded: it must hold every opaque pixel of those layers (e.g. the union of project_box() of the
    /// opaque draws' bounds); pixels outside keep their colour. Nothing is recorded for an empty region.
    /// `resolution`: one obscurance value per 2x2 or per 4x4 pixels.
    void record(VkCommandBuffer cmd, std::uint32_t first_layer, std::uint32_t layer_count, const PixelRect& region,
                OcclusionResolution resolution = OcclusionResolution::kHalf) const;

    bool valid() const { return pipelines_[0].get() != VK_NULL_HANDLE; }  ///< false when default-constructed

private:
    using UniqueSampler = gpu::UniqueHandle<VkSampler, vkDestroySampler>;
    int width_ = 0, height_ = 0;
    VkBuffer eyes_ = VK_NULL_HANDLE;  // the EyesUniform buffer the sets bind
    gpu::UniqueDescriptorSetLayout set_layout_;
    gpu::UniquePipelineLayout layout_;
    gpu::UniquePipeline pipelines_[2];        // stereo_ao.comp: the obscurance per 2x2 block, per 4x4 block
    gpu::UniquePipeline apply_pipelines_[2];  // stereo_ao_apply.comp: upsample and scale the colour, likewise
    gpu::ImageArray half_;                    // RGBA16F, one layer per eye; its contents last one record()
    UniqueSampler sampler_;
    gpu::UniqueDescriptorPool pool_;
    VkDescriptorSet sets_[3] = {};  // both layers, layer 0 only, layer 1 only; freed with the pool
};

}  // namespace tridex::renderer
