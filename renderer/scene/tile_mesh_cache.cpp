// renderer/scene/tile_mesh_cache.cpp - version-checked tile uploads.
#include "renderer/scene/tile_mesh_cache.hpp"

#include <string>

#include "core/error.hpp"

namespace tridex::renderer {

std::size_t TileMeshCache::sync(const gpu::Context& context, std::span<const TileMesh> tiles,
                                std::vector<GpuMesh>* retired, const ModelFrame& frame) {
    ++syncs_;
    context_ = &context;
    const auto retire = [&](Entry& e) {
        if (!retired) return;
        retired->push_back(std::move(e.mesh));
        for (GpuMesh& l : e.levels) retired->push_back(std::move(l));
        e.mesh = GpuMesh{};
        e.levels.clear();
    };
    if (!(frame == frame_)) {  // every mesh stored in the old frame goes
        for (auto& kv : entries_) retire(*kv.second);
        entries_.clear();
        order_.clear();
        frame_ = frame;
    }
    // Blocks with one vertex + index buffer over each: tile draws of one block share a binding.
    if (!pool_)
        pool_ = gpu::BufferPool::create(context, VkDeviceSize{32} << 20,
                                        VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    const auto key_of = [](const TileMesh& t, std::size_t i) { return t.id == TileMesh::kIdFromPosition ? i : t.id; };
    std::size_t changed = 0;
    // Takes tile t (at i) into its entry; a new or changed version retires what was uploaded.
    const auto take = [&](Entry& e, const TileMesh& t, std::size_t i, bool fresh) {
        e.seen = syncs_;
        e.source = t;
        e.index = i;
        if (fresh || e.version != t.version || e.uploaded.size() != t.levels.size() + 1) {
            // Replaced buffers are retired, not overwritten: earlier frames in flight may still read them.
            retire(e);
            e.levels.resize(t.levels.size());
            e.uploaded.assign(t.levels.size() + 1, 0);
            e.version = t.version;
            ++changed;
        }
    };
    // The same ids in the same order as the last sync's (every frame between publishes, and a publish that moved no
    // tile): each entry is found by its position, none is dropped, and none is listed twice (the last sync checked).
    bool same = order_.size() == tiles.size() && entries_.size() == order_.size();
    for (std::size_t i = 0; same && i < tiles.size(); ++i)
        same = key_of(order_[i]->source, order_[i]->index) == key_of(tiles[i], i);
    if (same) {
        for (std::size_t i = 0; i < tiles.size(); ++i) take(*order_[i], tiles[i], i, false);
        return changed;
    }
    order_.clear();
    for (std::size_t i = 0; i < tiles.size(); ++i) {
        const TileMesh& t = tiles[i];
        const std::uint64_t key = key_of(t, i);
        auto [it, fresh] = entries_.try_emplace(key);
        if (fresh) it->second = std::make_unique<Entry>();
        Entry& e = *it->second;
        if (!fresh && e.seen == syncs_) {
            order_.clear();
            throw Error("renderer: SceneView.tiles lists tile id " + std::to_string(key) + " twice");
        }
        take(e, t, i, fresh);
        order_.push_back(&e);
    }
    std::erase_if(entries_, [&](const auto& kv) {
        if (kv.second->seen == syncs_) return false;
        retire(*kv.second);
        return true;
    });
    return changed;
}

const GpuMesh& TileMeshCache::need(std::size_t i, std::size_t level) {
    if (i >= order_.size())
        throw Error("TileMeshCache::need: index " + std::to_string(i) + " >= " + std::to_string(order_.size()));
    Entry& e = *order_[i];
    if (level > e.levels.size())
        throw Error("TileMeshCache::need: tile " + std::to_string(i) + " has no level " + std::to_string(level));
    GpuMesh& slot = level == 0 ? e.mesh : e.levels[level - 1];
    if (e.uploaded[level]) return slot;
    static const TriMesh kEmpty;
    const TileMesh& t = e.source;
    try {
        if (level == 0) {
            std::span<const std::uint8_t> materials;
            if (t.materials) materials = *t.materials;
            std::span<const Vec3> normals;
            if (t.normals) normals = *t.normals;
            slot.assign(*context_, t.mesh ? *t.mesh : kEmpty, materials, normals, pool_.get(), frame_);
        } else {
            const TileMeshLevel& l = t.levels[level - 1];
            std::span<const std::uint8_t> lm;
            std::span<const Vec3> ln;
            if (l.materials) lm = *l.materials;
            if (l.normals) ln = *l.normals;
            try {
                slot.assign(*context_, l.mesh ? *l.mesh : kEmpty, lm, ln, pool_.get(), frame_);
            } catch (const Error& err) {
                throw Error("level " + std::to_string(level) + ": " + err.what());
            }
        }
    } catch (const Error& err) {
        throw Error(std::string(list_name_) + "[" + std::to_string(e.index) + "]: " + err.what());
    }
    e.uploaded[level] = 1;
    ++pending_uploads_;
    ++uploads_total_;
    return slot;
}

std::size_t TileMeshCache::take_uploads() {
    const std::size_t n = pending_uploads_;
    pending_uploads_ = 0;
    return n;
}

}  // namespace tridex::renderer
