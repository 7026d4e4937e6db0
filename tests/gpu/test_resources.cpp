// Tests of gpu/ buffers, image arrays and shader modules on lavapipe, with validation on.
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "core/error.hpp"
#include "gpu/buffer.hpp"
#include "gpu/context.hpp"
#include "gpu/image_array.hpp"
#include "gpu/shader_module.hpp"
#include "shaders/spirv.hpp"

namespace tridex::gpu {
namespace {

TEST(Buffer, HostBufferWriteReadRoundTrip) {
    Context ctx = Context::create({});
    {
        Buffer b = Buffer::create(ctx, 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryDomain::kHost);
        ASSERT_NE(b.mapped(), nullptr);
        std::vector<std::uint8_t> in(100), out(100, 0);
        std::iota(in.begin(), in.end(), 7);
        b.write(in.data(), in.size(), 156);
        b.read(out.data(), out.size(), 156);
        EXPECT_EQ(in, out);
        EXPECT_THROW(b.write(in.data(), in.size(), 157), Error);  // one byte past the end
        EXPECT_THROW(b.read(out.data(), 1, 256), Error);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(Buffer, DeviceBufferUploadDownloadRoundTrip) {
    Context ctx = Context::create({});
    {
        Buffer b = Buffer::create(ctx, 4096, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryDomain::kDevice);
        EXPECT_EQ(b.mapped(), nullptr);
        std::vector<std::uint32_t> in(1000), out(1000, 0);
        std::iota(in.begin(), in.end(), 123456u);
        upload(ctx, b, in.data(), in.size() * 4, 64);
        download(ctx, b, out.data(), out.size() * 4, 64);
        EXPECT_EQ(in, out);
        EXPECT_THROW(b.write(in.data(), 4), Error);  // not host-visible
        EXPECT_THROW(upload(ctx, b, in.data(), 4096, 4), Error);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(Buffer, ZeroSizeIsAnError) {
    Context ctx = Context::create({});
    EXPECT_THROW(Buffer::create(ctx, 0, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryDomain::kHost), Error);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(Buffer, MoveTransfersOwnership) {
    Context ctx = Context::create({});
    {
        Buffer a = Buffer::create(ctx, 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryDomain::kHost);
        const VkBuffer h = a.handle();
        Buffer b = std::move(a);
        EXPECT_EQ(b.handle(), h);
        EXPECT_EQ(a.handle(), VK_NULL_HANDLE);
        EXPECT_EQ(b.size(), 64u);
        a = std::move(b);
        EXPECT_EQ(a.handle(), h);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(ImageArray, CreatesLayerViewsAndRejectsBadSizes) {
    Context ctx = Context::create({});
    {
        ImageArrayInfo info;
        info.width = 32;
        info.height = 16;
        info.layers = 2;
        info.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        ImageArray img = ImageArray::create(ctx, info);
        EXPECT_NE(img.handle(), VK_NULL_HANDLE);
        EXPECT_NE(img.array_view(), VK_NULL_HANDLE);
        EXPECT_NE(img.layer_view(0), img.layer_view(1));
        EXPECT_THROW(img.layer_view(2), std::out_of_range);
        info.width = 0;
        EXPECT_THROW(ImageArray::create(ctx, info), Error);
        info.width = ctx.properties().limits.maxImageDimension2D + 1;
        EXPECT_THROW(ImageArray::create(ctx, info), Error);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(ShaderModule, EmbeddedShadersLoadAndGarbageIsRejected) {
    Context ctx = Context::create({});
    for (std::string_view name : shaders::names()) {
        UniqueShaderModule m = create_shader_module(ctx, shaders::spirv(name));
        EXPECT_NE(m.get(), VK_NULL_HANDLE) << name;
    }
    EXPECT_GE(shaders::names().size(), 4u);
    EXPECT_THROW(shaders::spirv("no_such_shader"), Error);
    const std::uint32_t garbage[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    EXPECT_THROW(create_shader_module(ctx, garbage), Error);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::gpu
