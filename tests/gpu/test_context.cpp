// Tests of gpu/context: device selection on lavapipe, features, and the validation message counter.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <thread>

#include "core/error.hpp"
#include "gpu/check.hpp"
#include "gpu/context.hpp"
#include "gpu/device_clock.hpp"
#include "gpu/unique_handle.hpp"

namespace tridex::gpu {
namespace {

TEST(Context, CreatesLavapipeDeviceWithValidation) {
    Context ctx = Context::create({});
    // The test environment sets TRIDEX_VALIDATION=1 and VK_DRIVER_FILES=lavapipe.
    EXPECT_TRUE(ctx.validation_enabled());
    EXPECT_NE(ctx.device_name().find("llvmpipe"), std::string::npos) << ctx.device_name();
    EXPECT_GE(ctx.properties().apiVersion, VK_API_VERSION_1_2);
    EXPECT_NE(ctx.device(), VK_NULL_HANDLE);
    EXPECT_NE(ctx.queue(), VK_NULL_HANDLE);
    std::printf("device: %s, multiview %d, shaderOutputLayer %d\n", ctx.device_name().c_str(),
                ctx.features().multiview, ctx.features().shader_output_layer);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(Context, MoveKeepsTheDeviceAlive) {
    Context a = Context::create({.validation = true});
    const VkDevice device = a.device();
    Context b = std::move(a);
    EXPECT_EQ(b.device(), device);
    b.submit_and_wait([](VkCommandBuffer) {});  // an empty command buffer round trip
    EXPECT_EQ(b.validation_messages(), 0u);
}

TEST(Context, CountsValidationMessages) {
    // A buffer with usage 0 violates VUID-VkBufferCreateInfo-usage-requiredbitmask: the layer must
    // report it and the counter must see it (proves that "0 messages" in other tests means something).
    Context ctx = Context::create({.validation = true});
    ASSERT_EQ(ctx.validation_messages(), 0u);
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = 64;
    info.usage = 0;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkBuffer buffer = VK_NULL_HANDLE;
    std::fprintf(stderr, "(the next validation error is expected)\n");
    vkCreateBuffer(ctx.device(), &info, nullptr, &buffer);
    if (buffer != VK_NULL_HANDLE) vkDestroyBuffer(ctx.device(), buffer, nullptr);
    EXPECT_GE(ctx.validation_messages(), 1u);
}

TEST(Context, MemoryTypeHonoursRequiredFlags) {
    Context ctx = Context::create({});
    const std::uint32_t host = ctx.memory_type(~0u, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(ctx.physical_device(), &mp);
    EXPECT_TRUE(mp.memoryTypes[host].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    // No memory type allowed (type_bits == 0) -> a clear error, not a crash.
    EXPECT_THROW(ctx.memory_type(0u, 0), Error);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(Context, ExceptionInRecordPropagatesAndLeavesContextUsable) {
    Context ctx = Context::create({});
    EXPECT_THROW(ctx.submit_and_wait([](VkCommandBuffer) { throw Error("boom"); }), Error);
    ctx.submit_and_wait([](VkCommandBuffer) {});
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(Check, NamesTheFailedCall) {
    EXPECT_EQ(check(VK_SUCCESS, "x"), VK_SUCCESS);
    EXPECT_EQ(check(VK_TIMEOUT, "x"), VK_TIMEOUT);
    try {
        check(VK_ERROR_OUT_OF_DEVICE_MEMORY, "vkAllocateMemory");
        FAIL() << "check did not throw";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "Vulkan: vkAllocateMemory failed: VK_ERROR_OUT_OF_DEVICE_MEMORY (-2)");
    }
}

// Two timestamps written on the device, one in each of two submissions: on the host's steady clock they fall
// between the host times around their submissions, and keep the device's distance between them.
TEST(DeviceClock, TimestampsLandOnTheHostSteadyClock) {
    Context ctx = Context::create({});
    // Mesa's lavapipe offers VK_EXT_calibrated_timestamps against CLOCK_MONOTONIC.
    ASSERT_TRUE(ctx.features().calibrated_timestamps);
    VkQueryPoolCreateInfo q{};
    q.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    q.queryType = VK_QUERY_TYPE_TIMESTAMP;
    q.queryCount = 2;
    VkQueryPool raw = VK_NULL_HANDLE;
    check(vkCreateQueryPool(ctx.device(), &q, nullptr, &raw), "vkCreateQueryPool");
    const UniqueQueryPool pool(ctx.device(), raw);
    const auto steady_s = [] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    };
    double before[2], after[2];
    for (std::uint32_t k = 0; k < 2; ++k) {
        before[k] = steady_s();
        ctx.submit_and_wait([&](VkCommandBuffer cmd) {
            if (k == 0) vkCmdResetQueryPool(cmd, pool.get(), 0, 2);
            vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool.get(), k);
        });
        after[k] = steady_s();
        if (k == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    std::uint64_t ticks[2] = {};
    check(vkGetQueryPoolResults(ctx.device(), pool.get(), 0, 2, sizeof ticks, ticks, sizeof ticks[0],
                                VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    const std::uint64_t mask = ~std::uint64_t{0};
    double host[2];
    for (int k = 0; k < 2; ++k) {
        const std::optional<double> s = device_ticks_to_steady_s(ctx, ticks[k], mask);
        ASSERT_TRUE(s.has_value()) << k;
        host[k] = *s;
        EXPECT_GE(host[k], before[k] - 1e-4) << k;  // 0.1 ms for the calibration's own deviation
        EXPECT_LE(host[k], after[k] + 1e-4) << k;
    }
    const double device_gap_s =
        static_cast<double>(ticks[1] - ticks[0]) * ctx.properties().limits.timestampPeriod * 1e-9;
    EXPECT_NEAR(host[1] - host[0], device_gap_s, 1e-4);
    EXPECT_GT(host[1] - host[0], 0.019);  // the 20 ms sleep between them
    // No valid bits: nothing to convert.
    EXPECT_FALSE(device_ticks_to_steady_s(ctx, ticks[0], 0).has_value());
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::gpu
