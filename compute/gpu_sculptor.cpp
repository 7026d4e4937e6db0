// compute/gpu_sculptor.cpp - batching sweeps into ray tiles, the compute dispatch, and the host's share
// (retried rays, pool compaction, the CPU mirror).
#include "compute/gpu_sculptor.hpp"

#include <algorithm>
#include <cstring>
#include <sstream>

#include "core/error.hpp"
#include "gpu/check.hpp"
#include "gpu/compute_pipeline.hpp"
#include "gpu/shader_module.hpp"
#include "shaders/spirv.hpp"

namespace tridex::compute {
namespace {

constexpr int kTileRays = 8;           // rays per tile side (the kernel's local size)
constexpr std::uint32_t kMaxGroups = 65535;  // workgroups per dispatch we rely on (the Vulkan minimum)
constexpr int kBindings = 10;
constexpr std::size_t kMaxBinding = std::size_t{128} << 20;  // lavapipe's maxStorageBufferRange

struct Push {
    std::int32_t axis, nu, nv;
    std::uint32_t tile_base, pool_chunks, retry_capacity;
    float depth_cells;  // the lattice's cells along `axis`: union chords are clipped to [0, depth_cells]
};

struct TileEntry {
    std::uint32_t tu, tv, first, count;
};

// Orders one dispatch's tiles so that every contiguous 1/2, 1/4 or 1/8 of them carries about the same
// work: sorted by sweep count (the work per ray), descending, then dealt by the bit-reversed residue of the
// rank modulo 8 (ranks 0, 8, 16, ... first, then 4, 12, ..., then 2, 10, ...). llvmpipe (Mesa
// lp_cs_tpool) gives each of its threads one contiguous block of workgroups, so the tiles' order decides
// its balance; tiles are independent, so the order changes no result.
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
    : context_(context), mirror_(mirror), slabs_(GpuDexelSlabs::upload(context, mirror, options.initial_pool_chunks)) {
    const VkDevice dev = context.device();
    gpu::ComputeLayout cl = gpu::create_compute_layout(context, kBindings, sizeof(Push));
    const VkDescriptorSetLayout layout = cl.set_layout.get();
    set_layout_ = std::move(cl.set_layout);
    pipeline_layout_ = std::move(cl.pipeline_layout);

    // Two variants of the kernel: the specialisation constant HAS_MESH (constant_id 0) compiles the mesh-tool
    // path in or out, so batches without mesh tools run the smaller kernel (1.5x faster on llvmpipe).
    const gpu::UniqueShaderModule module = gpu::create_shader_module(context, shaders::spirv("dexel_sweep_comp"));
    for (int variant = 0; variant < 2; ++variant) {
        const VkBool32 has_mesh = variant == 1 ? VK_TRUE : VK_FALSE;
        const VkSpecializationMapEntry entry{0, 0, sizeof(VkBool32)};
        VkSpecializationInfo spec{};
        spec.mapEntryCount = 1;
        spec.pMapEntries = &entry;
        spec.dataSize = sizeof(VkBool32);
        spec.pData = &has_mesh;
        (variant == 1 ? mesh_pipeline_ : pipeline_) =
            gpu::create_compute_pipeline(context, module.get(), pipeline_layout_.get(), &spec);
    }

    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3 * kBindings};
    VkDescriptorPoolCreateInfo pi{};
    pi.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    pi.maxSets = 3;
    pi.poolSizeCount = 1;
    pi.pPoolSizes = &size;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    gpu::check(vkCreateDescriptorPool(dev, &pi, nullptr, &pool), "vkCreateDescriptorPool");
    descriptor_pool_ = gpu::UniqueDescriptorPool(dev, pool);
    VkDescriptorSetLayout layouts[3] = {layout, layout, layout};
    VkDescriptorSetAllocateInfo ai{};
    ai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    ai.descriptorPool = pool;
    ai.descriptorSetCount = 3;
    ai.pSetLayouts = layouts;
    gpu::check(vkAllocateDescriptorSets(dev, &ai, sets_), "vkAllocateDescriptorSets");

    tools_ = host_storage(context_, 16);
    ensure_batch_capacity(64, 256, 1024, 256 * 64);
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

void GpuSculptor::ensure_batch_capacity(std::size_t sweeps, std::size_t tiles, std::size_t indices, std::size_t retry) {
    bool rebind = sets_[0] != VK_NULL_HANDLE && sweeps_.handle() == VK_NULL_HANDLE;
    auto grow = [&](gpu::Buffer& buf, std::size_t bytes) {
        if (buf.handle() != VK_NULL_HANDLE && buf.size() >= bytes) return;
        buf = host_storage(context_, std::max<std::size_t>(bytes, buf.size() * 2));
        rebind = true;
    };
    grow(sweeps_, sweeps * sizeof(GridSweep));
    grow(tiles_, tiles * sizeof(TileEntry));
    grow(index_, indices * sizeof(std::uint32_t));
    if (retry > retry_capacity_ || counters_[0].handle() == VK_NULL_HANDLE) {
        retry_capacity_ = std::max(retry, retry_capacity_ * 2);
        for (auto& c : counters_) c = host_storage(context_, 16 + 4 * retry_capacity_);
        rebind = true;
    }
    if (rebind) bind_descriptors();
}

void GpuSculptor::bind_descriptors() {
    for (int a = 0; a < 3; ++a) {
        const gpu::Buffer* bufs[kBindings] = {&slabs_.buffer(a, 0), &slabs_.buffer(a, 1), &slabs_.buffer(a, 2),
                                              &slabs_.buffer(a, 3), &slabs_.buffer(a, 4), &sweeps_,
                                              &tiles_,              &index_,              &counters_[a],
                                              &tools_};
        VkDescriptorBufferInfo info[kBindings];
        VkWriteDescriptorSet w[kBindings]{};
        for (int i = 0; i < kBindings; ++i) {
            info[i] = VkDescriptorBufferInfo{bufs[i]->handle(), 0, VK_WHOLE_SIZE};
            w[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
            w[i].dstSet = sets_[a];
            w[i].dstBinding = static_cast<std::uint32_t>(i);
            w[i].descriptorCount = 1;
            w[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            w[i].pBufferInfo = &info[i];
        }
        vkUpdateDescriptorSets(context_.device(), kBindings, w, 0, nullptr);
    }
}

std::size_t GpuSculptor::redo_on_host(int axis, std::span<const std::uint32_t> rays, std::span<const GridSweep> sweeps,
                                      const ToolTable& tools) {
    std::size_t changed = 0;
    const int nu = slabs_.nu(axis);
    std::vector<Interval> ray;
    for (const std::uint32_t id : rays) {
        const int u = static_cast<int>(id % static_cast<std::uint32_t>(nu)), v = static_cast<int>(id / static_cast<std::uint32_t>(nu));
        slabs_.read_ray(axis, u, v, ray);
        const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
        bool any = false;
        for (const GridSweep& g : sweeps)
            if (u >= g.lo[ua] && u <= g.hi[ua] && v >= g.lo[va] && v <= g.hi[va]) any |= apply_sweep_to_ray(g, axis, u, v, ray, static_cast<float>(mirror_.lattice.cells[axis]), tools);
        if (!any) continue;
        ++changed;
        if (!slabs_.write_ray(axis, u, v, ray)) {
            ++stats_.compactions;
            if (slabs_.compact(context_, axis)) bind_descriptors();
            if (!slabs_.write_ray(axis, u, v, ray)) throw Error("GPU tri-dexel: no pool room after compaction (internal error)");
        }
    }
    return changed;
}

BooleanStats GpuSculptor::apply(std::span<const Sweep> batch) {
    BooleanStats stats;
    const GridBatch converted = to_grid_batch(mirror_.lattice, batch);  // throws before anything changes
    const std::vector<GridSweep>& grid = converted.sweeps;
    const std::vector<std::size_t>& source = converted.source;
    if (grid.empty()) return stats;
    upload_tools(converted.tools);  // throws before anything changes when the tools do not fit

    // Ray tiles under each sweep's footprint, per set; each tile lists its sweeps in batch order.
    std::vector<TileEntry> tiles;
    std::vector<std::uint32_t> index;
    std::uint32_t base[3] = {0, 0, 0}, count[3] = {0, 0, 0};
    std::vector<std::pair<std::uint64_t, std::uint32_t>> pairs;
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = mirror_.sets[a];
        const int tiles_u = (set.nu + kTileRays - 1) / kTileRays;
        pairs.clear();
        for (std::uint32_t s = 0; s < grid.size(); ++s) {
            int u0, u1, v0, v1;
            if (!sweep_footprint(grid[s], set, u0, u1, v0, v1)) continue;
            stats.rays_visited += static_cast<std::size_t>(u1 - u0 + 1) * static_cast<std::size_t>(v1 - v0 + 1);
            for (int tv = v0 / kTileRays; tv <= v1 / kTileRays; ++tv)
                for (int tu = u0 / kTileRays; tu <= u1 / kTileRays; ++tu)
                    pairs.emplace_back(static_cast<std::uint64_t>(tu) + static_cast<std::uint64_t>(tiles_u) * tv, s);
        }
        std::stable_sort(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        base[a] = static_cast<std::uint32_t>(tiles.size());
        for (std::size_t i = 0; i < pairs.size();) {
            std::size_t j = i;
            TileEntry t{static_cast<std::uint32_t>(pairs[i].first % tiles_u), static_cast<std::uint32_t>(pairs[i].first / tiles_u),
                        static_cast<std::uint32_t>(index.size()), 0};
            for (; j < pairs.size() && pairs[j].first == pairs[i].first; ++j) index.push_back(pairs[j].second);
            t.count = static_cast<std::uint32_t>(j - i);
            tiles.push_back(t);
            i = j;
        }
        count[a] = static_cast<std::uint32_t>(tiles.size()) - base[a];
        balance_tiles(tiles.begin() + base[a], tiles.end());
    }
    if (tiles.empty()) return stats;
    const std::uint32_t most = std::max({count[0], count[1], count[2]});
    ensure_batch_capacity(grid.size(), tiles.size(), index.size(), static_cast<std::size_t>(most) * kTileRays * kTileRays);
    sweeps_.write(grid.data(), grid.size() * sizeof(GridSweep));
    tiles_.write(tiles.data(), tiles.size() * sizeof(TileEntry));
    index_.write(index.data(), index.size() * sizeof(std::uint32_t));
    for (int a = 0; a < 3; ++a) {
        const std::uint32_t head[4] = {slabs_.pool_head(a), 0, 0, 0};
        counters_[a].write(head, sizeof(head));
    }

    context_.submit_and_wait([&](VkCommandBuffer cmd) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, converted.tools.empty() ? pipeline_.get() : mesh_pipeline_.get());
        for (int a = 0; a < 3; ++a) {
            if (count[a] == 0) continue;
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_.get(), 0, 1, &sets_[a], 0, nullptr);
            for (std::uint32_t done = 0; done < count[a]; done += kMaxGroups) {
                const Push push{a, slabs_.nu(a), slabs_.nv(a), base[a] + done, slabs_.pool_chunks(a),
                                static_cast<std::uint32_t>(retry_capacity_),
                                static_cast<float>(mirror_.lattice.cells[a])};
                vkCmdPushConstants(cmd, pipeline_layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Push), &push);
                vkCmdDispatch(cmd, std::min(kMaxGroups, count[a] - done), 1, 1);
                ++stats_.dispatches;
            }
        }
        // Make the kernel's writes visible to the host reads that follow the fence.
        VkMemoryBarrier barrier{};
    barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
        barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
    });
    ++stats_.batches;
    stats_.sweeps += grid.size();
    stats_.ray_tiles += tiles.size();

    std::vector<std::uint32_t> retry;
    for (int a = 0; a < 3; ++a) {
        std::uint32_t head[4];
        counters_[a].read(head, sizeof(head));
        slabs_.pool_head(a) = head[0];
        stats.rays_changed += head[2];
        if (head[1] == 0) continue;
        if (head[1] > retry_capacity_) throw Error("GPU tri-dexel: retry list overflow (internal error)");
        retry.resize(head[1]);
        counters_[a].read(retry.data(), retry.size() * 4, 16);
        stats_.retried_rays += retry.size();
        ++stats_.compactions;
        if (slabs_.compact(context_, a)) bind_descriptors();
        stats.rays_changed += redo_on_host(a, retry, grid, converted.tools);
    }
    // The mirror's footprint rays, then its dirty tiles.
    for (int a = 0; a < 3; ++a) {
        RaySet& set = mirror_.sets[a];
        for (std::uint32_t t = base[a]; t < base[a] + count[a]; ++t) {
            const int u0 = static_cast<int>(tiles[t].tu) * kTileRays, v0 = static_cast<int>(tiles[t].tv) * kTileRays;
            for (int v = v0; v < std::min(v0 + kTileRays, set.nv); ++v)
                for (int u = u0; u < std::min(u0 + kTileRays, set.nu); ++u) slabs_.read_ray(a, u, v, set.ray(u, v));
        }
    }
    if (stats.rays_changed > 0)
        for (const std::size_t i : source) mirror_.mark_dirty(sweep_bounds(batch[i]));
    return stats;
}

}  // namespace tridex::compute
