// renderer/scene/tile_mesh_cache.cpp - version-checked tile uploads.
#include "renderer/scene/tile_mesh_cache.hpp"

#include <string>

#include "core/error.hpp"

namespace tridex::renderer {

std::size_t TileMeshCache::sync(const gpu::Context& context, std::span<const TileMesh> tiles,
                                std::vector<GpuMesh>* retired) {
    ++syncs_;
    order_.clear();
    if (!pool_) pool_ = gpu::BufferPool::create(context);
    std::size_t uploads = 0;
    for (std::size_t i = 0; i < tiles.size(); ++i) {
        const TileMesh& t = tiles[i];
        const std::uint64_t key = t.id == TileMesh::kIdFromPosition ? i : t.id;
        auto [it, fresh] = entries_.try_emplace(key);
        if (fresh) it->second = std::make_unique<Entry>();
        Entry& e = *it->second;
        if (!fresh && e.seen == syncs_) {
            order_.clear();
            throw Error("renderer: SceneView.tiles lists tile id " + std::to_string(key) + " twice");
        }
        e.seen = syncs_;
        if (fresh || e.version != t.version) {
            try {
                static const TriMesh kEmpty;
                const TriMesh& mesh = t.mesh ? *t.mesh : kEmpty;
                std::span<const std::uint8_t> materials;
                if (t.materials) materials = *t.materials;
                if (retired && !fresh) {  // new buffers: earlier frames may still read the old ones
                    GpuMesh next;
                    next.assign(context, mesh, materials, pool_.get());
                    retired->push_back(std::move(e.mesh));
                    e.mesh = std::move(next);
                } else {
                    e.mesh.assign(context, mesh, materials, pool_.get());
                }
            } catch (const Error& err) {
                entries_.erase(it);
                order_.clear();
                throw Error("SceneView.tiles[" + std::to_string(i) + "]: " + err.what());
            }
            e.version = t.version;
            ++uploads;
        }
        order_.push_back(&e);
    }
    std::erase_if(entries_, [&](const auto& kv) {
        if (kv.second->seen == syncs_) return false;
        if (retired) retired->push_back(std::move(kv.second->mesh));
        return true;
    });
    uploads_total_ += uploads;
    return uploads;
}

const GpuMesh& TileMeshCache::mesh(std::size_t i) const {
    if (i >= order_.size())
        throw Error("TileMeshCache::mesh: index " + std::to_string(i) + " >= " + std::to_string(order_.size()));
    return order_[i]->mesh;
}

}  // namespace tridex::renderer
