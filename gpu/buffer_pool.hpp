// gpu/buffer_pool.hpp - many small host-visible buffers sub-allocated from a few large memory blocks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"

namespace tridex::gpu {

class BufferPool;

/// One VkBuffer bound to a range of a BufferPool block (host-visible, coherent, persistently mapped). Move-only
/// RAII: destroying it destroys the buffer and returns its range to the pool, which must outlive it; the GPU must
/// be done with it first.
class PooledBuffer {
public:
    PooledBuffer() = default;
    ~PooledBuffer();
    PooledBuffer(PooledBuffer&& o) noexcept;
    PooledBuffer& operator=(PooledBuffer&& o) noexcept;
    PooledBuffer(const PooledBuffer&) = delete;
    PooledBuffer& operator=(const PooledBuffer&) = delete;

    VkBuffer handle() const { return buffer_; }  ///< the buffer (VK_NULL_HANDLE when empty)
    VkDeviceSize size() const { return size_; }  ///< bytes asked for
    void* mapped() const { return mapped_; }     ///< its first byte in the mapped block
    /// A buffer spanning its whole block (usage: the pool's block_usage), so that draws of many PooledBuffers
    /// of one block can share one binding; VK_NULL_HANDLE when the pool makes none (block_usage 0) or when empty.
    VkBuffer block_buffer() const;
    /// Where this buffer starts in block_buffer(), bytes (a multiple of the alignment asked of allocate()).
    VkDeviceSize offset() const { return offset_; }

private:
    friend class BufferPool;
    void release();
    BufferPool* pool_ = nullptr;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
    std::size_t block_ = 0;
    VkDeviceSize offset_ = 0, span_ = 0;  // the range taken from the block (aligned), bytes
};

/// Sub-allocates host-visible, coherent buffers from VkDeviceMemory blocks of block_bytes (larger requests get a
/// block of their own size), first fit over each block's sorted free ranges, with freed ranges merged with their
/// neighbours; a block that becomes empty is freed unless it is the only one. Real GPUs allow only about 4096
/// live allocations (VkPhysicalDeviceLimits::maxMemoryAllocationCount), which thousands of per-tile buffers would
/// exceed; the pool needs a handful. Not thread-safe. Move-only; the Context must outlive it, and it must outlive
/// its PooledBuffers.
class BufferPool {
public:
    /// A pool making blocks of `block_bytes` (> 0; default 32 MiB). Allocates nothing yet. With block_usage
    /// non-zero, each block also gets one buffer of that usage over all of it (PooledBuffer::block_buffer; a
    /// block whose memory type that buffer cannot use gets none). Throws tridex::Error when block_bytes is 0.
    static std::unique_ptr<BufferPool> create(const Context& context, VkDeviceSize block_bytes = VkDeviceSize{32} << 20,
                                              VkBufferUsageFlags block_usage = 0);
    ~BufferPool();
    BufferPool(const BufferPool&) = delete;
    BufferPool& operator=(const BufferPool&) = delete;

    /// A buffer of `bytes` (> 0) with `usage`, bound to a range of a block (a new block when none has room) that
    /// starts at a multiple of `alignment` bytes (>= 1; e.g. a vertex stride, so a draw sharing the block's
    /// buffer can address it by vertexOffset) and of the buffer's own required alignment.
    /// Throws tridex::Error when bytes or alignment is 0 or on a Vulkan failure (out of memory, no host-visible type).
    PooledBuffer allocate(VkDeviceSize bytes, VkBufferUsageFlags usage, VkDeviceSize alignment = 1);

    std::size_t blocks() const;          ///< VkDeviceMemory allocations held now
    std::size_t live_buffers() const { return live_; }  ///< PooledBuffers not yet destroyed
    VkDeviceSize used_bytes() const;     ///< bytes of the blocks taken by live buffers (aligned)
    VkDeviceSize block_bytes() const { return block_bytes_; }  ///< the usual block size

private:
    friend class PooledBuffer;
    struct Range {
        VkDeviceSize offset, size;
    };
    struct Block {
        VkDeviceMemory memory = VK_NULL_HANDLE;
        std::uint32_t type = 0;
        VkDeviceSize size = 0;
        void* mapped = nullptr;
        VkBuffer whole = VK_NULL_HANDLE;  // over the whole block (block_usage), or null
        std::vector<Range> free;  // sorted by offset, never adjacent
    };
    BufferPool() = default;
    void give_back(std::size_t block, VkDeviceSize offset, VkDeviceSize span);
    void free_block(Block& b);
    const Context* context_ = nullptr;
    VkDeviceSize block_bytes_ = 0;
    VkBufferUsageFlags block_usage_ = 0;
    std::vector<Block> blocks_;  // a freed block keeps its slot (memory null) so indices stay valid
    std::size_t live_ = 0;
};

}  // namespace tridex::gpu
