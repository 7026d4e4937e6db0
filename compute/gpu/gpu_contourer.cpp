// compute/gpu/gpu_contourer.cpp - the contouring pipeline, its descriptors, and update(): dispatch, read the
// per-tile status, re-allocate and redispatch tiles whose region was too small, host-contour tiles the kernel hands back.
#include "compute/gpu/gpu_contourer.hpp"

#include <algorithm>
#include <string>

#include "compute/contour/contour_table.hpp"
#include "core/error.hpp"
#include "gpu/check.hpp"
#include "gpu/descriptor_sets.hpp"
#include "gpu/compute_pipeline.hpp"
#include "gpu/shader_module.hpp"
#include "shaders/spirv.hpp"

namespace tridex::compute {
namespace {

constexpr int kBindings = 23;
constexpr std::uint32_t kMaxGroups = 65535;
// Tile states the kernel reports: done; region too small; contour on the host (lists full; the device's loop cap hit).
constexpr std::uint32_t kOk = 0, kOverflow = 1, kSplit = 2, kLoopCap = 3;

struct Push {
    std::int32_t cells[4];
    std::int32_t tiles[4];
    std::uint32_t job_base;
};

gpu::Buffer host_storage(const gpu::Context& c, std::size_t bytes, VkBufferUsageFlags extra = 0) {
    return gpu::Buffer::create(c, std::max<std::size_t>(bytes, 16), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | extra, gpu::MemoryDomain::kHost);
}

}  // namespace

GpuContourer::GpuContourer(const gpu::Context& context, const GpuDexelSlabs& slabs, const Lattice& lattice,
                           std::size_t initial_vertices, std::size_t initial_indices)
    : context_(context), slabs_(slabs), lattice_(lattice) {
    if (!context.features().shader_float64)
        throw Error("GPU contouring: the device '" + context.device_name() + "' lacks shaderFloat64; contour on the CPU");
    for (int a = 0; a < 3; ++a) {
        if (lattice.cells[a] < 1 || slabs.nu(a) != lattice.nodes((a + 1) % 3) || slabs.nv(a) != lattice.nodes((a + 2) % 3))
            throw Error("GPU contouring: the slabs of ray set " + std::string(1, "XYZ"[a]) + " do not match the lattice");
        tiles_[a] = (lattice.cells[a] + TileGrid::kTileCells - 1) / TileGrid::kTileCells;
    }
    const std::size_t tiles = static_cast<std::size_t>(tiles_[0]) * tiles_[1] * tiles_[2];
    regions_.assign(tiles, Region{});
    create_pipeline();

    std::vector<std::uint32_t> table(256 * 4, 0);
    const auto& cases = contour::cell_cases();
    for (int c = 0; c < 256; ++c) {
        table[4 * c] = cases[c].components | (static_cast<std::uint32_t>(cases[c].merged_faces) << 8);
        for (int e = 0; e < 12; ++e)
            table[4 * c + 1 + e / 8] |= static_cast<std::uint32_t>(cases[c].edge_component[e] + 1) << (4 * (e % 8));
    }
    cases_ = host_storage(context, table.size() * 4);
    cases_.write(table.data(), table.size() * 4);
    jobs_ = host_storage(context, tiles * 4);
    status_ = host_storage(context, tiles * 16);
    regions_buf_ = host_storage(context, tiles * 16);
    std::fill_n(static_cast<std::uint32_t*>(regions_buf_.mapped()), tiles * 4, 0u);
    commands_ = host_storage(context, tiles * 20, VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT);
    std::fill_n(static_cast<std::uint32_t*>(commands_.mapped()), tiles * 5, 0u);
    vpool_ = initial_vertices > 0 ? initial_vertices : 64 * 1024;
    ipool_ = initial_indices > 0 ? initial_indices : 384 * 1024;
    vertices_ = host_storage(context, vpool_ * sizeof(GpuContourVertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    vertices_d_ = host_storage(context, vpool_ * 24);
    indices_ = host_storage(context, ipool_ * 4, VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
}

GpuContourer::~GpuContourer() = default;

void GpuContourer::create_pipeline() {
    const VkDevice dev = context_.device();
    gpu::ComputeLayout cl = gpu::create_compute_layout(context_, kBindings, sizeof(Push));
    const VkDescriptorSetLayout layout = cl.set_layout.get();
    set_layout_ = std::move(cl.set_layout);
    pipeline_layout_ = std::move(cl.pipeline_layout);
    const gpu::UniqueShaderModule module = gpu::create_shader_module(context_, shaders::spirv("dexel_contour_comp"));
    pipeline_ = gpu::create_compute_pipeline(context_, module.get(), pipeline_layout_.get());

    descriptor_pool_ = gpu::allocate_descriptor_sets(dev, {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kBindings}}, layout, 1, &set_);
}

void GpuContourer::bind_descriptors() {
    const gpu::Buffer* bufs[kBindings];
    for (int a = 0; a < 3; ++a)
        for (int i = 0; i < 5; ++i) bufs[5 * a + i] = &slabs_.buffer(a, i);
    const gpu::Buffer* rest[8] = {&cases_, &jobs_, &regions_buf_, &status_, &vertices_, &vertices_d_, &indices_, &commands_};
    for (int i = 0; i < 8; ++i) bufs[15 + i] = rest[i];
    VkDescriptorBufferInfo info[kBindings];
    VkWriteDescriptorSet w[kBindings]{};
    for (int i = 0; i < kBindings; ++i) {
        info[i] = VkDescriptorBufferInfo{bufs[i]->handle(), 0, VK_WHOLE_SIZE};
        w[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        w[i].dstSet = set_;
        w[i].dstBinding = static_cast<std::uint32_t>(i);
        w[i].descriptorCount = 1;
        w[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w[i].pBufferInfo = &info[i];
    }
    vkUpdateDescriptorSets(context_.device(), kBindings, w, 0, nullptr);
}

void GpuContourer::dispatch(const std::vector<std::uint32_t>& jobs) {
    if (jobs.empty()) return;
    jobs_.write(jobs.data(), jobs.size() * 4);
    bind_descriptors();  // the slabs may have replaced buffers (pool compaction) since the last call
    const auto count = static_cast<std::uint32_t>(jobs.size());
    context_.submit_and_wait([&](VkCommandBuffer cmd) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_.get(), 0, 1, &set_, 0, nullptr);
        for (std::uint32_t done = 0; done < count; done += kMaxGroups) {
            const Push push{{lattice_.cells[0], lattice_.cells[1], lattice_.cells[2], 0}, {tiles_[0], tiles_[1], tiles_[2], 0}, done};
            vkCmdPushConstants(cmd, pipeline_layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Push), &push);
            vkCmdDispatch(cmd, std::min(kMaxGroups, count - done), 1, 1);
            ++stats_.dispatches;
        }
        // The kernel's writes: visible to the host (status), and to later draws (indirect, index, vertex).
        VkMemoryBarrier barrier{};
        barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
        barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_INDEX_READ_BIT |
                                VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                             VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, 0, 1,
                             &barrier, 0, nullptr, 0, nullptr);
    });
}

std::size_t GpuContourer::update(std::span<const std::uint32_t> tiles) {
    std::vector<std::uint32_t> jobs(tiles.begin(), tiles.end());
    std::sort(jobs.begin(), jobs.end());
    jobs.erase(std::unique(jobs.begin(), jobs.end()), jobs.end());
    if (!jobs.empty() && jobs.back() >= regions_.size())
        throw Error("GPU contouring: tile " + std::to_string(jobs.back()) + " out of range (the lattice has " +
                    std::to_string(regions_.size()) + " tiles)");
    stats_.last_tiles = jobs.size();
    stats_.last_cpu_tiles = 0;
    if (jobs.empty()) return 0;
    ++stats_.updates;
    std::vector<std::uint32_t> host;
    for (int round = 0; !jobs.empty(); ++round) {
        dispatch(jobs);
        std::vector<std::uint32_t> retry;
        const auto* status = static_cast<const std::uint32_t*>(status_.mapped());
        // First every finished tile's counts (a pool regrow below copies regions by them), then the rest.
        for (std::size_t j = 0; j < jobs.size(); ++j)
            if (status[4 * j] == kOk) {
                regions_[jobs[j]].vused = status[4 * j + 1];
                regions_[jobs[j]].iused = status[4 * j + 2];
                stats_.split_faces_gpu += status[4 * j + 3];
                ++stats_.tiles_gpu;
            }
        for (std::size_t j = 0; j < jobs.size(); ++j) {
            const std::uint32_t t = jobs[j], state = status[4 * j], nv = status[4 * j + 1], ni = status[4 * j + 2];
            if (state == kOk) continue;
            if (state == kSplit || state == kLoopCap) {
                host.push_back(t);
                if (state == kLoopCap) ++stats_.tiles_loop_capped;
            } else if (state == kOverflow && round == 0) {
                reserve(t, nv, ni);
                retry.push_back(t);
                ++stats_.region_retries;
            } else {
                throw Error("GPU contouring: tile " + std::to_string(t) + " reported state " + std::to_string(state) +
                            " after its region was sized for it (internal error)");
            }
        }
        jobs = std::move(retry);
    }
    for (const std::uint32_t t : host) contour_on_host(t);
    stats_.tiles_cpu += host.size();
    stats_.last_cpu_tiles = host.size();
    pieces_.clear();
    return stats_.last_tiles;
}

std::size_t GpuContourer::update_dirty(const TileGrid& grid) {
    if (grid.count() != regions_.size())
        throw Error("GPU contouring: the tile grid has " + std::to_string(grid.count()) + " tiles, the contourer " +
                    std::to_string(regions_.size()));
    return update(grid.dirty_tiles());
}

std::uint32_t GpuContourer::tile_index_count(std::size_t tile) const {
    if (tile >= regions_.size())
        throw Error("GPU contouring: tile " + std::to_string(tile) + " out of range (the lattice has " +
                    std::to_string(regions_.size()) + " tiles)");
    return regions_[tile].iused;
}

}  // namespace tridex::compute
