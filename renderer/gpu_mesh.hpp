// renderer/gpu_mesh.hpp - a TriMesh's vertices (position + normal, float) and indices in host-visible buffers.
#pragma once

#include <cstdint>

#include "core/tri_mesh.hpp"
#include "gpu/buffer.hpp"
#include "gpu/context.hpp"

namespace tridex::renderer {

/// Vertex (MeshVertex: position m, area-weighted unit normal from core vertex_normals) and uint32 index
/// buffers of one mesh, in MemoryDomain::kHost so they can be refilled every frame. Buffers grow (never
/// shrink) when a larger mesh is assigned. Move-only.
class GpuMesh {
public:
    /// Copies `mesh` (positions converted to float) into the buffers, growing them when needed.
    /// An empty mesh gives index_count() == 0. Throws tridex::Error when a triangle index is out of
    /// range or a position is not finite (naming the triangle / vertex), or on a Vulkan failure.
    /// Not safe while the GPU still reads the buffers from an earlier submission.
    void assign(const gpu::Context& context, const TriMesh& mesh);

    VkBuffer vertices() const { return vertices_.handle(); }
    VkBuffer indices() const { return indices_.handle(); }
    std::uint32_t index_count() const { return index_count_; }

private:
    gpu::Buffer vertices_, indices_;
    std::uint32_t index_count_ = 0;
};

}  // namespace tridex::renderer
