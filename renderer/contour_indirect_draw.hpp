// renderer/contour_indirect_draw.hpp - offscreen drawing of a tiled surface that lives in GPU buffers
// (as compute/gpu_contourer.hpp fills them) with one indexed indirect draw per tile: no CPU copy.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <vulkan/vulkan.h>

#include "core/math.hpp"
#include "gpu/context.hpp"
#include "renderer/image.hpp"

namespace tridex::renderer {

/// One vertex as the GPU contourer writes it (16 bytes): position in grid units, material id.
struct ContourDrawVertex {
    float grid[3];
    std::uint32_t material;
};
static_assert(sizeof(ContourDrawVertex) == 16);

/// The device buffers of a tiled surface: `draw_count` VkDrawIndexedIndirectCommand records (stride 20
/// bytes) in `commands`, whose firstIndex / vertexOffset address `indices` (uint32) and `vertices`
/// (ContourDrawVertex). Records with indexCount 0 draw nothing.
struct IndirectSurface {
    VkBuffer vertices = VK_NULL_HANDLE;
    VkBuffer indices = VK_NULL_HANDLE;
    VkBuffer commands = VK_NULL_HANDLE;
    std::uint32_t draw_count = 0;
};

/// A small mono offscreen renderer for such surfaces: width x height RGBA8 colour + 32-bit depth, facets
/// flat-shaded (normal from screen-space derivatives, one fixed light), colour per material id
/// (shaders/dexel_contour_draw.*). Draws either the device buffers with vkCmdDrawIndexedIndirect (one
/// call per record: the gpu::Context does not enable multiDrawIndirect) or, as the reference, host arrays
/// in the same vertex format with vkCmdDrawIndexed; both through the same pipeline, so the images of the
/// same triangles are the same. The StereoRenderer's lit, per-vertex-normal pipeline does not draw these
/// buffers (they carry no normals). Move-only; the Context must outlive it; render calls are synchronous.
class ContourIndirectRenderer {
public:
    /// Builds the render pass, target and pipeline. Throws tridex::Error when width/height are outside
    /// 1..4096 or on a Vulkan failure.
    static ContourIndirectRenderer create(const gpu::Context& context, int width, int height);
    ~ContourIndirectRenderer();
    ContourIndirectRenderer(ContourIndirectRenderer&&) noexcept;
    ContourIndirectRenderer& operator=(ContourIndirectRenderer&&) noexcept;

    /// Draws `surface` (its buffers must stay alive and unchanged until this returns) with clip_from_grid
    /// (projection * view * world_from_grid, Vulkan clip space, depth 0..1) and reads the image back.
    /// Throws tridex::Error when a buffer handle is null while draw_count > 0, or on a Vulkan failure.
    Image render_indirect(const IndirectSurface& surface, const glm::mat4& clip_from_grid);
    /// Draws the triangle list (`vertices`, `indices`, uint32, 3 per triangle) the same way, uploaded
    /// through a host buffer, with one vkCmdDrawIndexed. Throws tridex::Error when an index is out of range
    /// or indices.size() is not a multiple of 3.
    Image render_direct(std::span<const ContourDrawVertex> vertices, std::span<const std::uint32_t> indices,
                        const glm::mat4& clip_from_grid);

private:
    struct Impl;
    explicit ContourIndirectRenderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace tridex::renderer
