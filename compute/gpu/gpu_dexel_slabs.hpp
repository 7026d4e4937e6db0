// compute/gpu/gpu_dexel_slabs.hpp - the tri-dexel model in GPU buffers: per ray set a structure-of-arrays
// slab with two inline intervals per ray plus a spill pool for rays that need more.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "gpu/buffer.hpp"
#include "gpu/context.hpp"

namespace tridex::compute {

/// Bytes of one ray set's slab on the GPU.
struct SlabBytes {
    std::size_t meta = 0;         ///< 4 B per ray: interval count, pool region (chunks) and offset
    std::size_t inline_depth = 0; ///< 16 B per ray: two (enter, exit) pairs, float grid units
    std::size_t inline_mat = 0;   ///< 4 B per ray: the four end materials of the inline intervals
    std::size_t pool = 0;         ///< spill pool: 12 B per interval slot (depths + materials)
    std::size_t total() const { return meta + inline_depth + inline_mat + pool; }
};

/// The tri-dexel model's intervals in host-visible storage buffers, one slab per ray set
/// (DESIGN.md, representation hints). Per ray: `meta` = count (bits 0-6, <= 120) | pool region size in
/// chunks of 8 intervals (bits 7-10) | region offset in chunks (bits 11-31); rays with <= 2 intervals
/// keep them in the inline slots, longer rays in their pool region. Pool regions are handed out by the
/// GPU kernel from a bump counter; abandoned regions are reclaimed by compact(). No binding exceeds the
/// device's maxStorageBufferRange (128 MiB on lavapipe): the pool is at most 2^21 chunks and the inline
/// arrays are refused up front when a set's rays would not fit.
/// The buffers are host-visible (on lavapipe, the only memory there is), so the host reads and writes
/// rays directly between submissions. Not thread-safe; the GPU must be idle when the host touches it.
class GpuDexelSlabs {
public:
    static constexpr int kInline = 2;             ///< intervals stored in a ray's own slots
    static constexpr int kChunk = 8;              ///< intervals per pool chunk
    static constexpr int kMaxRayIntervals = 120;  ///< most intervals a ray can hold (15 chunks)
    static constexpr std::uint32_t kMaxPoolChunks = 1u << 21;  ///< offset field width; 128 MiB of depths

    /// Bytes a model on `lattice` needs with `pool_chunks` pool chunks per set (per set, all sets equal
    /// in size only for cubic lattices, so returned per set).
    static std::array<SlabBytes, 3> bytes_for(const Lattice& lattice, std::uint32_t pool_chunks);

    /// Refuses, before anything is allocated, a lattice whose slabs would not fit `context`'s device: a ray
    /// set's inline depth array or a pool of `pool_chunks` chunks over maxStorageBufferRange, or all slabs
    /// together over half the largest memory heap. Throws tridex::Error with the resolution, both sizes in
    /// MiB and the way out (--resolution, --cpu). Returns the total bytes otherwise.
    static std::size_t check_fits(const gpu::Context& context, const Lattice& lattice, const std::array<std::uint32_t, 3>& pool_chunks);

    /// Uploads `model` into new slabs. Throws tridex::Error, before allocating, when one set's inline
    /// array would exceed the device's maxStorageBufferRange, or the whole model would exceed the
    /// largest device-local heap (the message names the resolution, both sizes, and suggests
    /// --resolution or --cpu), or a ray has more than kMaxRayIntervals intervals. `pool_chunks` > 0
    /// sets each set's initial pool size (grown at once if the model needs more); 0 = twice the model's
    /// need, at least 4096 chunks.
    static GpuDexelSlabs upload(const gpu::Context& context, const TriDexel& model, std::uint32_t pool_chunks = 0);

    /// Storage buffers of ray set `axis`: binding order of shaders/dexel_sweep.comp (0 meta, 1 inline
    /// depths, 2 inline materials, 3 pool depths, 4 pool materials).
    const gpu::Buffer& buffer(int axis, int binding) const { return sets_[axis].buffers[binding]; }
    /// Pool capacity of set `axis`, chunks.
    std::uint32_t pool_chunks(int axis) const { return sets_[axis].pool_chunks; }
    /// Chunks handed out in set `axis` (the kernel's bump counter; may exceed pool_chunks after a failed
    /// allocation, until compact()).
    std::uint32_t& pool_head(int axis) { return sets_[axis].pool_head; }

    /// Reads ray (u, v) of set `axis` into `out` (replaced). Never throws for valid indices.
    void read_ray(int axis, int u, int v, std::vector<Interval>& out) const;
    /// Writes `ray` into ray (u, v) of set `axis`, using the ray's pool region when it is big enough or
    /// a new region at the pool head. Returns false (ray unchanged) when the pool has no room;
    /// throws tridex::Error when the ray has more than kMaxRayIntervals intervals.
    bool write_ray(int axis, int u, int v, const std::vector<Interval>& ray);

    /// Repacks set `axis`'s pool so live regions are contiguous (each sized to its ray), and grows it
    /// (doubling, up to kMaxPoolChunks) until at least half of it is free. Buffers may be replaced:
    /// callers re-bind descriptors when it returns true. Throws tridex::Error when even kMaxPoolChunks
    /// cannot hold the live intervals (the message gives the numbers).
    bool compact(const gpu::Context& context, int axis);

    /// Intervals held in pool regions (rays with more than kInline intervals), all sets.
    std::uint64_t spilled_intervals() const;
    /// Current bytes of each set's slab.
    std::array<SlabBytes, 3> bytes() const;
    /// Decodes every ray into `out` (same lattice), for tests and checks.
    void download(TriDexel& out) const;
    /// Rays of set `axis` along u and v.
    int nu(int axis) const { return sets_[axis].nu; }
    int nv(int axis) const { return sets_[axis].nv; }

private:
    struct Set {
        int nu = 0, nv = 0;
        std::uint32_t pool_chunks = 0;
        std::uint32_t pool_head = 0;
        std::array<gpu::Buffer, 5> buffers;
    };
    void create_pool(const gpu::Context& context, Set& set, std::uint32_t chunks);
    std::array<Set, 3> sets_;
};

}  // namespace tridex::compute
