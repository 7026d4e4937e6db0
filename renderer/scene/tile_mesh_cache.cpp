// renderer/scene/tile_mesh_cache.cpp - version-checked tile uploads.
#include "renderer/scene/tile_mesh_cache.hpp"

#include <string>

#include "core/error.hpp"

namespace tridex::renderer {

std::size_t TileMeshCache::sync(const gpu::Context& context, std::span<const TileMesh> tiles,
                                std::vector<GpuMesh>* retired, const ModelFrame& frame) {
    ++syncs_;
    if (!(frame == frame_)) {  // every mesh stored in the old frame goes
        for (auto& kv : entries_)
            if (retired) {
                retired->push_back(std::move(kv.second->mesh));
                for (GpuMesh& l : kv.second->levels) retired->push_back(std::move(l));
            }
        entries_.clear();
        frame_ = frame;
    }
    order_.clear();
    // Blocks with one vertex + index buffer over each: tile draws of one block share a binding.
    if (!pool_)
        pool_ = gpu::BufferPool::create(context, VkDeviceSize{32} << 20,
                                        VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
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
                // Replaced buffers are retired, not overwritten: earlier frames in flight may still read them.
                const auto upload = [&](GpuMesh& slot, const TriMesh& m, std::span<const std::uint8_t> mats,
                                        std::span<const Vec3> normals) {
                    if (retired && !fresh) {
                        GpuMesh next;
                        next.assign(context, m, mats, normals, pool_.get(), frame);
                        retired->push_back(std::move(slot));
                        slot = std::move(next);
                    } else {
                        slot.assign(context, m, mats, normals, pool_.get(), frame);
                    }
                };
                upload(e.mesh, mesh, materials, {});
                if (retired)
                    for (std::size_t k = t.levels.size(); k < e.levels.size(); ++k) retired->push_back(std::move(e.levels[k]));
                e.levels.resize(t.levels.size());
                for (std::size_t k = 0; k < t.levels.size(); ++k) {
                    const TileMeshLevel& l = t.levels[k];
                    std::span<const std::uint8_t> lm;
                    std::span<const Vec3> ln;
                    if (l.materials) lm = *l.materials;
                    if (l.normals) ln = *l.normals;
                    try {
                        upload(e.levels[k], l.mesh ? *l.mesh : kEmpty, lm, ln);
                    } catch (const Error& err) {
                        throw Error("level " + std::to_string(k + 1) + ": " + err.what());
                    }
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
        if (retired) {
            retired->push_back(std::move(kv.second->mesh));
            for (GpuMesh& l : kv.second->levels) retired->push_back(std::move(l));
        }
        return true;
    });
    uploads_total_ += uploads;
    return uploads;
}

const GpuMesh& TileMeshCache::mesh(std::size_t i, std::size_t level) const {
    if (i >= order_.size())
        throw Error("TileMeshCache::mesh: index " + std::to_string(i) + " >= " + std::to_string(order_.size()));
    if (level == 0) return order_[i]->mesh;
    if (level > order_[i]->levels.size())
        throw Error("TileMeshCache::mesh: tile " + std::to_string(i) + " has no level " + std::to_string(level));
    return order_[i]->levels[level - 1];
}

}  // namespace tridex::renderer
