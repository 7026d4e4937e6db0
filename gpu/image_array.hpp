// gpu/image_array.hpp - a 2D array image (one layer per eye) with its views and memory.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "gpu/unique_handle.hpp"

namespace tridex::gpu {

/// What to create: size in pixels, layer count, format, usage, and the aspect of its views.
struct ImageArrayInfo {
    std::uint32_t width = 0;   ///< pixels, 1..maxImageDimension2D
    std::uint32_t height = 0;  ///< pixels, 1..maxImageDimension2D
    std::uint32_t layers = 1;  ///< array layers, 1..maxImageArrayLayers
    VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;  ///< COLOR or DEPTH
};

/// An optimal-tiling, single-sample 2D array image in device-local memory, with one VK_IMAGE_VIEW_TYPE_2D_ARRAY
/// view over all layers and one VK_IMAGE_VIEW_TYPE_2D view per layer. Starts in VK_IMAGE_LAYOUT_UNDEFINED.
/// Move-only RAII; the Context must outlive it and the GPU must be done with it before destruction.
class ImageArray {
public:
    ImageArray() = default;
    /// Creates the image, its memory and views. Throws tridex::Error when a dimension is 0 or above the
    /// device limits, when the format does not support `usage` with optimal tiling, or on a Vulkan failure.
    static ImageArray create(const Context& context, const ImageArrayInfo& info);

    ~ImageArray();
    ImageArray(ImageArray&& o) noexcept;
    ImageArray& operator=(ImageArray&& o) noexcept;
    ImageArray(const ImageArray&) = delete;
    ImageArray& operator=(const ImageArray&) = delete;

    VkImage handle() const { return image_; }              ///< the image
    VkImageView array_view() const { return array_view_.get(); }  ///< 2D_ARRAY view of all layers
    VkImageView layer_view(std::uint32_t layer) const { return layer_views_.at(layer).get(); }  ///< 2D view of one layer
    const ImageArrayInfo& info() const { return info_; }   ///< what it was created with

private:
    void release();
    VkDevice device_ = VK_NULL_HANDLE;
    VkImage image_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    ImageArrayInfo info_;
    UniqueImageView array_view_;
    std::vector<UniqueImageView> layer_views_;
};

}  // namespace tridex::gpu
