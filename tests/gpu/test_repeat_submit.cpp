// gpu::RepeatSubmitter: one command buffer and fence reused for many submissions, both fence waits, on lavapipe
// with validation on.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "gpu/buffer.hpp"
#include "gpu/context.hpp"
#include "gpu/repeat_submit.hpp"

namespace tridex::gpu {
namespace {

// Fills `buf` with `value` on the GPU and makes the write visible to the host.
void record_fill(VkCommandBuffer cmd, const Buffer& buf, std::uint32_t value) {
    vkCmdFillBuffer(cmd, buf.handle(), 0, VK_WHOLE_SIZE, value);
    VkMemoryBarrier barrier{};
    barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

class RepeatSubmit : public ::testing::TestWithParam<FenceWait> {};

TEST_P(RepeatSubmit, EverySubmissionRunsAndFinishesBeforeRunReturns) {
    Context ctx = Context::create({});
    {
        Buffer buf = Buffer::create(ctx, 4096, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryDomain::kHost);
        RepeatSubmitter sub(ctx, GetParam());
        EXPECT_EQ(sub.wait_mode(), GetParam());
        std::vector<std::uint32_t> got(1024);
        for (std::uint32_t i = 1; i <= 50; ++i) {
            sub.run([&](VkCommandBuffer cmd) { record_fill(cmd, buf, 0x1000u + i); });
            buf.read(got.data(), 4096);
            ASSERT_EQ(got.front(), 0x1000u + i) << "submission " << i;
            ASSERT_EQ(got.back(), 0x1000u + i) << "submission " << i;
        }
        // An exception while recording submits nothing, and the submitter stays usable.
        EXPECT_THROW(sub.run([&](VkCommandBuffer cmd) {
            record_fill(cmd, buf, 7u);
            throw std::runtime_error("recording failed");
        }),
                     std::runtime_error);
        buf.read(got.data(), 4);
        EXPECT_EQ(got.front(), 0x1000u + 50u);
        sub.run([&](VkCommandBuffer cmd) { record_fill(cmd, buf, 9u); });
        buf.read(got.data(), 4);
        EXPECT_EQ(got.front(), 9u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Waits, RepeatSubmit, ::testing::Values(FenceWait::kBlock, FenceWait::kPoll),
                         [](const ::testing::TestParamInfo<FenceWait>& p) { return p.param == FenceWait::kBlock ? "Block" : "Poll"; });

}  // namespace
}  // namespace tridex::gpu
