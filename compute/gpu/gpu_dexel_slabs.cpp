// compute/gpu/gpu_dexel_slabs.cpp - encoding rays into GPU slabs, reading them back, compacting the pool.
#include "compute/gpu/gpu_dexel_slabs.hpp"

#include <algorithm>
#include <cstring>
#include <sstream>

#include "core/error.hpp"

namespace tridex::compute {
namespace {

constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

std::uint32_t meta_word(std::uint32_t count, std::uint32_t cap, std::uint32_t off) { return count | (cap << 7) | (off << 11); }
std::uint32_t meta_count(std::uint32_t m) { return m & 127u; }
std::uint32_t meta_cap(std::uint32_t m) { return (m >> 7) & 15u; }
std::uint32_t meta_off(std::uint32_t m) { return m >> 11; }
std::uint32_t chunks_for(std::size_t n) { return static_cast<std::uint32_t>((n + GpuDexelSlabs::kChunk - 1) / GpuDexelSlabs::kChunk); }
std::uint32_t mat_pair(const Interval& iv) { return iv.enter_material | (static_cast<std::uint32_t>(iv.exit_material) << 8); }

std::size_t rays_of(const Lattice& L, int axis) {
    return static_cast<std::size_t>(L.nodes((axis + 1) % 3)) * static_cast<std::size_t>(L.nodes((axis + 2) % 3));
}

std::size_t largest_heap(const gpu::Context& context) {
    VkPhysicalDeviceMemoryProperties props{};
    vkGetPhysicalDeviceMemoryProperties(context.physical_device(), &props);
    std::size_t best = 0;
    for (std::uint32_t i = 0; i < props.memoryHeapCount; ++i) best = std::max<std::size_t>(best, props.memoryHeaps[i].size);
    return best;
}

}  // namespace

std::array<SlabBytes, 3> GpuDexelSlabs::bytes_for(const Lattice& L, std::uint32_t pool_chunks) {
    std::array<SlabBytes, 3> b{};
    for (int a = 0; a < 3; ++a) {
        const std::size_t rays = rays_of(L, a);
        b[a].meta = rays * 4;
        b[a].inline_depth = rays * 16;
        b[a].inline_mat = rays * 4;
        b[a].pool = static_cast<std::size_t>(pool_chunks) * kChunk * 12;
    }
    return b;
}

void GpuDexelSlabs::create_pool(const gpu::Context& context, Set& set, std::uint32_t chunks) {
    set.pool_chunks = chunks;
    const std::size_t slots = static_cast<std::size_t>(chunks) * kChunk;
    set.buffers[3] = gpu::Buffer::create(context, slots * 8, kStorage, gpu::MemoryDomain::kHost);
    set.buffers[4] = gpu::Buffer::create(context, slots * 4, kStorage, gpu::MemoryDomain::kHost);
}

std::size_t GpuDexelSlabs::check_fits(const gpu::Context& context, const Lattice& L, const std::array<std::uint32_t, 3>& chunks) {
    const std::size_t range = context.properties().limits.maxStorageBufferRange;
    std::size_t total = 0;
    for (int a = 0; a < 3; ++a) {
        const SlabBytes b = bytes_for(L, chunks[a])[a];
        total += b.total();
        if (b.inline_depth > range || static_cast<std::size_t>(chunks[a]) * kChunk * 8 > range) {
            std::ostringstream msg;
            msg << "GPU tri-dexel: resolution " << L.cells[0] << "x" << L.cells[1] << "x" << L.cells[2] << " needs a "
                << std::max(b.inline_depth, static_cast<std::size_t>(chunks[a]) * kChunk * 8) / (1024 * 1024)
                << " MiB buffer for ray set " << "XYZ"[a] << ", more than the device's maxStorageBufferRange of "
                << range / (1024 * 1024) << " MiB; lower --resolution or sculpt with --cpu";
            throw Error(msg.str());
        }
    }
    const std::size_t heap = largest_heap(context);
    if (total > heap / 2) {
        std::ostringstream msg;
        msg << "GPU tri-dexel: resolution " << L.cells[0] << "x" << L.cells[1] << "x" << L.cells[2] << " needs "
            << total / (1024 * 1024) << " MiB of GPU memory, more than half of the device's " << heap / (1024 * 1024)
            << " MiB heap; lower --resolution or sculpt with --cpu";
        throw Error(msg.str());
    }
    return total;
}

GpuDexelSlabs GpuDexelSlabs::upload(const gpu::Context& context, const TriDexel& model, std::uint32_t pool_chunks) {
    const Lattice& L = model.lattice;
    // Pool demand of the initial model, per set.
    std::array<std::uint32_t, 3> need{}, chunks{};
    for (int a = 0; a < 3; ++a)
        for (const auto& ray : model.sets[a].rays) {
            if (ray.size() > static_cast<std::size_t>(kMaxRayIntervals)) {
                std::ostringstream msg;
                msg << "GPU tri-dexel: a ray of set " << "XYZ"[a] << " holds " << ray.size() << " intervals, more than the "
                    << kMaxRayIntervals << " the GPU layout stores; use --cpu";
                throw Error(msg.str());
            }
            if (ray.size() > static_cast<std::size_t>(kInline)) need[a] += chunks_for(ray.size());
        }
    for (int a = 0; a < 3; ++a) {
        const std::uint32_t want = pool_chunks > 0 ? std::max(pool_chunks, need[a]) : std::max<std::uint32_t>(4096u, 2u * need[a]);
        chunks[a] = std::min<std::uint32_t>(kMaxPoolChunks, want);
    }
    check_fits(context, L, chunks);
    GpuDexelSlabs s;
    for (int a = 0; a < 3; ++a) {
        Set& set = s.sets_[a];
        set.nu = model.sets[a].nu;
        set.nv = model.sets[a].nv;
        const std::size_t rays = rays_of(L, a);
        set.buffers[0] = gpu::Buffer::create(context, rays * 4, kStorage, gpu::MemoryDomain::kHost);
        set.buffers[1] = gpu::Buffer::create(context, rays * 16, kStorage, gpu::MemoryDomain::kHost);
        set.buffers[2] = gpu::Buffer::create(context, rays * 4, kStorage, gpu::MemoryDomain::kHost);
        s.create_pool(context, set, chunks[a]);
        std::memset(set.buffers[0].mapped(), 0, rays * 4);
        std::memset(set.buffers[1].mapped(), 0, rays * 16);
        std::memset(set.buffers[2].mapped(), 0, rays * 4);
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u) {
                const auto& ray = model.sets[a].ray(u, v);
                if (!ray.empty()) s.write_ray(a, u, v, ray);
            }
    }
    return s;
}

void GpuDexelSlabs::read_ray(int axis, int u, int v, std::vector<Interval>& out) const {
    const Set& set = sets_[axis];
    const std::size_t ray = static_cast<std::size_t>(u) + static_cast<std::size_t>(set.nu) * v;
    const std::uint32_t m = static_cast<const std::uint32_t*>(set.buffers[0].mapped())[ray];
    const std::uint32_t n = meta_count(m);
    out.resize(n);
    if (n <= static_cast<std::uint32_t>(kInline)) {
        const float* d = static_cast<const float*>(set.buffers[1].mapped()) + ray * 4;
        const std::uint32_t mm = static_cast<const std::uint32_t*>(set.buffers[2].mapped())[ray];
        for (std::uint32_t i = 0; i < n; ++i) {
            const std::uint32_t pair = i == 0 ? (mm & 0xffffu) : (mm >> 16);
            out[i] = Interval{d[2 * i], d[2 * i + 1], static_cast<std::uint8_t>(pair & 0xffu), static_cast<std::uint8_t>(pair >> 8)};
        }
    } else {
        const std::size_t off = static_cast<std::size_t>(meta_off(m)) * kChunk;
        const float* d = static_cast<const float*>(set.buffers[3].mapped());
        const std::uint32_t* mt = static_cast<const std::uint32_t*>(set.buffers[4].mapped());
        for (std::uint32_t i = 0; i < n; ++i) {
            const std::uint32_t pair = mt[off + i];
            out[i] = Interval{d[2 * (off + i)], d[2 * (off + i) + 1], static_cast<std::uint8_t>(pair & 0xffu),
                              static_cast<std::uint8_t>((pair >> 8) & 0xffu)};
        }
    }
}

bool GpuDexelSlabs::write_ray(int axis, int u, int v, const std::vector<Interval>& r) {
    Set& set = sets_[axis];
    if (r.size() > static_cast<std::size_t>(kMaxRayIntervals)) {
        std::ostringstream msg;
        msg << "GPU tri-dexel: ray (" << u << ", " << v << ") of set " << "XYZ"[axis] << " needs " << r.size()
            << " intervals, more than the " << kMaxRayIntervals << " the GPU layout stores; use --cpu";
        throw Error(msg.str());
    }
    const std::size_t ray = static_cast<std::size_t>(u) + static_cast<std::size_t>(set.nu) * v;
    std::uint32_t* meta = static_cast<std::uint32_t*>(set.buffers[0].mapped());
    const std::uint32_t m = meta[ray];
    std::uint32_t cap = meta_cap(m), off = meta_off(m);
    const std::uint32_t n = static_cast<std::uint32_t>(r.size());
    if (n <= static_cast<std::uint32_t>(kInline)) {
        float* d = static_cast<float*>(set.buffers[1].mapped()) + ray * 4;
        std::uint32_t mm = 0;
        for (int i = 0; i < 4; ++i) d[i] = 0.0f;
        for (std::uint32_t i = 0; i < n; ++i) {
            d[2 * i] = r[i].enter;
            d[2 * i + 1] = r[i].exit;
            mm |= mat_pair(r[i]) << (16 * i);
        }
        static_cast<std::uint32_t*>(set.buffers[2].mapped())[ray] = mm;
    } else {
        if (cap * kChunk < n) {
            const std::uint32_t need = chunks_for(n);
            if (set.pool_head + need > set.pool_chunks) return false;
            off = set.pool_head;
            cap = need;
            set.pool_head += need;
        }
        float* d = static_cast<float*>(set.buffers[3].mapped());
        std::uint32_t* mt = static_cast<std::uint32_t*>(set.buffers[4].mapped());
        const std::size_t base = static_cast<std::size_t>(off) * kChunk;
        for (std::uint32_t i = 0; i < n; ++i) {
            d[2 * (base + i)] = r[i].enter;
            d[2 * (base + i) + 1] = r[i].exit;
            mt[base + i] = mat_pair(r[i]);
        }
    }
    meta[ray] = meta_word(n, cap, off);
    return true;
}

bool GpuDexelSlabs::compact(const gpu::Context& context, int axis) {
    Set& set = sets_[axis];
    const std::size_t rays = static_cast<std::size_t>(set.nu) * set.nv;
    std::uint32_t* meta = static_cast<std::uint32_t*>(set.buffers[0].mapped());
    std::uint64_t live = 0;
    for (std::size_t i = 0; i < rays; ++i)
        if (meta_count(meta[i]) > static_cast<std::uint32_t>(kInline)) live += chunks_for(meta_count(meta[i]));
    std::uint64_t want = set.pool_chunks;
    while (want < kMaxPoolChunks && live * 2 > want) want *= 2;
    want = std::min<std::uint64_t>(want, kMaxPoolChunks);
    if (live > want) {
        std::ostringstream msg;
        msg << "GPU tri-dexel: ray set " << "XYZ"[axis] << " needs " << live * kChunk * 12 / (1024 * 1024)
            << " MiB of spill pool, more than the " << std::uint64_t{kMaxPoolChunks} * kChunk * 12 / (1024 * 1024)
            << " MiB one pool may bind; lower --resolution or sculpt with --cpu";
        throw Error(msg.str());
    }
    // Copy live regions out, then back in packed order (into a new, larger pool when growing).
    const float* d = static_cast<const float*>(set.buffers[3].mapped());
    const std::uint32_t* mt = static_cast<const std::uint32_t*>(set.buffers[4].mapped());
    std::vector<float> depth;
    std::vector<std::uint32_t> mats;
    depth.reserve(live * kChunk * 2);
    mats.reserve(live * kChunk);
    for (std::size_t i = 0; i < rays; ++i) {
        const std::uint32_t n = meta_count(meta[i]);
        if (n <= static_cast<std::uint32_t>(kInline)) {
            meta[i] = meta_word(n, 0, 0);  // drop a region a short ray no longer needs
            continue;
        }
        const std::size_t src = static_cast<std::size_t>(meta_off(meta[i])) * kChunk;
        const std::uint32_t at = static_cast<std::uint32_t>(mats.size() / kChunk);
        const std::uint32_t cap = chunks_for(n);
        for (std::uint32_t k = 0; k < cap * kChunk; ++k) {
            const bool used = k < n;
            depth.push_back(used ? d[2 * (src + k)] : 0.0f);
            depth.push_back(used ? d[2 * (src + k) + 1] : 0.0f);
            mats.push_back(used ? mt[src + k] : 0u);
        }
        meta[i] = meta_word(n, cap, at);
    }
    const bool grown = want != set.pool_chunks;
    if (grown) create_pool(context, set, static_cast<std::uint32_t>(want));
    if (!depth.empty()) {
        std::memcpy(set.buffers[3].mapped(), depth.data(), depth.size() * sizeof(float));
        std::memcpy(set.buffers[4].mapped(), mats.data(), mats.size() * sizeof(std::uint32_t));
    }
    set.pool_head = static_cast<std::uint32_t>(live);
    return grown;
}

std::uint64_t GpuDexelSlabs::spilled_intervals() const {
    std::uint64_t n = 0;
    for (const Set& set : sets_) {
        const std::uint32_t* meta = static_cast<const std::uint32_t*>(set.buffers[0].mapped());
        const std::size_t rays = static_cast<std::size_t>(set.nu) * set.nv;
        for (std::size_t i = 0; i < rays; ++i)
            if (meta_count(meta[i]) > static_cast<std::uint32_t>(kInline)) n += meta_count(meta[i]);
    }
    return n;
}

std::array<SlabBytes, 3> GpuDexelSlabs::bytes() const {
    std::array<SlabBytes, 3> b{};
    for (int a = 0; a < 3; ++a) {
        const Set& set = sets_[a];
        b[a].meta = set.buffers[0].size();
        b[a].inline_depth = set.buffers[1].size();
        b[a].inline_mat = set.buffers[2].size();
        b[a].pool = set.buffers[3].size() + set.buffers[4].size();
    }
    return b;
}

void GpuDexelSlabs::download(TriDexel& out) const {
    for (int a = 0; a < 3; ++a)
        for (int v = 0; v < sets_[a].nv; ++v)
            for (int u = 0; u < sets_[a].nu; ++u) read_ray(a, u, v, out.sets[a].ray(u, v));
}

}  // namespace tridex::compute
