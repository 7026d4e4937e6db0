// renderer/scene/gpu_mesh.hpp - a TriMesh's vertices (position + normal + material, float) and indices in
// host-visible buffers.
#pragma once

#include <cstdint>
#include <span>

#include "core/tri_mesh.hpp"
#include "gpu/buffer.hpp"
#include "gpu/buffer_pool.hpp"
#include "gpu/context.hpp"

namespace tridex::renderer {

/// How a mesh's vertex positions are stored: (p - origin_m) / unit_m in float, p in world m. The default stores
/// world m; with another frame a draw needs world_from_model = translate(origin_m) * scale(unit_m). Storing a
/// lattice's grid units lets a mesh meet the GPU contour's tiles (drawn through world_from_grid) with bit-identical
/// vertices: a float grid position turned into world m in double and back gives the same float.
struct ModelFrame {
    Vec3 origin_m{0.0};
    double unit_m = 1.0;  ///< > 0 and finite
    bool operator==(const ModelFrame&) const = default;
};

/// Vertex (MeshVertex: position m, area-weighted unit normal from core vertex_normals, material id) and
/// uint32 index buffers of one mesh, host-visible so they can be refilled every frame: each buffer with its own
/// memory (MemoryDomain::kHost), or sub-allocated from a gpu::BufferPool (per-tile meshes: thousands of them
/// would exceed a real GPU's allocation limit). Buffers grow (never shrink) when a larger mesh is assigned.
/// Move-only; a pool it was given must outlive it.
class GpuMesh {
public:
    /// Copies `mesh` (positions converted to float) into the buffers, growing them when needed.
    /// `materials` is empty (every vertex gets material 0) or holds one material id per vertex
    /// (0..kMaterialCount-1, see material_palette.hpp). An empty mesh gives index_count() == 0.
    /// Throws tridex::Error when a triangle index is out of range, a position is not finite (naming the
    /// triangle / vertex), materials.size() is neither 0 nor the vertex count, or a material id is out of
    /// range (naming the vertex), or on a Vulkan failure. Not safe while the GPU still reads the buffers
    /// from an earlier submission. `normals` is empty (area-weighted normals of `mesh`) or one unit normal per
    /// vertex to use instead (e.g. a simplified mesh shaded with its full mesh's normals); a wrong size or a
    /// non-finite normal throws. With `pool`, new buffers come from it (sub-allocated) instead of their own memory.
    /// `frame` says how positions are stored (ModelFrame; a unit_m that is not finite and > 0 throws).
    void assign(const gpu::Context& context, const TriMesh& mesh, std::span<const std::uint8_t> materials = {},
                std::span<const Vec3> normals = {}, gpu::BufferPool* pool = nullptr, const ModelFrame& frame = {});

    VkBuffer vertices() const { return pooled_vertices_.handle() ? pooled_vertices_.handle() : vertices_.handle(); }
    VkBuffer indices() const { return pooled_indices_.handle() ? pooled_indices_.handle() : indices_.handle(); }
    std::uint32_t index_count() const { return index_count_; }

    /// Where a draw finds this mesh: buffers to bind and the firstIndex / vertexOffset of vkCmdDrawIndexed.
    /// Meshes from one pool block (a pool made with vertex and index block usage) share that block's buffer, so
    /// consecutive draws of them bind nothing new; other meshes are their own buffers at offsets 0.
    struct DrawRange {
        VkBuffer vertices = VK_NULL_HANDLE;
        VkBuffer indices = VK_NULL_HANDLE;
        std::uint32_t first_index = 0;  ///< in indices
        std::int32_t vertex_offset = 0;  ///< in vertices (MeshVertex)
    };
    DrawRange draw_range() const;

private:
    gpu::Buffer vertices_, indices_;
    gpu::PooledBuffer pooled_vertices_, pooled_indices_;
    std::uint32_t index_count_ = 0;
};

}  // namespace tridex::renderer
