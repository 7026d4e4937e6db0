// compute/gpu/gpu_sculptor.hpp - swept-volume Booleans on the GPU: batches of sweeps in one submission.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

#include "compute/gpu/gpu_dexel_slabs.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/model/tridexel.hpp"
#include "gpu/buffer.hpp"
#include "gpu/context.hpp"
#include "gpu/repeat_submit.hpp"
#include "gpu/shader_module.hpp"
#include "gpu/unique_handle.hpp"

namespace tridex::compute {

/// Counters of a GpuSculptor since it was created.
struct GpuSculptStats {
    std::uint64_t batches = 0;       ///< submissions (one per apply() call, more for batches over 682 sweeps)
    std::uint64_t sweeps = 0;        ///< sweeps applied
    std::uint64_t dispatches = 0;    ///< vkCmdDispatch calls (one per batch, for all three ray sets)
    std::uint64_t workgroups = 0;    ///< workgroups dispatched (each takes several tiles in turn), summed over batches
    std::uint64_t ray_tiles = 0;     ///< 4 x 2-ray tiles dispatched, summed over batches
    std::uint64_t retried_rays = 0;  ///< rays the kernel handed back (pool full, > 16 intervals, loop cap), redone on the host
    /// Of those, rays whose loops the device cut short or whose tile it never reached: llvmpipe stops every loop of
    /// a shader run once its SIMD group has taken 65,535 loop iterations (a tile under hundreds of long mesh-tool
    /// sweeps can); the host redoes them from the mirror.
    std::uint64_t loop_capped_rays = 0;
    std::uint64_t compactions = 0;   ///< spill-pool compactions (each may grow the pool)
    double prepare_s = 0.0;  ///< host time before submitting (tile lists, uploads), s, summed over batches
    double submit_s = 0.0;   ///< time from recording the command buffer until its fence signalled, s, summed
    double finish_s = 0.0;   ///< host time after the fence (retried rays, the mirror's rays), s, summed
};

/// Options of a GpuSculptor.
struct GpuSculptorOptions {
    /// Initial spill-pool size per ray set, chunks of 8 intervals; 0 = twice what the model needs, at
    /// least 4096. Small values exercise compaction and growth (tests).
    std::uint32_t initial_pool_chunks = 0;
    /// How apply() waits for a batch's fence (gpu::FenceWait).
    gpu::FenceWait fence_wait = gpu::FenceWait::kBlock;
    /// Workgroups per dispatch asked for, at most 65535 (each takes the batch's ray tiles in turn: w, w +
    /// workgroups, ...). A batch gets fewer when it has fewer tiles, and more (up to one per tile, at most 65535) when a
    /// workgroup's tiles could run more loop iterations than llvmpipe allows one shader invocation (65,535 in
    /// all loops). 0 = 2 per hardware thread on a CPU device (Mesa lavapipe, where each workgroup costs a fixed
    /// entry and exit), else 65535. The result does not depend on it.
    std::uint32_t workgroups = 0;
    /// Loop iterations one workgroup may take, as the host bounds them, before it gets more workgroups (llvmpipe
    /// stops every loop of a shader run past 65,535 in all; the default keeps a margin). 0 = no bound: `workgroups`
    /// are dispatched as asked, and the kernel's own check of the spent budget (the host then redoes the rays it
    /// could not finish) is all that keeps the result right. The result does not depend on it.
    std::uint64_t loop_budget = 60000;
};

/// The GPU path of the sculpt thread: holds the tri-dexel model in GpuDexelSlabs and applies batches of
/// sweeps with shaders/dexel_sweep.comp. Per batch, only the 4 x 2-ray tiles of each ray set under some
/// sweep's footprint are dispatched (the tiles of all three sets in one dispatch, whose workgroups take them in
/// turn, GpuSculptorOptions::workgroups; the
/// device must offer shaderStorageBufferArrayDynamicIndexing, else the constructor throws); each
/// invocation applies, in order, the batch's sweeps whose footprint holds its tile. The sweeps go in a
/// 64 KiB uniform buffer (682 sweeps; a longer batch runs as several submissions, in order).
/// The kernel is specialised to the operations and tool kinds a batch holds (one pipeline per pair; the
/// ball-subtract one is made with the sculptor, others on their first batch, which then takes tens of
/// ms longer on lavapipe). The result equals
/// the CPU reference (apply_sweep, same float arithmetic) ray for ray; the tests check it bit for bit.
/// After the GPU finishes, the footprint rays are copied into the CPU `mirror` model (for contouring and
/// the active surface) and the mirror's tiles under the sweeps are marked dirty.
/// Spill pool: when the kernel finds no room for a ray (or the ray would exceed the kernel's 16 intervals) it leaves
/// the ray untouched and lists it; the host compacts (and if needed grows) the pool and redoes those rays
/// with the CPU reference, so no interval is ever dropped. A ray needing more than 120 intervals throws.
/// Mesh tools (ToolKind::kMesh): the batch's distinct tool dexels (GridBatch::tools) are packed into one
/// storage buffer (binding 9, re-uploaded only when the batch's tool table changes); a batch whose tools
/// need more than 128 MiB (or maxStorageBufferRange) is refused with tridex::Error before anything changes.
/// Not thread-safe: one thread calls apply(). The Context and the mirror must outlive the sculptor.
class GpuSculptor {
public:
    /// Uploads `mirror` (the current model) to the GPU. Throws tridex::Error when the model does not fit
    /// (GpuDexelSlabs::upload) or the pipeline cannot be created.
    GpuSculptor(const gpu::Context& context, TriDexel& mirror, const GpuSculptorOptions& options = {});
    ~GpuSculptor();
    GpuSculptor(const GpuSculptor&) = delete;
    GpuSculptor& operator=(const GpuSculptor&) = delete;

    /// Applies `batch` in order (sweeps with op kNone are skipped) in one GPU submission and waits for it;
    /// then updates the mirror's footprint rays and dirty tiles. Returns rays visited (footprint rays
    /// summed over sweeps, as the CPU path counts them) and rays changed. Throws tridex::Error before
    /// changing anything when a sweep is invalid (to_grid_sweep), and on a Vulkan failure or a ray over
    /// 120 intervals (the model is then only partly updated; the caller should stop sculpting).
    BooleanStats apply(std::span<const Sweep> batch);

    /// Replaces whole rays (undo and redo): each image's intervals become its ray's in the slabs and the mirror,
    /// and the mirror's tiles around `box_m` (world m) are marked dirty. Compacts a set's pool when a ray finds no
    /// room. Throws tridex::Error on an image outside the model or over kMaxRayIntervals intervals, or when even
    /// a compacted pool has no room (rays before it are then written).
    void write_rays(std::span<const RayImage> rays, const Aabb& box_m);

    /// Copies ray `index` of set `axis` of the mirror into the slabs (after the host changed it in the mirror, e.g. a
    /// clay operation's re-sampled ray), compacting the set's pool when it has no room. Marks nothing dirty. Throws
    /// tridex::Error on a ray outside the model, over kMaxRayIntervals intervals, or with no room after compaction.
    void store_mirror_ray(int axis, std::uint32_t index);

    /// The GPU-resident model.
    const GpuDexelSlabs& slabs() const { return slabs_; }
    /// The CPU mirror of the model (what the constructor was given).
    TriDexel& mirror() { return mirror_; }
    /// Counters since creation.
    const GpuSculptStats& stats() const { return stats_; }

private:
    void ensure_batch_capacity(std::size_t tiles, std::size_t indices, std::size_t retry);
    // One chunk of a batch (at most max_sweeps_ sweeps `grid`, from batch[source[i]]) in one submission: its tiles
    // (list_tiles), the buffers (upload_batch), the kernel variant, the tile order (order_tiles), the dispatch, the
    // host's share (finish_on_host), the mirror's rays (read_footprint_rays) and dirty tiles. Returns its stats.
    BooleanStats apply_grid(std::span<const Sweep> batch, std::span<const GridSweep> grid, std::span<const std::size_t> source,
                            const ToolTable& tools);
    struct TileList;  // a chunk's ray tiles, their sweeps and dispatch order (gpu_sculptor.cpp)
    // Fills `list` with the ray tiles under the chunk's sweep footprints (per set, in tile order), each listing its
    // sweeps in batch order, and the footprint rays visited.
    void list_tiles(std::span<const GridSweep> grid, TileList& list) const;
    // Grows the batch buffers as needed and writes the chunk's sweeps, tile sweep lists and each set's pool head.
    void upload_batch(const TileList& list, std::span<const GridSweep> grid);
    // The kernel specialised to the chunk's operations and tool kinds (no mesh tools).
    VkPipeline pipeline_for_chunk(std::span<const GridSweep> grid);
    // Orders the tiles for the workgroups (list.order, then the zeroed done words), uploads them and returns the number
    // of workgroups to dispatch.
    std::uint32_t order_tiles(TileList& list, std::span<const GridSweep> grid, const ToolTable& tools);
    // Records and submits the dispatch of `groups` workgroups over `listed` tiles and waits for it; returns the time
    // just before the submission (where GpuSculptStats::prepare_s ends and submit_s begins).
    std::chrono::steady_clock::time_point dispatch(VkPipeline pipeline, std::uint32_t groups, std::size_t listed);
    // Reads back the pool heads and the rays the kernel handed back or may have left half done, redoes those on the
    // host (compacting a pool the kernel overran); returns the rays changed (the kernel's and the host's).
    std::size_t finish_on_host(const TileList& list, std::span<const GridSweep> grid, const ToolTable& tools);
    // Copies the chunk's footprint rays from the slabs into the mirror.
    void read_footprint_rays(const TileList& list);
    void bind_descriptors();
    // Applies `sweeps` (in order, those whose footprint holds the ray) to rays `rays` (indices in set `axis`) as the
    // mirror holds them (the model before the batch), and writes each that changed, or each when `rewrite` (the
    // slabs' copy may be half written), to the slabs; returns how many changed.
    std::size_t redo_on_host(int axis, std::span<const std::uint32_t> rays, std::span<const GridSweep> sweeps, const ToolTable& tools,
                             bool rewrite);
    void upload_tools(const ToolTable& tools);
    gpu::UniquePipeline create_pipeline(bool mesh, std::uint32_t ops, std::uint32_t kinds) const;
    VkPipeline pipeline_for(std::uint32_t ops, std::uint32_t kinds);

    const gpu::Context& context_;
    TriDexel& mirror_;
    GpuDexelSlabs slabs_;
    gpu::RepeatSubmitter submitter_;  // one command buffer and fence for every batch
    GpuSculptStats stats_;
    gpu::UniqueDescriptorSetLayout set_layout_;
    gpu::UniquePipelineLayout pipeline_layout_;
    gpu::UniqueShaderModule module_;     // shaders/dexel_sweep.comp
    gpu::UniquePipeline pipelines_[8][4];  // [OPS][KINDS]: kernels without the mesh-tool path, made on first use
    gpu::UniquePipeline mesh_pipeline_;  // kernel with it (and every operation and tool), for batches holding kMesh sweeps
    gpu::UniqueDescriptorPool descriptor_pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;  // bindings 0-4 and 8 are arrays of one buffer per ray set
    gpu::Buffer sweeps_, tiles_, index_;
    gpu::Buffer counters_[3];
    gpu::Buffer tools_;            // the batch's mesh-tool dexels (pack_tools words), binding 9
    ToolTable uploaded_tools_;     // what tools_ holds now
    std::size_t retry_capacity_ = 0;
    std::size_t max_sweeps_ = 0;   // sweeps per dispatch: what the uniform buffer sweeps_ holds
    std::uint32_t workgroups_ = 0;  // workgroups per dispatch (GpuSculptorOptions::workgroups, resolved)
    std::uint64_t loop_budget_ = 0;  // GpuSculptorOptions::loop_budget
};

}  // namespace tridex::compute
