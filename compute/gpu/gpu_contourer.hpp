// compute/gpu/gpu_contourer.hpp - contouring of dirty tiles on the GPU, from the GPU tri-dexel slabs, into
// vertex and index buffers that a renderer draws with one indexed indirect draw command per tile.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <vector>

#include "compute/contour/contour_tile.hpp"
#include "compute/gpu/gpu_dexel_slabs.hpp"
#include "compute/model/lattice.hpp"
#include "compute/model/tridexel.hpp"
#include "core/tri_mesh.hpp"
#include "gpu/buffer.hpp"
#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"

namespace tridex::compute {

/// One vertex of the GPU contour, 16 bytes (std430 `struct { vec3 grid; uint material; }`).
struct GpuContourVertex {
    float grid[3];          ///< position in grid units (world m = lattice.origin_m + grid * lattice.cell_m)
    std::uint32_t material; ///< material id (0..255), the CPU contourer's "vertex materials" rule
};
static_assert(sizeof(GpuContourVertex) == 16);

/// Counters of a GpuContourer since it was created (the `last_` ones for the last update()).
struct GpuContourStats {
    std::uint64_t updates = 0;          ///< update() calls with at least one tile
    std::uint64_t tiles_gpu = 0;        ///< tile contours written by the GPU kernel
    std::uint64_t tiles_cpu = 0;        ///< tiles contoured on the host (> 128 split faces, or split faces and > 4096 edges, or loop-capped)
    std::uint64_t tiles_loop_capped = 0; ///< of those, tiles the kernel could not finish under the device's loop cap (llvmpipe)
    std::uint64_t split_faces_gpu = 0;  ///< split faces (sub-cell tunnels) the kernel handled, summed over tile contours
    std::uint64_t region_retries = 0;   ///< tiles whose region was too small: re-allocated and redispatched
    std::uint64_t pool_grows = 0;       ///< vertex/index pools reallocated (compacted, usually grown)
    std::uint64_t dispatches = 0;       ///< vkCmdDispatch calls
    std::size_t last_tiles = 0;         ///< tiles redone by the last update()
    std::size_t last_cpu_tiles = 0;     ///< of those, contoured on the host
};

/// GPU manifold dual contouring of the tiles of a tri-dexel model held in GpuDexelSlabs.
///
/// Method: the CPU Contourer's (contour_tile.hpp: X-ray node occupancy with the half-open rule, crossings
/// from each edge's own ray, one vertex per cell surface component from contour_table.hpp placed by the
/// QEF of its crossings with normals estimated from the neighbouring rays, relative to and falling back on
/// their mean, clamped into the cell (contour_qef.hpp: sharp edges and corners kept), one quad per
/// sign-change edge split along the shorter diagonal), in shaders/dexel_contour.comp (the QEF part in
/// dexel_contour_qef.glsl), one workgroup per tile, in double precision without contraction: on lavapipe
/// (tested) vertex positions equal the CPU's doubles bit for bit (Vulkan does not require correctly rounded
/// double sqrt and division or denormal preservation, so another device may differ in the last bits,
/// which only the CPU-vs-GPU comparison tests would see; tiles sharing a vertex still compute it alike)
/// (the float vertex buffer rounds them: |error| <= 2^-24 x
/// |grid coordinate|), and the triangles are the same, including the face-split rule for tunnels thinner
/// than a cell (contour_tile.hpp: split-face vertices, fans around edge crossings). Tiles with more split
/// faces or edges than the kernel's shared lists hold (> 128 split faces, or split faces and > 4096 edges;
/// only dense random occupancy gets there) are contoured on the host with contour::TileContourer from
/// rays read out of the slabs (counted in GpuContourStats::tiles_cpu); so are tiles whose work a device's
/// shader loop cap cut short (llvmpipe stops every loop after 65535 iterations per SIMD group and run of the
/// kernel, summed over its loops; the kernel probes for it after its counting and after its writes, and
/// reports the tile; GpuContourStats::tiles_loop_capped).
///
/// Buffers: tile t owns a vertex region and an index region inside shared pools; its indices are local
/// to its vertex region, and its draw command (VkDrawIndexedIndirectCommand, 20 bytes, at t * 20 of
/// draw_commands(); indexCount 0 when the tile holds no surface) sets firstIndex and vertexOffset. A tile
/// holds copies of the vertices it shares with neighbour tiles, so redoing a tile never touches another.
/// A region too small for a new contour is reported by the kernel (nothing written, the old contour stays
/// drawable), re-allocated with slack and the tile redispatched; a full pool is compacted and grown (the
/// buffers are then replaced: buffer_generation() changes). Nothing is dropped.
///
/// The buffers are host-visible (lavapipe has no other memory). Not thread-safe: update() waits for its
/// submissions, and nobody may draw from the buffers while it runs. The Context and the slabs must
/// outlive the contourer; the slabs may replace their buffers between calls (re-bound each update()).
class GpuContourer {
public:
    /// Builds the pipeline for a model on `lattice` (tile grid TileGrid::kTileCells cells per side).
    /// `initial_vertices` / `initial_indices` size the pools (0 = 64 Ki vertices / 384 Ki indices); small
    /// values exercise the grow path. Throws tridex::Error when the device lacks shaderFloat64, the slabs'
    /// lattice differs from `lattice`, or on a Vulkan failure.
    GpuContourer(const gpu::Context& context, const GpuDexelSlabs& slabs, const Lattice& lattice,
                 std::size_t initial_vertices = 0, std::size_t initial_indices = 0);
    ~GpuContourer();
    GpuContourer(const GpuContourer&) = delete;
    GpuContourer& operator=(const GpuContourer&) = delete;

    /// Re-contours tiles `tiles` (linear indices tx + tiles_x * (ty + tiles_y * tz); duplicates ignored)
    /// from the slabs' current content, waiting for the GPU. Returns the number of tiles redone. The first
    /// call must cover every tile holding surface. Throws tridex::Error when a tile index is out of range,
    /// a pool would exceed maxStorageBufferRange, or on a Vulkan failure.
    std::size_t update(std::span<const std::uint32_t> tiles);
    /// As update(tiles) with the tiles flagged dirty in `grid` (flags left unchanged). Throws as update(),
    /// or tridex::Error when `grid` has a different tile count.
    std::size_t update_dirty(const TileGrid& grid);

    /// The vertex buffer (GpuContourVertex; also usable as a storage buffer).
    const gpu::Buffer& vertex_buffer() const { return vertices_; }
    /// The uint32 index buffer (indices local to each tile's vertex region).
    const gpu::Buffer& index_buffer() const { return indices_; }
    /// tile_count() VkDrawIndexedIndirectCommand records (stride 20 bytes), one per tile.
    const gpu::Buffer& draw_commands() const { return commands_; }
    /// Changes whenever the three buffers above are replaced (pool growth).
    std::uint64_t buffer_generation() const { return generation_; }
    /// Number of tiles (draw commands).
    std::uint32_t tile_count() const { return static_cast<std::uint32_t>(regions_.size()); }
    /// Indices tile `tile` draws (0 = no surface). Throws tridex::Error when tile >= tile_count().
    std::uint32_t tile_index_count(std::size_t tile) const;

    /// Reads the buffers back into one mesh in world metres, CCW from outside: per tile its vertices (the
    /// double positions the kernel computed, before rounding to float) and triangles; vertices shared by
    /// tiles appear once per tile. `materials` (optional) gets one id per vertex. For tests and export.
    TriMesh download(std::vector<std::uint8_t>* materials = nullptr) const;
    /// The float vertices of tile `tile` (as drawn), its local triangles and, when `grid` is given, the
    /// double positions the floats were rounded from (grid units). For tests. Throws tridex::Error when
    /// tile >= tile_count() or an index lies beyond the tile's vertices.
    void download_tile(std::size_t tile, std::vector<GpuContourVertex>& vertices, std::vector<std::array<std::uint32_t, 3>>& triangles,
                       std::vector<Vec3>* grid = nullptr) const;

    /// Counters since creation.
    const GpuContourStats& stats() const { return stats_; }

private:
    struct Region {
        std::uint32_t voff = 0, vcap = 0, ioff = 0, icap = 0;  // mirrors the GPU's region[] entry
        std::uint32_t vused = 0, iused = 0;
    };
    void create_pipeline();
    void bind_descriptors();
    void dispatch(const std::vector<std::uint32_t>& jobs);
    /// Gives `tile` a region of at least (nv, ni), compacting / growing the pools when they are full.
    void reserve(std::uint32_t tile, std::uint32_t nv, std::uint32_t ni);
    void regrow(std::size_t extra_v, std::size_t extra_i);
    void write_command(std::uint32_t tile);
    /// Contours `tile` on the host from the slabs (tiles the kernel hands back) and writes it into its region.
    void contour_on_host(std::uint32_t tile);
    const contour::TileMesh& host_piece(std::uint32_t tile);
    void fill_scratch_rays(std::uint32_t tile);

    const gpu::Context& context_;
    const GpuDexelSlabs& slabs_;
    Lattice lattice_;
    std::array<int, 3> tiles_{};
    gpu::UniqueDescriptorSetLayout set_layout_;
    gpu::UniquePipelineLayout pipeline_layout_;
    gpu::UniquePipeline pipeline_;
    gpu::UniqueDescriptorPool descriptor_pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
    gpu::Buffer cases_, jobs_, regions_buf_, status_, vertices_, vertices_d_, indices_, commands_;
    std::vector<Region> regions_;
    std::size_t vpool_ = 0, ipool_ = 0, vhead_ = 0, ihead_ = 0;
    std::uint64_t generation_ = 1;
    GpuContourStats stats_;
    // Host fallback: a model holding the rays the host-contoured tiles read, and their pieces.
    std::unique_ptr<TriDexel> scratch_;  // created on the first host-contoured tile
    contour::TileContourer worker_;
    std::map<std::uint32_t, contour::TileMesh> pieces_;
};

}  // namespace tridex::compute
