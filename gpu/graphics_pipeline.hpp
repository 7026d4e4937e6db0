// gpu/graphics_pipeline.hpp - a graphics pipeline of triangle lists from a vertex and a fragment shader.
#pragma once

#include <cstdint>
#include <span>

#include "gpu/unique_handle.hpp"

namespace tridex::gpu {

/// What varies between tridex's graphics pipelines: shaders, vertex layout, culling, depth and blending, and a
/// fixed or dynamic viewport. Every pipeline draws filled triangle lists, counter-clockwise front faces, one sample,
/// into subpass 0 of a render pass with one colour attachment (RGBA written).
struct GraphicsPipelineDesc {
    VkShaderModule vertex = VK_NULL_HANDLE;    ///< its `main` is the vertex stage
    VkShaderModule fragment = VK_NULL_HANDLE;  ///< its `main` is the fragment stage
    std::span<const VkVertexInputBindingDescription> bindings{};      ///< empty: no vertex buffers
    std::span<const VkVertexInputAttributeDescription> attributes{};  ///< empty: no vertex attributes
    VkCullModeFlags cull = VK_CULL_MODE_NONE;
    /// The render pass has a depth attachment: depth test (VK_COMPARE_OP_LESS) and write as below. false: no
    /// depth-stencil state at all.
    bool depth = false;
    bool depth_test = false;
    bool depth_write = false;
    /// Colour = src * alpha + dst * (1 - alpha), alpha = src + dst * (1 - src alpha); false: colour replaced.
    bool alpha_blend = false;
    /// Viewport and scissor fixed to width x height pixels; both 0: dynamic (set per draw).
    std::uint32_t width = 0, height = 0;
};

/// Creates the pipeline `desc` describes for `pass` (subpass 0) and `layout`. Throws tridex::Error naming the
/// Vulkan call when the device refuses.
UniquePipeline create_graphics_pipeline(VkDevice device, VkRenderPass pass, VkPipelineLayout layout,
                                        const GraphicsPipelineDesc& desc);

}  // namespace tridex::gpu
