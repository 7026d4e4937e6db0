// gpu/buffer_pool.cpp - first-fit sub-allocation of buffers from large host-visible memory blocks.
#include "gpu/buffer_pool.hpp"

#include <algorithm>
#include <numeric>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "gpu/check.hpp"

namespace tridex::gpu {
namespace {

VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return a <= 1 ? v : (v + a - 1) / a * a; }

}  // namespace

PooledBuffer::~PooledBuffer() { release(); }

PooledBuffer::PooledBuffer(PooledBuffer&& o) noexcept
    : pool_(std::exchange(o.pool_, nullptr)),
      buffer_(std::exchange(o.buffer_, VK_NULL_HANDLE)),
      size_(std::exchange(o.size_, 0)),
      mapped_(std::exchange(o.mapped_, nullptr)),
      block_(o.block_),
      offset_(o.offset_),
      span_(o.span_) {}

PooledBuffer& PooledBuffer::operator=(PooledBuffer&& o) noexcept {
    if (this != &o) {
        release();
        pool_ = std::exchange(o.pool_, nullptr);
        buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
        size_ = std::exchange(o.size_, 0);
        mapped_ = std::exchange(o.mapped_, nullptr);
        block_ = o.block_;
        offset_ = o.offset_;
        span_ = o.span_;
    }
    return *this;
}

void PooledBuffer::release() {
    if (!pool_) return;
    if (buffer_ != VK_NULL_HANDLE) vkDestroyBuffer(pool_->context_->device(), buffer_, nullptr);
    pool_->give_back(block_, offset_, span_);
    pool_ = nullptr;
    buffer_ = VK_NULL_HANDLE;
    size_ = 0;
    mapped_ = nullptr;
}

VkBuffer PooledBuffer::block_buffer() const { return pool_ ? pool_->blocks_[block_].whole : VK_NULL_HANDLE; }

std::unique_ptr<BufferPool> BufferPool::create(const Context& context, VkDeviceSize block_bytes,
                                               VkBufferUsageFlags block_usage) {
    if (block_bytes == 0) throw Error("gpu: BufferPool block size must be > 0");
    std::unique_ptr<BufferPool> p(new BufferPool());
    p->context_ = &context;
    p->block_bytes_ = block_bytes;
    p->block_usage_ = block_usage;
    return p;
}

BufferPool::~BufferPool() {
    for (Block& b : blocks_) free_block(b);
}

void BufferPool::free_block(Block& b) {
    if (b.whole != VK_NULL_HANDLE) vkDestroyBuffer(context_->device(), b.whole, nullptr);
    if (b.memory != VK_NULL_HANDLE) vkFreeMemory(context_->device(), b.memory, nullptr);  // also unmaps
    b = Block{};
}

std::size_t BufferPool::blocks() const {
    return static_cast<std::size_t>(
        std::count_if(blocks_.begin(), blocks_.end(), [](const Block& b) { return b.memory != VK_NULL_HANDLE; }));
}

VkDeviceSize BufferPool::used_bytes() const {
    VkDeviceSize used = 0;
    for (const Block& b : blocks_) {
        if (b.memory == VK_NULL_HANDLE) continue;
        used += b.size;
        for (const Range& r : b.free) used -= r.size;
    }
    return used;
}

PooledBuffer BufferPool::allocate(VkDeviceSize bytes, VkBufferUsageFlags usage, VkDeviceSize alignment) {
    if (bytes == 0) throw Error("gpu: BufferPool::allocate with size 0");
    if (alignment == 0) throw Error("gpu: BufferPool::allocate with alignment 0");
    const VkDevice device = context_->device();
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = bytes;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkBuffer buffer = VK_NULL_HANDLE;
    check(vkCreateBuffer(device, &info, nullptr, &buffer), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, buffer, &req);
    const auto fail = [&](const auto& e) {
        vkDestroyBuffer(device, buffer, nullptr);
        throw e;
    };
    std::uint32_t type = 0;
    try {
        type = context_->memory_type(req.memoryTypeBits,
                                     VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                     VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    } catch (const Error& e) {
        fail(e);
    }
    const VkDeviceSize align = std::lcm(std::max<VkDeviceSize>(req.alignment, 1), alignment);
    // First fit in a block of that memory type; else a new block (in a freed block's slot when there is one).
    std::size_t block = blocks_.size();
    VkDeviceSize offset = 0, span = 0;
    for (std::size_t i = 0; i < blocks_.size() && block == blocks_.size(); ++i) {
        Block& b = blocks_[i];
        if (b.memory == VK_NULL_HANDLE || b.type != type) continue;
        for (std::size_t k = 0; k < b.free.size(); ++k) {
            const VkDeviceSize start = align_up(b.free[k].offset, align);
            const VkDeviceSize end = b.free[k].offset + b.free[k].size;
            if (start + req.size > end) continue;
            block = i;
            offset = start;
            span = req.size;
            break;
        }
    }
    if (block == blocks_.size()) {
        Block b;
        b.type = type;
        b.size = std::max(block_bytes_, align_up(req.size, align));
        VkMemoryAllocateInfo alloc{};
        alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
        alloc.allocationSize = b.size;
        alloc.memoryTypeIndex = type;
        const VkResult r = vkAllocateMemory(device, &alloc, nullptr, &b.memory);
        if (r != VK_SUCCESS)
            fail(Error("gpu: BufferPool could not allocate a block of " + std::to_string(b.size) + " bytes (" +
                       std::to_string(static_cast<int>(r)) + ")"));
        if (vkMapMemory(device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped) != VK_SUCCESS) {
            vkFreeMemory(device, b.memory, nullptr);
            fail(Error("gpu: BufferPool could not map a block"));
        }
        if (block_usage_ != 0) {  // one buffer over the whole block, aliasing the sub-allocated ones
            VkBufferCreateInfo whole = info;
            whole.size = b.size;
            whole.usage = block_usage_;
            if (vkCreateBuffer(device, &whole, nullptr, &b.whole) == VK_SUCCESS) {
                VkMemoryRequirements wreq;
                vkGetBufferMemoryRequirements(device, b.whole, &wreq);
                if (!(wreq.memoryTypeBits & (1u << type)) || wreq.size > b.size ||
                    vkBindBufferMemory(device, b.whole, b.memory, 0) != VK_SUCCESS) {
                    vkDestroyBuffer(device, b.whole, nullptr);
                    b.whole = VK_NULL_HANDLE;
                }
            } else {
                b.whole = VK_NULL_HANDLE;
            }
        }
        b.free.push_back(Range{0, b.size});
        const auto empty = std::find_if(blocks_.begin(), blocks_.end(),
                                        [](const Block& x) { return x.memory == VK_NULL_HANDLE; });
        block = empty == blocks_.end() ? blocks_.size() : static_cast<std::size_t>(empty - blocks_.begin());
        if (empty == blocks_.end())
            blocks_.push_back(std::move(b));
        else
            *empty = std::move(b);
        offset = 0;
        span = req.size;
    }
    // Take [offset, offset + span) out of the free range holding it.
    Block& b = blocks_[block];
    for (std::size_t k = 0; k < b.free.size(); ++k) {
        const Range r = b.free[k];
        if (offset < r.offset || offset + span > r.offset + r.size) continue;
        std::vector<Range> parts;
        if (offset > r.offset) parts.push_back(Range{r.offset, offset - r.offset});
        if (offset + span < r.offset + r.size) parts.push_back(Range{offset + span, r.offset + r.size - offset - span});
        b.free.erase(b.free.begin() + static_cast<std::ptrdiff_t>(k));
        b.free.insert(b.free.begin() + static_cast<std::ptrdiff_t>(k), parts.begin(), parts.end());
        break;
    }
    if (vkBindBufferMemory(device, buffer, b.memory, offset) != VK_SUCCESS) {
        give_back(block, offset, span);
        fail(Error("gpu: BufferPool could not bind a buffer"));
    }
    PooledBuffer out;
    out.pool_ = this;
    out.buffer_ = buffer;
    out.size_ = bytes;
    out.mapped_ = static_cast<std::uint8_t*>(b.mapped) + offset;
    out.block_ = block;
    out.offset_ = offset;
    out.span_ = span;
    ++live_;
    return out;
}

void BufferPool::give_back(std::size_t block, VkDeviceSize offset, VkDeviceSize span) {
    --live_;
    Block& b = blocks_.at(block);
    auto it = std::lower_bound(b.free.begin(), b.free.end(), offset,
                               [](const Range& r, VkDeviceSize o) { return r.offset < o; });
    it = b.free.insert(it, Range{offset, span});
    // Merge with the following and the preceding range when they touch.
    if (auto next = it + 1; next != b.free.end() && it->offset + it->size == next->offset) {
        it->size += next->size;
        b.free.erase(next);
    }
    if (it != b.free.begin()) {
        auto prev = it - 1;
        if (prev->offset + prev->size == it->offset) {
            prev->size += it->size;
            b.free.erase(it);
        }
    }
    // An empty block goes back to the driver unless it is the only one.
    if (b.free.size() == 1 && b.free[0].size == b.size && blocks() > 1) free_block(b);
}

}  // namespace tridex::gpu
