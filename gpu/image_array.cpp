// gpu/image_array.cpp - 2D array image creation, memory binding and views.
#include "gpu/image_array.hpp"

#include <string>
#include <utility>

#include "core/error.hpp"
#include "gpu/check.hpp"

namespace tridex::gpu {
namespace {

VkFormatFeatureFlags needed_features(VkImageUsageFlags usage) {
    VkFormatFeatureFlags f = 0;
    if (usage & VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT) f |= VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT;
    if (usage & VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT) f |= VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT;
    if (usage & VK_IMAGE_USAGE_SAMPLED_BIT) f |= VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
    if (usage & VK_IMAGE_USAGE_STORAGE_BIT) f |= VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT;
    if (usage & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) f |= VK_FORMAT_FEATURE_TRANSFER_SRC_BIT;
    if (usage & VK_IMAGE_USAGE_TRANSFER_DST_BIT) f |= VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
    return f;
}

UniqueImageView make_view(VkDevice device, VkImage image, const ImageArrayInfo& info, VkImageViewType type,
                          std::uint32_t first_layer, std::uint32_t layers) {
    VkImageViewCreateInfo v{};
    v.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
    v.image = image;
    v.viewType = type;
    v.format = info.format;
    v.subresourceRange = {info.aspect, 0, 1, first_layer, layers};
    VkImageView view = VK_NULL_HANDLE;
    check(vkCreateImageView(device, &v, nullptr, &view), "vkCreateImageView");
    return UniqueImageView(device, view);
}

}  // namespace

ImageArray ImageArray::create(const Context& context, const ImageArrayInfo& info) {
    const VkPhysicalDeviceLimits& lim = context.properties().limits;
    if (info.width == 0 || info.height == 0 || info.layers == 0 || info.width > lim.maxImageDimension2D ||
        info.height > lim.maxImageDimension2D || info.layers > lim.maxImageArrayLayers)
        throw Error("gpu: ImageArray size " + std::to_string(info.width) + "x" + std::to_string(info.height) + "x" +
                    std::to_string(info.layers) + " is empty or exceeds the device limit " +
                    std::to_string(lim.maxImageDimension2D));
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(context.physical_device(), info.format, &fp);
    const VkFormatFeatureFlags need = needed_features(info.usage);
    if ((fp.optimalTilingFeatures & need) != need)
        throw Error("gpu: ImageArray format " + std::to_string(static_cast<int>(info.format)) +
                    " does not support the requested usage with optimal tiling");

    ImageArray img;
    img.device_ = context.device();
    img.info_ = info;
    VkImageCreateInfo ci{};
    ci.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
    ci.imageType = VK_IMAGE_TYPE_2D;
    ci.format = info.format;
    ci.extent = {info.width, info.height, 1};
    ci.mipLevels = 1;
    ci.arrayLayers = info.layers;
    ci.samples = VK_SAMPLE_COUNT_1_BIT;
    ci.tiling = VK_IMAGE_TILING_OPTIMAL;
    ci.usage = info.usage;
    ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    check(vkCreateImage(img.device_, &ci, nullptr, &img.image_), "vkCreateImage");

    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(img.device_, img.image_, &req);
    VkMemoryAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = context.memory_type(req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    check(vkAllocateMemory(img.device_, &alloc, nullptr, &img.memory_), "vkAllocateMemory");
    check(vkBindImageMemory(img.device_, img.image_, img.memory_, 0), "vkBindImageMemory");

    img.array_view_ = make_view(img.device_, img.image_, info, VK_IMAGE_VIEW_TYPE_2D_ARRAY, 0, info.layers);
    for (std::uint32_t l = 0; l < info.layers; ++l)
        img.layer_views_.push_back(make_view(img.device_, img.image_, info, VK_IMAGE_VIEW_TYPE_2D, l, 1));
    return img;
}

ImageArray::~ImageArray() { release(); }

ImageArray::ImageArray(ImageArray&& o) noexcept
    : device_(o.device_),
      image_(std::exchange(o.image_, VK_NULL_HANDLE)),
      memory_(std::exchange(o.memory_, VK_NULL_HANDLE)),
      info_(o.info_),
      array_view_(std::move(o.array_view_)),
      layer_views_(std::move(o.layer_views_)) {}

ImageArray& ImageArray::operator=(ImageArray&& o) noexcept {
    if (this != &o) {
        release();
        device_ = o.device_;
        image_ = std::exchange(o.image_, VK_NULL_HANDLE);
        memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
        info_ = o.info_;
        array_view_ = std::move(o.array_view_);
        layer_views_ = std::move(o.layer_views_);
    }
    return *this;
}

void ImageArray::release() {
    layer_views_.clear();  // views before the image
    array_view_.reset();
    if (image_ != VK_NULL_HANDLE) vkDestroyImage(device_, image_, nullptr);
    if (memory_ != VK_NULL_HANDLE) vkFreeMemory(device_, memory_, nullptr);
    image_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
}

}  // namespace tridex::gpu
