// gpu/buffer.hpp - a VkBuffer with its own memory, created in a named memory domain.
#pragma once

#include <cstddef>
#include <cstdint>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"

namespace tridex::gpu {

/// Where a buffer's memory lives.
enum class MemoryDomain {
    kDevice,  ///< device-local; not mapped, fill it with upload() (staging copy)
    kHost,    ///< host-visible and coherent, persistently mapped; for uploads each frame and readback
};

/// One VkBuffer bound to its own VkDeviceMemory allocation. Move-only RAII; the Context must outlive it,
/// and the GPU must be done with it before it is destroyed (callers wait on their submissions).
class Buffer {
public:
    Buffer() = default;
    /// Creates a buffer of `bytes` (> 0) with `usage` in `domain`; kDevice buffers also get
    /// TRANSFER_DST usage so upload() works. Throws tridex::Error when bytes == 0 or on a Vulkan failure
    /// (out of memory, no suitable memory type).
    static Buffer create(const Context& context, VkDeviceSize bytes, VkBufferUsageFlags usage, MemoryDomain domain);

    ~Buffer();
    Buffer(Buffer&& o) noexcept;
    Buffer& operator=(Buffer&& o) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    VkBuffer handle() const { return buffer_; }     ///< the buffer (VK_NULL_HANDLE when empty)
    VkDeviceSize size() const { return size_; }      ///< size in bytes
    MemoryDomain domain() const { return domain_; }  ///< the memory domain it was created in
    /// Mapped pointer of a kHost buffer (valid for its lifetime); nullptr for kDevice.
    void* mapped() const { return mapped_; }

    /// Copies `bytes` from `src` into a kHost buffer at `offset`. Throws tridex::Error if the buffer is
    /// not kHost or the range [offset, offset + bytes) exceeds size().
    void write(const void* src, std::size_t bytes, std::size_t offset = 0);
    /// Copies `bytes` at `offset` of a kHost buffer into `dst`. Same errors as write().
    void read(void* dst, std::size_t bytes, std::size_t offset = 0) const;

private:
    void release();
    VkDevice device_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    MemoryDomain domain_ = MemoryDomain::kHost;
    void* mapped_ = nullptr;
};

/// Copies `bytes` from host memory into `dst` at `offset` (any domain) through a temporary staging
/// buffer and a one-shot submission; returns when the copy is complete. Throws tridex::Error when the
/// range exceeds dst.size() or on a Vulkan failure.
void upload(const Context& context, const Buffer& dst, const void* src, std::size_t bytes, std::size_t offset = 0);

/// Copies `bytes` at `offset` of `src` (any domain) into host memory `dst`, waiting for completion.
/// Same errors as upload().
void download(const Context& context, const Buffer& src, void* dst, std::size_t bytes, std::size_t offset = 0);

}  // namespace tridex::gpu
