// compute/runtime/gpu_contour_share.hpp - the GPU contour of a session, shared between the sculpt thread (which
// re-contours dirty tiles into it) and the render thread (which draws its buffers with indirect draws).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "compute/contour/contour_tiles.hpp"
#include "compute/gpu/gpu_contourer.hpp"
#include "compute/gpu/gpu_dexel_slabs.hpp"
#include "compute/model/tridexel.hpp"
#include "core/tri_mesh.hpp"
#include "gpu/context.hpp"
#include "gpu/indirect_workpiece.hpp"

namespace tridex::app {

/// A compute::GpuContourer on the sculptor's slabs behind one mutex: the sculpt thread holds it while
/// update() writes the buffers, the render thread while a frame that draws them is recorded, submitted and
/// waited for (lock_frame). So contouring never writes while a frame reads, and a frame always sees one
/// consistent set of buffers (re-bound every frame: a pool growth replaces them, buffer_generation()).
/// Both threads must submit on the same Context (the renderer's). The Context and slabs must outlive it.
class GpuContourShare {
public:
    /// Builds the contourer for `model` (its lattice and tile grid; the slabs hold the same model on the
    /// GPU). `initial_vertices` / `initial_indices` size its pools (0 = GpuContourer's defaults; small values
    /// make pools grow, replacing the buffers: tests). Throws tridex::Error as GpuContourer's constructor (no
    /// shaderFloat64, lattice mismatch, Vulkan).
    GpuContourShare(const gpu::Context& context, const compute::GpuDexelSlabs& slabs, const compute::TriDexel& model,
                    std::size_t initial_vertices = 0, std::size_t initial_indices = 0);

    /// Contours every tile (the first update must cover all tiles holding surface). Returns tiles redone.
    /// Throws as GpuContourer::update.
    std::size_t update_all();
    /// Re-contours the tiles flagged dirty in `grid` (flags left unchanged: the caller clears them), under
    /// the lock. Returns tiles redone. Throws as GpuContourer::update_dirty.
    std::size_t update_dirty(const compute::TileGrid& grid);
    /// Content version of tile `tile` (IndirectTile::version; 0 = never contoured). Throws tridex::Error out of range.
    std::uint64_t tile_version(std::size_t tile) const;
    /// From now on every update copies the tiles it redid out of the buffers (their float vertices as drawn, in
    /// world m: origin + grid * cell in double, compacted to the vertices their triangles use, and their materials)
    /// for refresh_tiles; a contour made before this call is copied whole now. Without this call nothing is copied
    /// (the default). Locks the buffers (waits for a frame being drawn); a second call does nothing.
    void read_back_tiles();
    /// Refreshes `cache` (TileSurfaceCache::refresh) from the copies of the tiles redone since the last call, so it
    /// can build their levels of detail for the renderer to draw in place of their indirect draws while
    /// TileSurface::source_version equals IndirectTile::version. Never waits for a frame (the copies were made by
    /// the updates). Returns tiles read (0 before the first update). Throws tridex::Error without
    /// read_back_tiles(), or as TileSurfaceCache::refresh (the cache is then unchanged and the copies kept).
    /// Call from the thread that calls the updates.
    std::size_t refresh_tiles(compute::TileSurfaceCache& cache);

    /// Locks the buffers for one frame and describes them in `out` (buffers, world_from_grid, the
    /// non-empty tiles with their world bounds: the tile's cells grown by one cell). Keep the returned lock
    /// until the frame that draws `out` has finished on the GPU. A re-contouring that is waiting goes first
    /// (the render thread yields to it): a render loop that locks again right after each frame would
    /// otherwise starve the sculpt thread (std::mutex is not fair), so a waiting update is delayed by at
    /// most the frame in flight.
    std::unique_lock<std::mutex> lock_frame(renderer::IndirectWorkpiece& out);

    /// The contourer's counters (locks).
    compute::GpuContourStats stats() const;
    /// The surface read back to a CPU mesh in world m (GpuContourer::download; locks). `materials` gets one
    /// id per vertex when given.
    TriMesh download(std::vector<std::uint8_t>* materials = nullptr) const;
    /// Number of updates so far (update_all / update_dirty calls that redid at least one tile).
    std::uint64_t updates() const;
    /// Time update_dirty() waited for the lock (a frame being drawn), summed and the longest wait, ms.
    double lock_wait_ms_total() const;
    double lock_wait_ms_max() const;

private:
    void rebuild_tiles();  // the non-empty tile list, under the lock
    std::size_t redo(
        const std::vector<std::uint32_t>& tiles);         // contours them and gives them new versions, under the lock
    void stash(const std::vector<std::uint32_t>& tiles);  // copies them out for refresh_tiles, under the lock

    mutable std::mutex mutex_;
    std::atomic<int> updates_waiting_{0};  // update_dirty() calls waiting for mutex_; lock_frame() yields to them
    compute::Lattice lattice_;
    std::array<int, 3> tiles_{};
    std::unique_ptr<compute::GpuContourer> contourer_;
    std::uint64_t updates_ = 0, listed_ = ~0ull;  // updates_ when `list_` was built
    std::vector<renderer::IndirectTile> list_;
    std::vector<std::uint64_t> versions_;  // per tile, see tile_version()
    // Tiles copied out for refresh_tiles (read_back_tiles): per tile the version and triangle count of the newest
    // copy, and the copies not yet handed to a cache. Written under both mutexes, read under stash_mutex_.
    std::atomic<bool> read_back_{false};
    std::mutex stash_mutex_;
    std::vector<std::uint64_t> stash_versions_;
    std::vector<std::uint32_t> stash_triangles_;
    struct ReadBack {
        TriMesh mesh;                         // world m
        std::vector<std::uint8_t> materials;  // per mesh vertex
    };
    std::unordered_map<std::uint32_t, ReadBack> stash_tiles_;
    std::uint64_t triangles_ = 0;
    double wait_total_ms_ = 0.0, wait_max_ms_ = 0.0;  // update_dirty's lock waits
};

}  // namespace tridex::app
