// renderer/scene/tile_mesh_cache.hpp - per-tile workpiece meshes on the GPU, re-uploaded only when they change.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include "core/aabb.hpp"
#include "core/tri_mesh.hpp"
#include "gpu/buffer_pool.hpp"
#include "gpu/context.hpp"
#include "renderer/scene/gpu_mesh.hpp"
#include "renderer/scene/tile_lod.hpp"

namespace tridex::renderer {

/// One tile of the workpiece surface as the renderer draws it (the contouring works per 16^3-cell tile).
struct TileMesh {
    const TriMesh* mesh = nullptr;  ///< the tile's triangles, model m (SceneView::workpiece_pose places them; nullptr or empty: nothing to draw)
    Aabb bounds_m;                  ///< model box holding the tile's triangles, m (the culling test uses it)
    /// Content version: the renderer re-uploads the tile only when this differs from the uploaded one, so
    /// bump it whenever the mesh (or its materials) changes.
    std::uint64_t version = 0;
    /// Optional per-vertex material ids (size = mesh->positions.size(), values 0..kMaterialCount-1); nullptr = 0.
    const std::vector<std::uint8_t>* materials = nullptr;
    /// Stable identity of the tile across frames (e.g. its linear tile index in the lattice);
    /// kIdFromPosition = its position in the list, which must then be the same every frame.
    std::uint64_t id = kIdFromPosition;
    static constexpr std::uint64_t kIdFromPosition = std::numeric_limits<std::uint64_t>::max();
    /// Coarser levels of detail of `mesh`, finest first (optional): uploaded with the tile (again when its
    /// version changes), and each eye draws the coarsest whose error projects to at most SceneView::lod_max_px.
    std::span<const TileMeshLevel> levels{};
    /// Index in SceneView::tile_groups of the smallest group holding this tile (TileGroup), or kNoGroup.
    std::size_t group = kNoGroup;
    static constexpr std::size_t kNoGroup = std::numeric_limits<std::size_t>::max();
    /// Optional per-vertex unit normals (size = mesh->positions.size()), e.g. the whole surface's at the tile's border
    /// vertices, so that neighbouring tiles shade a shared vertex alike; nullptr or empty = the mesh's own
    /// area-weighted normals (core vertex_normals).
    const std::vector<Vec3>* normals = nullptr;
};

/// GPU copies of tile meshes keyed by TileMesh::id. sync() takes the frame's list: it notes which tiles are new or
/// changed version and frees tiles no longer listed; unchanged tiles cost nothing. A tile's mesh, or one of its
/// levels, is uploaded only when a draw asks for it (need()): a tile drawn at a coarse level, or under a group drawn
/// in its place, never uploads its full mesh, so a frame's uploads follow what it draws. Each tile has its own host-
/// visible GpuMesh (two buffers) sub-allocated from a pool whose blocks each have one buffer over the whole
/// block, so the draws of all tiles in a block bind one buffer (GpuMesh::draw_range). Move-only; the Context must outlive it. Not safe while the GPU still
/// reads an earlier frame (the caller retires replaced meshes: sync()'s `retired`).
class TileMeshCache {
public:
    /// An empty cache; `list_name` names its list in need()'s errors ("SceneView.tiles", "SceneView.tile_groups").
    explicit TileMeshCache(const char* list_name = "SceneView.tiles") : list_name_(list_name) {}
    /// Makes the cache hold exactly `tiles` (empty or null meshes included) and returns how many tiles are new or
    /// changed their version (their meshes are uploaded by need()). The tiles' meshes must stay as they are until the
    /// frame's need() calls are done. Throws tridex::Error when two tiles have the same id (naming it).
    /// With `retired`, the GPU meshes of replaced and dropped tiles are moved there instead of being overwritten
    /// or freed (for a caller whose earlier frames may still read them); changed tiles then get new buffers.
    /// `frame` says how positions are stored (GpuMesh::assign); when it differs from the last sync's, every tile is
    /// uploaded again when drawn.
    std::size_t sync(const gpu::Context& context, std::span<const TileMesh> tiles,
                     std::vector<GpuMesh>* retired = nullptr, const ModelFrame& frame = {});
    /// The GPU mesh of tiles[i] of the last sync() (level 0), or of its level `level` (1..tiles[i].levels.size()),
    /// uploaded now when it is not yet (within the frame of that sync: the tile's mesh is read). Throws tridex::Error
    /// when i or level is out of range, or GpuMesh::assign throws (bad indices, non-finite position, bad materials:
    /// "SceneView.tiles[i]: ...", with the cache's list name); a tile that failed is uploaded again at its next need().
    const GpuMesh& need(std::size_t i, std::size_t level = 0);
    /// Meshes (a tile's level each) need() uploaded since the last call; resets the count.
    std::size_t take_uploads();
    /// Tiles held (= the size of the last sync()'s list).
    std::size_t size() const { return order_.size(); }
    /// Uploads over the cache's lifetime.
    std::uint64_t uploads_total() const { return uploads_total_; }
    /// VkDeviceMemory allocations holding the tiles' buffers now (the pool's blocks; 0 before the first upload).
    std::size_t memory_blocks() const { return pool_ ? pool_->blocks() : 0; }
    /// Tile vertex and index buffers alive now.
    std::size_t buffers() const { return pool_ ? pool_->live_buffers() : 0; }

private:
    struct Entry {
        GpuMesh mesh;
        std::vector<GpuMesh> levels;  // TileMesh::levels, finest first
        std::vector<std::uint8_t> uploaded;  // per level (0 = the mesh): its GPU copy is of `version`
        std::uint64_t version = 0;
        std::uint64_t seen = 0;  // sync() call that listed it last
        TileMesh source;         // the last sync()'s tile: its meshes, valid within that frame
        std::size_t index = 0;   // its position in that sync()'s list
    };
    const char* list_name_;
    const gpu::Context* context_ = nullptr;  // of the last sync()
    std::size_t pending_uploads_ = 0;
    std::unique_ptr<gpu::BufferPool> pool_;  // declared first: destroyed after the entries' buffers
    std::unordered_map<std::uint64_t, std::unique_ptr<Entry>> entries_;
    std::vector<Entry*> order_;
    std::uint64_t syncs_ = 0;
    ModelFrame frame_{};  // of the uploaded meshes
    std::uint64_t uploads_total_ = 0;
};

}  // namespace tridex::renderer
