// gpu::BufferPool: thousands of small buffers in a few memory blocks, aligned and non-overlapping, ranges merged
// when freed, empty blocks returned, oversized requests in a block of their own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/error.hpp"
#include "gpu/buffer_pool.hpp"
#include "gpu/context.hpp"

namespace tridex::gpu {
namespace {

TEST(BufferPool, ManyBuffersFewBlocksNoOverlap) {
    Context ctx = Context::create({});
    {
        auto pool = BufferPool::create(ctx, VkDeviceSize{4} << 20);
        EXPECT_EQ(pool->blocks(), 0u);
        std::vector<PooledBuffer> buffers;
        for (int i = 0; i < 5000; ++i)  // 2500 tiles' vertex and index buffers, 200..1700 bytes each
            buffers.push_back(pool->allocate(200 + (i * 37) % 1500,
                                             i % 2 ? VK_BUFFER_USAGE_INDEX_BUFFER_BIT : VK_BUFFER_USAGE_VERTEX_BUFFER_BIT));
        std::printf("5000 buffers in %zu blocks of %llu bytes, %llu bytes used\n", pool->blocks(),
                    static_cast<unsigned long long>(pool->block_bytes()),
                    static_cast<unsigned long long>(pool->used_bytes()));
        EXPECT_LE(pool->blocks(), 3u);  // about 5 MB of buffers
        EXPECT_EQ(pool->live_buffers(), 5000u);
        // Every buffer writable through its mapping, none overlapping another: fill each with its index, then
        // check all.
        for (std::size_t i = 0; i < buffers.size(); ++i)
            std::memset(buffers[i].mapped(), static_cast<int>(i % 251), buffers[i].size());
        for (std::size_t i = 0; i < buffers.size(); ++i) {
            const auto* p = static_cast<const std::uint8_t*>(buffers[i].mapped());
            ASSERT_TRUE(std::all_of(p, p + buffers[i].size(), [&](std::uint8_t b) { return b == i % 251; }))
                << "buffer " << i << " overwritten";
        }
        // Free every other one, then allocate them again: the freed ranges are reused, no new block.
        const std::size_t blocks = pool->blocks();
        for (std::size_t i = 0; i < buffers.size(); i += 2) buffers[i] = PooledBuffer{};
        EXPECT_EQ(pool->live_buffers(), 2500u);
        for (std::size_t i = 0; i < buffers.size(); i += 2)
            buffers[i] = pool->allocate(200 + (i * 37) % 1500, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        EXPECT_EQ(pool->blocks(), blocks);
        // A request larger than a block gets a block of its own, given back when freed.
        PooledBuffer big = pool->allocate(VkDeviceSize{6} << 20, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        EXPECT_EQ(pool->blocks(), blocks + 1);
        big = PooledBuffer{};
        EXPECT_EQ(pool->blocks(), blocks);
        // Everything freed: the ranges merge back into whole blocks, all but one returned.
        buffers.clear();
        EXPECT_EQ(pool->live_buffers(), 0u);
        EXPECT_EQ(pool->blocks(), 1u);
        EXPECT_EQ(pool->used_bytes(), 0u);
        EXPECT_THROW(pool->allocate(0, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT), Error);
    }
    EXPECT_THROW(BufferPool::create(ctx, 0), Error);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// With a block usage, every buffer of a block is reachable through the block's shared buffer at offset(), which is
// a multiple of the alignment asked for (e.g. a 28-byte vertex stride); without one there is no shared buffer.
TEST(BufferPool, BlockBufferAndAlignment) {
    Context ctx = Context::create({});
    {
        auto plain = BufferPool::create(ctx, VkDeviceSize{1} << 20);
        const PooledBuffer p = plain->allocate(100, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, 28);
        EXPECT_EQ(p.block_buffer(), VkBuffer{VK_NULL_HANDLE});
        EXPECT_EQ(p.offset() % 28, 0u);
        EXPECT_THROW(plain->allocate(100, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, 0), Error);

        auto pool = BufferPool::create(ctx, VkDeviceSize{1} << 20,
                                       VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
        std::vector<PooledBuffer> buffers;
        for (int i = 0; i < 400; ++i)  // about 1.2 MB: at least two blocks
            buffers.push_back(pool->allocate(1000 + (i * 53) % 4000, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, 28));
        EXPECT_GE(pool->blocks(), 2u);
        std::vector<VkBuffer> shared;
        for (const PooledBuffer& b : buffers) {
            ASSERT_NE(b.block_buffer(), VkBuffer{VK_NULL_HANDLE});
            EXPECT_EQ(b.offset() % 28, 0u);
            EXPECT_NE(b.block_buffer(), b.handle());
            if (std::find(shared.begin(), shared.end(), b.block_buffer()) == shared.end()) shared.push_back(b.block_buffer());
        }
        EXPECT_EQ(shared.size(), pool->blocks());  // one shared buffer per block
        // Buffers of one block sit at distinct offsets of its mapping: mapped() - offset() is the block's start.
        for (const PooledBuffer& b : buffers)
            for (const PooledBuffer& c : buffers) {
                if (b.block_buffer() != c.block_buffer()) continue;
                ASSERT_EQ(static_cast<std::uint8_t*>(b.mapped()) - b.offset(), static_cast<std::uint8_t*>(c.mapped()) - c.offset());
            }
        buffers.clear();
        EXPECT_EQ(pool->blocks(), 1u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::gpu
