// renderer/stereo_frame.hpp - recording one stereo frame's draws for any eye strategy.
#pragma once

#include <cstdint>
#include <span>

#include <vulkan/vulkan.h>

#include "renderer/stereo_pipeline.hpp"
#include "renderer/stereo_target.hpp"
#include "renderer/stereo_uniforms.hpp"

namespace tridex::renderer {

/// One indexed draw (uint32 indices, MeshVertex vertices) seen by both eyes.
struct StereoDraw {
    PipelineKind kind = PipelineKind::kOpaque;
    VkBuffer vertices = VK_NULL_HANDLE;
    VkBuffer indices = VK_NULL_HANDLE;
    std::uint32_t index_count = 0;
    DrawConstants constants;  ///< `eye` is overwritten per pass for kPassPerEye
};

/// Records into `cmd` (in the recording state): the strategy's render pass instance(s) over `target`
/// clearing colour to `clear_rgba` (linear, 0..1) and depth to 1, `draws` in order for both eyes
/// (pass-per-eye: each draw once per pass with constants.eye = pass; multiview: once, the view mask
/// replicates it; instanced-layer: once with 2 instances), then the copy of both colour layers into the
/// target's readback buffer followed by a transfer -> host barrier. `eyes` is a descriptor set for
/// pipeline.set_layout() holding the EyesUniform.
void record_stereo_frame(VkCommandBuffer cmd, const StereoPipeline& pipeline, const StereoTarget& target,
                         VkDescriptorSet eyes, std::span<const StereoDraw> draws, const float clear_rgba[4]);

}  // namespace tridex::renderer
