// Tests of gpu/context: device selection on lavapipe, features, and the validation message counter.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "gpu/check.hpp"
#include "gpu/context.hpp"

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

}  // namespace
}  // namespace tridex::gpu
