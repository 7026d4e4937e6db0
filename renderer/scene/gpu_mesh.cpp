// renderer/scene/gpu_mesh.cpp - TriMesh -> vertex/index buffers.
#include "renderer/scene/gpu_mesh.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "renderer/scene/mesh_vertex.hpp"

namespace tridex::renderer {

void GpuMesh::assign(const gpu::Context& context, const TriMesh& mesh, std::span<const std::uint8_t> materials,
                     std::span<const Vec3> given_normals, gpu::BufferPool* pool, const ModelFrame& frame) {
    const std::size_t nv = mesh.positions.size();
    if (!std::isfinite(frame.unit_m) || !(frame.unit_m > 0.0) || !is_finite(frame.origin_m))
        throw Error("renderer: mesh frame unit_m must be finite and > 0 and origin_m finite");
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::uint32_t i : mesh.triangles[t])
            if (i >= nv)
                throw Error("renderer: mesh triangle " + std::to_string(t) + " has vertex index " + std::to_string(i) +
                            " >= vertex count " + std::to_string(nv));
    for (std::size_t v = 0; v < nv; ++v)
        if (!is_finite(mesh.positions[v]))
            throw Error("renderer: mesh vertex " + std::to_string(v) + " is not finite");
    if (!materials.empty() && materials.size() != nv)
        throw Error("renderer: mesh materials has " + std::to_string(materials.size()) +
                    " entries, expected 0 or one per vertex (" + std::to_string(nv) + ")");
    for (std::size_t v = 0; v < materials.size(); ++v)
        if (materials[v] >= kMaterialCount)
            throw Error("renderer: mesh vertex " + std::to_string(v) + " has material id " +
                        std::to_string(materials[v]) + " >= " + std::to_string(kMaterialCount));
    if (!given_normals.empty() && given_normals.size() != nv)
        throw Error("renderer: mesh normals has " + std::to_string(given_normals.size()) +
                    " entries, expected 0 or one per vertex (" + std::to_string(nv) + ")");
    for (std::size_t v = 0; v < given_normals.size(); ++v)
        if (!is_finite(given_normals[v])) throw Error("renderer: mesh normal " + std::to_string(v) + " is not finite");
    index_count_ = 0;
    if (mesh.triangles.empty()) return;

    const std::vector<Vec3> normals =
        given_normals.empty() ? vertex_normals(mesh) : std::vector<Vec3>(given_normals.begin(), given_normals.end());
    const VkDeviceSize vbytes = nv * sizeof(MeshVertex);
    const VkDeviceSize ibytes = mesh.triangles.size() * 3 * sizeof(std::uint32_t);
    void* vmap = nullptr;
    void* imap = nullptr;
    if (pool) {
        vertices_ = gpu::Buffer{};
        indices_ = gpu::Buffer{};
        if (pooled_vertices_.size() < vbytes)
            pooled_vertices_ = pool->allocate(vbytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, sizeof(MeshVertex));
        if (pooled_indices_.size() < ibytes)
            pooled_indices_ = pool->allocate(ibytes, VK_BUFFER_USAGE_INDEX_BUFFER_BIT, sizeof(std::uint32_t));
        vmap = pooled_vertices_.mapped();
        imap = pooled_indices_.mapped();
    } else {
        pooled_vertices_ = gpu::PooledBuffer{};
        pooled_indices_ = gpu::PooledBuffer{};
        if (vertices_.size() < vbytes)
            vertices_ =
                gpu::Buffer::create(context, vbytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, gpu::MemoryDomain::kHost);
        if (indices_.size() < ibytes)
            indices_ = gpu::Buffer::create(context, ibytes, VK_BUFFER_USAGE_INDEX_BUFFER_BIT, gpu::MemoryDomain::kHost);
        vmap = vertices_.mapped();
        imap = indices_.mapped();
    }
    auto* out = static_cast<MeshVertex*>(vmap);
    const bool identity = frame == ModelFrame{};
    for (std::size_t v = 0; v < nv; ++v)
        out[v] =
            MeshVertex{glm::vec3(identity ? mesh.positions[v] : (mesh.positions[v] - frame.origin_m) / frame.unit_m),
                       glm::vec3(normals[v]), materials.empty() ? 0u : static_cast<std::uint32_t>(materials[v])};
    auto* idx = static_cast<std::uint32_t*>(imap);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) idx[t * 3 + k] = mesh.triangles[t][k];
    index_count_ = static_cast<std::uint32_t>(mesh.triangles.size() * 3);
}

GpuMesh::DrawRange GpuMesh::draw_range() const {
    DrawRange r{vertices(), indices(), 0, 0};
    const VkBuffer shared_v = pooled_vertices_.block_buffer(), shared_i = pooled_indices_.block_buffer();
    if (shared_v != VK_NULL_HANDLE && pooled_vertices_.offset() % sizeof(MeshVertex) == 0) {
        r.vertices = shared_v;
        r.vertex_offset = static_cast<std::int32_t>(pooled_vertices_.offset() / sizeof(MeshVertex));
    }
    if (shared_i != VK_NULL_HANDLE && pooled_indices_.offset() % sizeof(std::uint32_t) == 0) {
        r.indices = shared_i;
        r.first_index = static_cast<std::uint32_t>(pooled_indices_.offset() / sizeof(std::uint32_t));
    }
    return r;
}

}  // namespace tridex::renderer
