// compute/gpu/gpu_sculptor.cpp - batching sweeps into ray tiles, the compute dispatch, and the host's share
// (retried rays, pool compaction, the CPU mirror).
#include "compute/gpu/gpu_sculptor.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstring>
#include <sstream>
#include <thread>

#include "core/error.hpp"
#include "gpu/check.hpp"
#include "gpu/descriptor_sets.hpp"
#include "gpu/compute_pipeline.hpp"
#include "gpu/shader_module.hpp"
#include "shaders/spirv.hpp"

namespace tridex::compute {
namespace {

// A tile is 8 rays, one for each of a workgroup's 8 invocations (one SIMD row of llvmpipe), laid out as kTileU x kTileV:
// 4 x 2 wastes fewer lanes at a footprint's edges than 8 x 1 (or 8 x 2 as two rows).
constexpr int kTileU = 4;  // rays per tile along u (the kernel's specialisation constant 1, TILE_U)
constexpr int kTileV = 8 / kTileU;
constexpr std::uint32_t kMaxGroups = 65535;  // workgroups per dispatch we rely on (the Vulkan minimum)
constexpr std::uint32_t kGroupsPerCpuThread = 2;  // workgroups per driver thread on a CPU device (GpuSculptorOptions::workgroups)
constexpr int kBindings = 10;
constexpr std::uint32_t kPerSetBindings = 0x11fu;  // bindings 0-4 (slabs) and 8 (counters): arrays of one buffer per ray set
constexpr int kSweepBinding = 5;  // the batch's sweeps: a uniform buffer (llvmpipe gathers those as vectors)
constexpr std::size_t kSweepUniformBytes = 65536;  // the Vulkan minimum of maxUniformBufferRange is 16384
constexpr std::size_t kMaxBinding = std::size_t{128} << 20;  // lavapipe's maxStorageBufferRange

// One ray set's constants (the kernel's SetConstants).
struct SetPush {
    std::int32_t nu = 0, nv = 0;
    std::uint32_t pool_chunks = 0;
    float depth_cells = 0.0f;  // the lattice's cells along the set's axis: union chords are clipped to [0, depth_cells]
};

struct Push {
    SetPush sets[3];
    std::uint32_t tile_count = 0, retry_capacity = 0;
    std::uint32_t two = 2;  // the kernel's loop-cap probe's trip count
};

// A retry entry's flag: the kernel's loops were cut short by the device's loop cap (shaders/dexel_sweep.comp).
constexpr std::uint32_t kRetryLoopCap = 0x80000000u;

// tu carries the tile's ray set in its top two bits (kSetShift): one dispatch covers all three sets.
struct TileEntry {
    std::uint32_t tu, tv, first, count;
};
constexpr int kSetShift = 30;
constexpr std::uint32_t kTileMask = (1u << kSetShift) - 1u;

// Orders one dispatch's tiles so that every contiguous 1/2, 1/4 or 1/8 of them carries about the same
// work: sorted by sweep count (the work per ray), descending, then dealt by the bit-reversed residue of the
// rank modulo 8 (ranks 0, 8, 16, ... first, then 4, 12, ..., then 2, 10, ...). The workgroups take the
// tiles in turn (w, w + groups, ...), so each gets about the same share of large and small tiles; with one
// workgroup per tile, llvmpipe (Mesa lp_cs_tpool) gives each of its threads one contiguous block of them.
// Tiles are independent, so the order changes no result.
void balance_tiles(std::vector<TileEntry>::iterator first, std::vector<TileEntry>::iterator last) {
    std::stable_sort(first, last, [](const TileEntry& x, const TileEntry& y) { return x.count > y.count; });
    static constexpr std::uint32_t kReverse3[8] = {0, 4, 2, 6, 1, 5, 3, 7};
    const std::size_t n = static_cast<std::size_t>(last - first);
    std::vector<std::pair<std::uint64_t, TileEntry>> keyed(n);
    for (std::size_t i = 0; i < n; ++i)
        keyed[i] = {static_cast<std::uint64_t>(kReverse3[i % 8]) << 40 | i, first[static_cast<std::ptrdiff_t>(i)]};
    std::sort(keyed.begin(), keyed.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t i = 0; i < n; ++i) first[static_cast<std::ptrdiff_t>(i)] = keyed[i].second;
}

// Mesa llvmpipe ends every loop of a shader invocation once the invocation's loops have run 65,535 iterations
// in all (gallivm LP_MAX_TGSI_LOOP_ITERATIONS, one budget shared by every loop), silently. A workgroup that takes
// several tiles should stay within it (the kernel notices when one did not, and the host then redoes that work:
// slower, but right), counted as an upper bound over the kernel's loops (shaders/dexel_sweep.comp; a loop of k
// turns counts k + 1, its last test included): per tile, its turn of the tile loop, loading and writing back at
// most 16 intervals, the two sweep loops' last tests and the two loop-cap probes (kTileIterations); per sweep
// listed in the tile, its turns in the register and array paths' sweep loops and their stamp loops' last tests
// (kSweepIterations); per stamp, its turns in the two stamp loops, the flat end's two sides and the span loop's last
// test (kStampIterations); per span (one per stamp, or one per interval of a mesh tool's ray), its turn of the span
// loop and the interval operation's at most three passes over 16 intervals (kSpanIterations). kLoopBudget keeps
// a margin below the limit (GpuSculptorOptions::loop_budget).
constexpr std::uint64_t kTileIterations = 46, kSweepIterations = 4, kStampIterations = 6, kSpanIterations = 52;

// The most intervals one ray of any of `tools` holds (1 when there are none: an analytic tool's one chord).
std::uint64_t spans_per_stamp(const ToolTable& tools) {
    std::uint64_t most = 1;
    for (const auto& t : tools)
        for (const ToolDexelSet& s : t->sets)
            for (std::size_t r = 0; r + 1 < s.first.size(); ++r) most = std::max<std::uint64_t>(most, s.first[r + 1] - s.first[r]);
    return most;
}

// Workgroups for a dispatch of `order`'s tiles (each listing its sweeps in `index`): `wanted` (at most one per
// tile), doubled until every workgroup's tiles (w, w + groups, ...) stay within `budget` loop iterations (0: no
// bound), or one per tile, never more than kMaxGroups (a dispatch's limit; past it a workgroup takes more than one
// tile even when that exceeds the budget, as one tile alone may).
std::uint32_t groups_within_loop_budget(const std::vector<TileEntry>& order, const std::vector<std::uint32_t>& index,
                                        std::span<const GridSweep> grid, const ToolTable& tools, std::uint32_t wanted,
                                        std::uint64_t budget) {
    const std::uint32_t most = static_cast<std::uint32_t>(std::min<std::size_t>(order.size(), kMaxGroups));
    const std::uint64_t spans = spans_per_stamp(tools);
    std::vector<std::uint64_t> cost(order.size(), kTileIterations), load;
    for (std::size_t t = 0; t < order.size(); ++t)
        for (std::uint32_t j = 0; j < order[t].count; ++j)
            cost[t] += kSweepIterations + std::uint64_t{grid[index[order[t].first + j]].stamps} * (kStampIterations + spans * kSpanIterations);
    std::uint32_t groups = std::max(1u, std::min(most, wanted));
    for (;;) {
        load.assign(groups, 0);
        for (std::size_t t = 0; t < order.size(); ++t) load[t % groups] += cost[t];
        if (budget == 0 || groups >= most || *std::max_element(load.begin(), load.end()) <= budget) return groups;
        groups = static_cast<std::uint32_t>(std::min<std::uint64_t>(most, std::uint64_t{groups} * 2));
    }
}

gpu::Buffer host_storage(const gpu::Context& c, std::size_t bytes) {
    return gpu::Buffer::create(c, std::max<std::size_t>(bytes, 16), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryDomain::kHost);
}

std::uint32_t bits(float f) {
    std::uint32_t b;
    std::memcpy(&b, &f, 4);
    return b;
}

/// The tools of a batch as the kernel's ToolData words: [t] = first word of tool t's block; a block is
/// k (float bits), then per ray set a: nu, nv, ref_u, ref_v, word of its `first` offsets, word of its
/// depths (float bits, 2 per interval); then those arrays.
std::vector<std::uint32_t> pack_tools(const ToolTable& tools) {
    std::vector<std::uint32_t> w(tools.size(), 0u);
    for (std::size_t t = 0; t < tools.size(); ++t) {
        const ToolDexels& d = *tools[t];
        w[t] = static_cast<std::uint32_t>(w.size());
        const std::size_t head = w.size();
        w.resize(head + 19, 0u);
        w[head] = bits(static_cast<float>(d.k));
        for (int a = 0; a < 3; ++a) {
            const ToolDexelSet& s = d.sets[a];
            std::uint32_t* h = &w[head + 1 + 6 * a];
            h[0] = static_cast<std::uint32_t>(s.nu);
            h[1] = static_cast<std::uint32_t>(s.nv);
            h[2] = static_cast<std::uint32_t>(s.ref_u);
            h[3] = static_cast<std::uint32_t>(s.ref_v);
            h[4] = static_cast<std::uint32_t>(w.size());
            w.insert(w.end(), s.first.begin(), s.first.end());
            w[head + 1 + 6 * a + 5] = static_cast<std::uint32_t>(w.size());
            for (const float f : s.depth) w.push_back(bits(f));
        }
    }
    return w;
}

}  // namespace

GpuSculptor::GpuSculptor(const gpu::Context& context, TriDexel& mirror, const GpuSculptorOptions& options)
    : context_(context), mirror_(mirror), slabs_(GpuDexelSlabs::upload(context, mirror, options.initial_pool_chunks)),
      submitter_(context, options.fence_wait) {
    const VkDevice dev = context.device();
    if (!context.features().storage_buffer_array_dynamic_indexing)
        throw Error("GPU sculpt: the Vulkan device cannot index arrays of storage buffers in shaders "
                    "(shaderStorageBufferArrayDynamicIndexing); use --cpu");
    gpu::ComputeLayout cl = gpu::create_compute_layout(context, kBindings, sizeof(Push), 1u << kSweepBinding, kPerSetBindings, 3);
    const VkDescriptorSetLayout layout = cl.set_layout.get();
    set_layout_ = std::move(cl.set_layout);
    pipeline_layout_ = std::move(cl.pipeline_layout);

    // Kernel variants by specialisation constants: HAS_MESH (constant_id 0) compiles the mesh-tool path in
    // (mesh_pipeline_, all operations and tools) or out; OPS and KINDS (constant_id 3, 4) compile in only
    // the batch's operations and tool kinds (pipeline_for; llvmpipe runs both sides of
    // every branch, so absent code costs time: about 1.4x for subtract-only ball batches); constant_id 1
    // is the tile width kTileU, constant_id 2 the sweeps per dispatch.
    max_sweeps_ = std::min<std::size_t>(kSweepUniformBytes, context.properties().limits.maxUniformBufferRange) / sizeof(GridSweep);
    module_ = gpu::create_shader_module(context, shaders::spirv("dexel_sweep_comp"));
    mesh_pipeline_ = create_pipeline(true, 7u, 3u);
    // Creating a variant takes tens of ms on lavapipe: the common one (ball, subtract) now, others on first use.
    pipelines_[1][1] = create_pipeline(false, 1u, 1u);
    descriptor_pool_ = gpu::allocate_descriptor_sets(
        dev, {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3 * 6 + 3}, {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1}}, layout, 1, &set_);

    tools_ = host_storage(context_, 16);
    sweeps_ = gpu::Buffer::create(context_, max_sweeps_ * sizeof(GridSweep), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryDomain::kHost);
    ensure_batch_capacity(256, 1024, 256 * 64);
    workgroups_ = options.workgroups;
    if (workgroups_ == 0) {
        // A CPU device runs a dispatch's workgroups on its worker threads (Mesa llvmpipe: one per core by
        // default), each entered and left at a fixed cost: a few per thread keep every thread busy to the end.
        // Elsewhere one workgroup per tile, as many as a dispatch is sure to take.
        const bool cpu = context.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
        workgroups_ = cpu ? kGroupsPerCpuThread * std::max(1u, std::thread::hardware_concurrency()) : kMaxGroups;
    }
    workgroups_ = std::min(workgroups_, kMaxGroups);
    loop_budget_ = options.loop_budget;
}

gpu::UniquePipeline GpuSculptor::create_pipeline(bool mesh, std::uint32_t ops, std::uint32_t kinds) const {
    const std::uint32_t values[5] = {mesh ? VK_TRUE : VK_FALSE, static_cast<std::uint32_t>(kTileU), static_cast<std::uint32_t>(max_sweeps_),
                                     ops, kinds};
    VkSpecializationMapEntry entries[5];
    for (std::uint32_t i = 0; i < 5; ++i) entries[i] = VkSpecializationMapEntry{i, 4 * i, 4};
    VkSpecializationInfo spec{};
    spec.mapEntryCount = 5;
    spec.pMapEntries = entries;
    spec.dataSize = sizeof(values);
    spec.pData = values;
    return gpu::create_compute_pipeline(context_, module_.get(), pipeline_layout_.get(), &spec);
}

VkPipeline GpuSculptor::pipeline_for(std::uint32_t ops, std::uint32_t kinds) {
    gpu::UniquePipeline& p = pipelines_[ops & 7u][kinds & 3u];
    if (p.get() == VK_NULL_HANDLE) p = create_pipeline(false, ops, kinds);
    return p.get();
}

void GpuSculptor::upload_tools(const ToolTable& tools) {
    if (tools.empty() || tools == uploaded_tools_) return;
    const std::vector<std::uint32_t> words = pack_tools(tools);
    const std::size_t bytes = words.size() * sizeof(std::uint32_t);
    const std::size_t limit = std::min<std::size_t>(kMaxBinding, context_.properties().limits.maxStorageBufferRange);
    if (bytes > limit) {
        std::ostringstream m;
        m << "GPU sculpt: the batch's mesh-tool dexels need " << (bytes >> 20) << " MiB, over the " << (limit >> 20)
          << " MiB one storage binding may hold; use a smaller tool, fewer rays per cell (k), fewer distinct tool"
             " orientations per batch, or --cpu";
        throw Error(m.str());
    }
    if (tools_.size() < bytes) {
        tools_ = host_storage(context_, std::max(bytes, std::min(limit, tools_.size() * 2)));
        bind_descriptors();
    }
    tools_.write(words.data(), bytes);
    uploaded_tools_ = tools;
}

GpuSculptor::~GpuSculptor() = default;

void GpuSculptor::ensure_batch_capacity(std::size_t tiles, std::size_t indices, std::size_t retry) {
    bool rebind = set_ != VK_NULL_HANDLE && tiles_.handle() == VK_NULL_HANDLE;
    auto grow = [&](gpu::Buffer& buf, std::size_t bytes) {
        if (buf.handle() != VK_NULL_HANDLE && buf.size() >= bytes) return;
        buf = host_storage(context_, std::max<std::size_t>(bytes, buf.size() * 2));
        rebind = true;
    };
    grow(tiles_, (tiles + (tiles + 3) / 4) * sizeof(TileEntry));  // the entries, then a done word per tile
    grow(index_, indices * sizeof(std::uint32_t));
    if (retry > retry_capacity_ || counters_[0].handle() == VK_NULL_HANDLE) {
        retry_capacity_ = std::max(retry, retry_capacity_ * 2);
        for (auto& c : counters_) c = host_storage(context_, 16 + 4 * retry_capacity_);
        rebind = true;
    }
    if (rebind) bind_descriptors();
}

void GpuSculptor::bind_descriptors() {
    // Bindings 0-4 and 8 hold one buffer per ray set (array element = axis), the others one buffer.
    VkDescriptorBufferInfo info[kBindings][3];
    VkWriteDescriptorSet w[kBindings]{};
    for (int i = 0; i < kBindings; ++i) {
        const bool per_set = ((kPerSetBindings >> i) & 1u) != 0;
        for (int a = 0; a < 3; ++a) {
            const gpu::Buffer* buf = i < 5             ? &slabs_.buffer(a, i)
                                     : i == kSweepBinding ? &sweeps_
                                     : i == 6             ? &tiles_
                                     : i == 7             ? &index_
                                     : i == 8             ? &counters_[a]
                                                          : &tools_;
            info[i][a] = VkDescriptorBufferInfo{buf->handle(), 0, VK_WHOLE_SIZE};
        }
        w[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        w[i].dstSet = set_;
        w[i].dstBinding = static_cast<std::uint32_t>(i);
        w[i].descriptorCount = per_set ? 3u : 1u;
        w[i].descriptorType = i == kSweepBinding ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w[i].pBufferInfo = info[i];
    }
    vkUpdateDescriptorSets(context_.device(), kBindings, w, 0, nullptr);
}

std::size_t GpuSculptor::redo_on_host(int axis, std::span<const std::uint32_t> rays, std::span<const GridSweep> sweeps,
                                      const ToolTable& tools, bool rewrite) {
    std::size_t changed = 0;
    const int nu = slabs_.nu(axis);
    std::vector<Interval> ray;
    for (const std::uint32_t id : rays) {
        const int u = static_cast<int>(id % static_cast<std::uint32_t>(nu)), v = static_cast<int>(id / static_cast<std::uint32_t>(nu));
        ray = mirror_.sets[axis].rays[id];  // the ray before the batch (the slabs' copy may be written in part)
        const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
        bool any = false;
        for (const GridSweep& g : sweeps)
            if (u >= g.lo[ua] && u <= g.hi[ua] && v >= g.lo[va] && v <= g.hi[va]) any |= apply_sweep_to_ray(g, axis, u, v, ray, static_cast<float>(mirror_.lattice.cells[axis]), tools);
        changed += any;
        if (!any && !rewrite) continue;
        if (!slabs_.write_ray(axis, u, v, ray)) {
            ++stats_.compactions;
            if (slabs_.compact(context_, axis)) bind_descriptors();
            if (!slabs_.write_ray(axis, u, v, ray)) throw Error("GPU tri-dexel: no pool room after compaction (internal error)");
        }
    }
    return changed;
}

void GpuSculptor::write_rays(std::span<const RayImage> rays, const Aabb& box_m) {
    for (const RayImage& r : rays) {
        if (r.axis > 2 || r.index >= mirror_.sets[r.axis].rays.size())
            throw Error("GPU tri-dexel: ray image outside the model (axis " + std::to_string(r.axis) + ", ray " +
                        std::to_string(r.index) + ")");
        const int nu = slabs_.nu(r.axis);
        const int u = static_cast<int>(r.index % static_cast<std::uint32_t>(nu)), v = static_cast<int>(r.index / static_cast<std::uint32_t>(nu));
        if (!slabs_.write_ray(r.axis, u, v, r.intervals)) {
            ++stats_.compactions;
            if (slabs_.compact(context_, r.axis)) bind_descriptors();
            if (!slabs_.write_ray(r.axis, u, v, r.intervals)) throw Error("GPU tri-dexel: no pool room after compaction (internal error)");
        }
        mirror_.sets[r.axis].rays[r.index] = r.intervals;
    }
    if (!rays.empty()) mirror_.mark_dirty(box_m);
}

void GpuSculptor::store_mirror_ray(int axis, std::uint32_t index) {
    if (axis < 0 || axis > 2 || index >= mirror_.sets[axis].rays.size())
        throw Error("GPU tri-dexel: ray outside the model (axis " + std::to_string(axis) + ", ray " + std::to_string(index) + ")");
    const int nu = slabs_.nu(axis);
    const int u = static_cast<int>(index % static_cast<std::uint32_t>(nu)), v = static_cast<int>(index / static_cast<std::uint32_t>(nu));
    const std::vector<Interval>& ray = mirror_.sets[axis].rays[index];
    if (slabs_.write_ray(axis, u, v, ray)) return;
    ++stats_.compactions;
    if (slabs_.compact(context_, axis)) bind_descriptors();
    if (!slabs_.write_ray(axis, u, v, ray)) throw Error("GPU tri-dexel: no pool room after compaction (internal error)");
}

BooleanStats GpuSculptor::apply(std::span<const Sweep> batch) {
    BooleanStats stats;
    const GridBatch converted = to_grid_batch(mirror_.lattice, batch);  // throws before anything changes
    if (converted.sweeps.empty()) return stats;
    upload_tools(converted.tools);  // throws before anything changes when the tools do not fit
    // The sweeps go in a uniform buffer of max_sweeps_ entries: longer batches run as several, in order.
    const std::span<const GridSweep> all(converted.sweeps);
    const std::span<const std::size_t> sources(converted.source);
    for (std::size_t at = 0; at < all.size(); at += max_sweeps_) {
        const std::size_t n = std::min(max_sweeps_, all.size() - at);
        const BooleanStats part = apply_grid(batch, all.subspan(at, n), sources.subspan(at, n), converted.tools);
        stats.rays_visited += part.rays_visited;
        stats.rays_changed += part.rays_changed;
    }
    return stats;
}

// A chunk's ray tiles under its sweeps' footprints (list_tiles) and the order the kernel takes them in (order_tiles).
struct GpuSculptor::TileList {
    std::vector<TileEntry> tiles;      // per set a contiguous range: base[a] .. base[a] + count[a]
    std::vector<std::uint32_t> index;  // each tile's sweeps (positions in the chunk) in batch order, from TileEntry::first
    std::uint32_t base[3] = {0, 0, 0}, count[3] = {0, 0, 0};
    std::size_t rays_visited = 0;      // footprint rays summed over the sweeps (BooleanStats::rays_visited)
    std::vector<TileEntry> order;      // the tiles as the kernel takes them (balance_tiles), then the done words
};

BooleanStats GpuSculptor::apply_grid(std::span<const Sweep> batch, std::span<const GridSweep> grid, std::span<const std::size_t> source,
                                     const ToolTable& tools) {
    BooleanStats stats;
    using Clock = std::chrono::steady_clock;
    const auto t_start = Clock::now();
    TileList list;
    list_tiles(grid, list);
    stats.rays_visited = list.rays_visited;
    if (list.tiles.empty()) return stats;
    upload_batch(list, grid);
    const VkPipeline pipeline = tools.empty() ? pipeline_for_chunk(grid) : mesh_pipeline_.get();
    const std::uint32_t groups = order_tiles(list, grid, tools);
    const auto t_submit = dispatch(pipeline, groups, list.tiles.size());
    const auto t_done = Clock::now();
    ++stats_.batches;
    stats_.sweeps += grid.size();
    stats_.ray_tiles += list.tiles.size();
    stats.rays_changed += finish_on_host(list, grid, tools);
    read_footprint_rays(list);
    if (stats.rays_changed > 0)
        for (const std::size_t i : source) mirror_.mark_dirty(sweep_dirty_bounds(batch[i], mirror_.lattice));
    stats_.prepare_s += std::chrono::duration<double>(t_submit - t_start).count();
    stats_.submit_s += std::chrono::duration<double>(t_done - t_submit).count();
    stats_.finish_s += std::chrono::duration<double>(Clock::now() - t_done).count();
    return stats;
}

void GpuSculptor::list_tiles(std::span<const GridSweep> grid, TileList& list) const {
    // Per set, the ray tiles under each sweep's footprint; each tile lists its sweeps in batch order (a counting sort
    // over the batch's box of tiles: count, prefix sums, then fill in batch order).
    struct Span {  // the tiles of one row of tiles (tv) that sweep s reaches: tu0..tu1
        std::uint32_t s;
        int tv, tu0, tu1;
    };
    std::vector<Span> spans;
    std::vector<std::uint32_t> slot;
    std::vector<TileEntry>& tiles = list.tiles;
    std::vector<std::uint32_t>& index = list.index;
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = mirror_.sets[a];
        spans.clear();
        int bu0 = INT32_MAX, bu1 = -1, bv0 = INT32_MAX, bv1 = -1;
        for (std::uint32_t s = 0; s < grid.size(); ++s) {
            int u0, u1, v0, v1;
            if (!sweep_footprint(grid[s], set, u0, u1, v0, v1)) continue;
            list.rays_visited += static_cast<std::size_t>(u1 - u0 + 1) * static_cast<std::size_t>(v1 - v0 + 1);
            // Only the tiles holding a ray of the swept volume's shadow (SweepShadow): the kernel would find no chord
            // on the others.
            const SweepShadow shadow(grid[s], a);
            for (int tv = v0 / kTileV; tv <= v1 / kTileV; ++tv) {
                int lo = u0, hi = u1;
                if (!shadow.band(std::max(v0, tv * kTileV), std::min(v1, tv * kTileV + kTileV - 1), lo, hi)) continue;
                const Span sp{s, tv, lo / kTileU, hi / kTileU};
                bu0 = std::min(bu0, sp.tu0);
                bu1 = std::max(bu1, sp.tu1);
                bv0 = std::min(bv0, sp.tv);
                bv1 = std::max(bv1, sp.tv);
                spans.push_back(sp);
            }
        }
        list.base[a] = static_cast<std::uint32_t>(tiles.size());
        if (spans.empty()) continue;
        const std::size_t bw = static_cast<std::size_t>(bu1 - bu0 + 1);
        slot.assign(bw * static_cast<std::size_t>(bv1 - bv0 + 1), 0u);
        for (const Span& sp : spans)
            for (int tu = sp.tu0; tu <= sp.tu1; ++tu) ++slot[static_cast<std::size_t>(sp.tv - bv0) * bw + static_cast<std::size_t>(tu - bu0)];
        // slot[i]: the tile's count -> the index position where its next sweep goes.
        for (std::size_t i = 0; i < slot.size(); ++i) {
            if (slot[i] == 0) continue;
            const TileEntry t{static_cast<std::uint32_t>(bu0 + static_cast<int>(i % bw)) | static_cast<std::uint32_t>(a) << kSetShift,
                              static_cast<std::uint32_t>(bv0 + static_cast<int>(i / bw)),
                              static_cast<std::uint32_t>(index.size()), slot[i]};
            tiles.push_back(t);
            slot[i] = t.first;
            index.resize(index.size() + t.count);
        }
        for (const Span& sp : spans)
            for (int tu = sp.tu0; tu <= sp.tu1; ++tu) index[slot[static_cast<std::size_t>(sp.tv - bv0) * bw + static_cast<std::size_t>(tu - bu0)]++] = sp.s;
        list.count[a] = static_cast<std::uint32_t>(tiles.size()) - list.base[a];
    }
}

void GpuSculptor::upload_batch(const TileList& list, std::span<const GridSweep> grid) {
    const std::uint32_t most = std::max({list.count[0], list.count[1], list.count[2]});
    ensure_batch_capacity(list.tiles.size(), list.index.size(), static_cast<std::size_t>(most) * kTileU * kTileV);
    sweeps_.write(grid.data(), grid.size() * sizeof(GridSweep));
    index_.write(list.index.data(), list.index.size() * sizeof(std::uint32_t));
    for (int a = 0; a < 3; ++a) {
        const std::uint32_t head[4] = {slabs_.pool_head(a), 0, 0, 0};
        counters_[a].write(head, sizeof(head));
    }
}

VkPipeline GpuSculptor::pipeline_for_chunk(std::span<const GridSweep> grid) {
    // The kernel variant with only the chunk's operations and tool kinds.
    std::uint32_t ops = 0, kinds = 0;
    for (const GridSweep& g : grid) {
        ops |= 1u << ((g.code & 0xffu) - 1u);  // kSubtract 1, kUnion 2, kPaint 3 (kNone never reaches here)
        kinds |= 1u << ((g.code >> 8) & 0xffu);  // kBall 0, kFlatEnd 1, kMesh 2
    }
    return pipeline_for(ops, kinds);
}

std::uint32_t GpuSculptor::order_tiles(TileList& list, std::span<const GridSweep> grid, const ToolTable& tools) {
    // One dispatch for all three sets: the sets write disjoint buffers and each set's pool head is advanced
    // atomically. Its workgroups_ workgroups (at most one per tile, more when llvmpipe's loop budget needs them:
    // groups_within_loop_budget) take the tiles in turn (workgroup w: tiles w, w + groups, ...). The tiles are
    // ordered over the whole list (balance_tiles) after the host kept each set's range for the mirror.
    const std::size_t listed = list.tiles.size();
    list.order = list.tiles;
    balance_tiles(list.order.begin(), list.order.end());
    const std::uint32_t groups = groups_within_loop_budget(list.order, list.index, grid, tools, workgroups_, loop_budget_);
    list.order.resize(listed + (listed + 3) / 4, TileEntry{0, 0, 0, 0});  // the done words, all 0
    tiles_.write(list.order.data(), list.order.size() * sizeof(TileEntry));
    return groups;
}

std::chrono::steady_clock::time_point GpuSculptor::dispatch(VkPipeline pipeline, std::uint32_t groups, std::size_t listed) {
    Push push{};
    for (int a = 0; a < 3; ++a)
        push.sets[a] = SetPush{slabs_.nu(a), slabs_.nv(a), slabs_.pool_chunks(a), static_cast<float>(mirror_.lattice.cells[a])};
    push.retry_capacity = static_cast<std::uint32_t>(retry_capacity_);
    push.tile_count = static_cast<std::uint32_t>(listed);
    const auto t_submit = std::chrono::steady_clock::now();
    submitter_.run([&](VkCommandBuffer cmd) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_.get(), 0, 1, &set_, 0, nullptr);
        vkCmdPushConstants(cmd, pipeline_layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Push), &push);
        vkCmdDispatch(cmd, groups, 1, 1);
        ++stats_.dispatches;
        stats_.workgroups += groups;
        // Make the kernel's writes visible to the host reads that follow the fence.
        VkMemoryBarrier barrier{};
        barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
        barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
    });
    return t_submit;
}

std::size_t GpuSculptor::finish_on_host(const TileList& list, std::span<const GridSweep> grid, const ToolTable& tools) {
    // The rays the kernel handed back, and those it may have left half done (the loop cap): the rays it listed with
    // kRetryLoopCap and every ray of the tiles a workgroup never reached (no done word).
    const std::size_t listed = list.tiles.size();
    const std::vector<TileEntry>& order = list.order;
    std::size_t changed = 0;
    std::vector<std::uint32_t> retry, capped[3], done((listed + 3) / 4 * 4);
    tiles_.read(done.data(), done.size() * 4, listed * sizeof(TileEntry));
    for (std::size_t t = 0; t < listed; ++t) {
        if (done[t] != 0) continue;
        const int a = static_cast<int>(order[t].tu >> kSetShift), nu = slabs_.nu(a), nv = slabs_.nv(a);
        const int u0 = static_cast<int>(order[t].tu & kTileMask) * kTileU, v0 = static_cast<int>(order[t].tv) * kTileV;
        for (int v = v0; v < std::min(v0 + kTileV, nv); ++v)
            for (int u = u0; u < std::min(u0 + kTileU, nu); ++u) capped[a].push_back(static_cast<std::uint32_t>(u + nu * v));
    }
    for (int a = 0; a < 3; ++a) {
        std::uint32_t head[4];
        counters_[a].read(head, sizeof(head));
        slabs_.pool_head(a) = head[0];
        changed += head[2];
        if (head[1] > retry_capacity_) throw Error("GPU tri-dexel: retry list overflow (internal error)");
        retry.resize(head[1]);
        if (!retry.empty()) counters_[a].read(retry.data(), retry.size() * 4, 16);
        const auto cap_end = std::partition(retry.begin(), retry.end(), [](std::uint32_t r) { return (r & kRetryLoopCap) != 0; });
        for (auto it = retry.begin(); it != cap_end; ++it) capped[a].push_back(*it & ~kRetryLoopCap);
        retry.erase(retry.begin(), cap_end);
        stats_.retried_rays += retry.size() + capped[a].size();
        stats_.loop_capped_rays += capped[a].size();
        if (retry.empty() && capped[a].empty()) continue;
        // Compact only when the kernel ran out of pool (its head then points past the end); rays listed for
        // having more than 16 intervals need none, and redo_on_host compacts when a write finds no room.
        if (head[0] > slabs_.pool_chunks(a)) {
            ++stats_.compactions;
            if (slabs_.compact(context_, a)) bind_descriptors();
        }
        changed += redo_on_host(a, retry, grid, tools, false);
        changed += redo_on_host(a, capped[a], grid, tools, true);
    }
    return changed;
}

void GpuSculptor::read_footprint_rays(const TileList& list) {
    // The mirror's footprint rays (its dirty tiles are marked by apply_grid).
    for (int a = 0; a < 3; ++a) {
        RaySet& set = mirror_.sets[a];
        for (std::uint32_t t = list.base[a]; t < list.base[a] + list.count[a]; ++t) {
            const int u0 = static_cast<int>(list.tiles[t].tu & kTileMask) * kTileU, v0 = static_cast<int>(list.tiles[t].tv) * kTileV;
            for (int v = v0; v < std::min(v0 + kTileV, set.nv); ++v)
                for (int u = u0; u < std::min(u0 + kTileU, set.nu); ++u) slabs_.read_ray(a, u, v, set.ray(u, v));
        }
    }
}

}  // namespace tridex::compute
