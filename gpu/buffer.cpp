// gpu/buffer.cpp - buffer creation per memory domain, mapped access and staged copies.
#include "gpu/buffer.hpp"

#include <cstring>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "gpu/check.hpp"

namespace tridex::gpu {
namespace {

void check_range(const char* what, std::size_t bytes, std::size_t offset, VkDeviceSize size) {
    if (offset > size || bytes > size - offset)
        throw Error(std::string("gpu: Buffer::") + what + " range [" + std::to_string(offset) + ", " +
                    std::to_string(offset + bytes) + ") exceeds the buffer size " + std::to_string(size));
}

}  // namespace

Buffer Buffer::create(const Context& context, VkDeviceSize bytes, VkBufferUsageFlags usage, MemoryDomain domain) {
    if (bytes == 0) throw Error("gpu: Buffer::create with size 0");
    Buffer b;
    b.device_ = context.device();
    b.size_ = bytes;
    b.domain_ = domain;
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = bytes;
    info.usage = usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(vkCreateBuffer(b.device_, &info, nullptr, &b.buffer_), "vkCreateBuffer");

    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(b.device_, b.buffer_, &req);
    const VkMemoryPropertyFlags required = domain == MemoryDomain::kHost
        ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
        : 0;
    const VkMemoryPropertyFlags preferred = domain == MemoryDomain::kHost
        ? VK_MEMORY_PROPERTY_HOST_CACHED_BIT
        : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    VkMemoryAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = context.memory_type(req.memoryTypeBits, required, preferred);
    check(vkAllocateMemory(b.device_, &alloc, nullptr, &b.memory_), "vkAllocateMemory");
    check(vkBindBufferMemory(b.device_, b.buffer_, b.memory_, 0), "vkBindBufferMemory");
    if (domain == MemoryDomain::kHost)
        check(vkMapMemory(b.device_, b.memory_, 0, VK_WHOLE_SIZE, 0, &b.mapped_), "vkMapMemory");
    return b;
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& o) noexcept
    : device_(o.device_),
      buffer_(std::exchange(o.buffer_, VK_NULL_HANDLE)),
      memory_(std::exchange(o.memory_, VK_NULL_HANDLE)),
      size_(std::exchange(o.size_, 0)),
      domain_(o.domain_),
      mapped_(std::exchange(o.mapped_, nullptr)) {}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        release();
        device_ = o.device_;
        buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
        memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
        size_ = std::exchange(o.size_, 0);
        domain_ = o.domain_;
        mapped_ = std::exchange(o.mapped_, nullptr);
    }
    return *this;
}

void Buffer::release() {
    if (buffer_ != VK_NULL_HANDLE) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_ != VK_NULL_HANDLE) vkFreeMemory(device_, memory_, nullptr);  // also unmaps
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
    size_ = 0;
}

void Buffer::write(const void* src, std::size_t bytes, std::size_t offset) {
    if (!mapped_) throw Error("gpu: Buffer::write on a buffer that is not in MemoryDomain::kHost");
    check_range("write", bytes, offset, size_);
    std::memcpy(static_cast<std::uint8_t*>(mapped_) + offset, src, bytes);
}

void Buffer::read(void* dst, std::size_t bytes, std::size_t offset) const {
    if (!mapped_) throw Error("gpu: Buffer::read on a buffer that is not in MemoryDomain::kHost");
    check_range("read", bytes, offset, size_);
    std::memcpy(dst, static_cast<const std::uint8_t*>(mapped_) + offset, bytes);
}

void upload(const Context& context, const Buffer& dst, const void* src, std::size_t bytes, std::size_t offset) {
    check_range("upload", bytes, offset, dst.size());
    if (bytes == 0) return;
    Buffer staging = Buffer::create(context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryDomain::kHost);
    staging.write(src, bytes);
    context.submit_and_wait([&](VkCommandBuffer cmd) {
        const VkBufferCopy region{0, offset, bytes};
        vkCmdCopyBuffer(cmd, staging.handle(), dst.handle(), 1, &region);
        // Later submissions (any stage) see the copied bytes.
        VkMemoryBarrier barrier{};
        barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
        barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &barrier,
                             0, nullptr, 0, nullptr);
    });
}

void download(const Context& context, const Buffer& src, void* dst, std::size_t bytes, std::size_t offset) {
    check_range("download", bytes, offset, src.size());
    if (bytes == 0) return;
    Buffer staging = Buffer::create(context, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryDomain::kHost);
    context.submit_and_wait([&](VkCommandBuffer cmd) {
        const VkBufferCopy region{offset, 0, bytes};
        vkCmdCopyBuffer(cmd, src.handle(), staging.handle(), 1, &region);
        // Make the transfer write visible to host reads after the fence.
        VkMemoryBarrier barrier{};
        barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
        barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0,
                             nullptr, 0, nullptr);
    });
    staging.read(dst, bytes);
}

}  // namespace tridex::gpu
