// renderer/stereo/stereo_pipeline.hpp - render pass, layouts and graphics pipelines for one eye strategy.
#pragma once

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"
#include "renderer/stereo/eye_strategy.hpp"

namespace tridex::renderer {

/// Attachment formats of every stereo target.
constexpr VkFormat kStereoColourFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kStereoDepthFormat = VK_FORMAT_D32_SFLOAT;

/// Which pipeline state a draw uses.
enum class PipelineKind {
    kOpaque,            ///< depth test + write, back faces culled, no blending
    kTranslucentBack,   ///< depth test, no depth write, front faces culled, alpha blending (draw first)
    kTranslucentFront,  ///< depth test, no depth write, back faces culled, alpha blending (draw second)
    kOverlay,           ///< no depth test or write, no culling, alpha blending (screen-space overlay, drawn last)
    /// As kOpaque, for the GPU contour's vertex buffers (ContourVertexInput: grid position + material, no
    /// normal; shaders stereo_contour_*: flat shading from screen-space derivatives), drawn indirectly.
    kContour,
};

/// Number of PipelineKind values.
constexpr int kPipelineKindCount = 5;

/// The GPU state shared by all frames of one eye strategy: two compatible render passes (with a view mask 0b11
/// for kMultiview): render_pass() for the opaque phase (colour RGBA8 and depth D32 cleared and stored, colour
/// left in GENERAL and depth in DEPTH_STENCIL_READ_ONLY_OPTIMAL for the ambient-occlusion compute pass), and
/// resume_pass() for the translucent and overlay phases (both loaded, colour left in TRANSFER_SRC_OPTIMAL for
/// readback and blits); framebuffers and pipelines made with render_pass() serve both;
/// the descriptor set layout (set 0 binding 0: EyesUniform), a pipeline layout with the DrawConstants
/// push range, and one pipeline per PipelineKind using shaders/stereo_mesh.* in the strategy's variant
/// (vertex input: MeshVertex, locations 0 position, 1 normal, 2 material id; kContour: 16-byte vertices of
/// the GPU contour, location 0 grid position, 2 material id, shaders stereo_contour_* in the same variant).
/// Viewport and scissor are dynamic. Move-only; the Context must outlive it.
class StereoPipeline {
public:
    /// Builds everything for `strategy`. Throws tridex::Error when the context does not support the
    /// strategy (see supported()) or on a Vulkan failure.
    static StereoPipeline create(const gpu::Context& context, EyeStrategy strategy);

    EyeStrategy strategy() const { return strategy_; }
    VkRenderPass render_pass() const { return render_pass_.get(); }  ///< the opaque phase's render pass
    VkRenderPass resume_pass() const { return resume_pass_.get(); }  ///< translucent + overlay phases
    VkDescriptorSetLayout set_layout() const { return set_layout_.get(); }
    VkPipelineLayout layout() const { return layout_.get(); }
    /// The pipeline for one kind of draw.
    VkPipeline pipeline(PipelineKind kind) const { return pipelines_[static_cast<int>(kind)].get(); }

private:
    EyeStrategy strategy_ = EyeStrategy::kPassPerEye;
    gpu::UniqueRenderPass render_pass_, resume_pass_;
    gpu::UniqueDescriptorSetLayout set_layout_;
    gpu::UniquePipelineLayout layout_;
    gpu::UniquePipeline pipelines_[kPipelineKindCount];
};

}  // namespace tridex::renderer
