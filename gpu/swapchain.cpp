// gpu/swapchain.cpp - surface queries, format/present-mode choice, swapchain creation and recreation.
#include "gpu/swapchain.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "gpu/check.hpp"

namespace tridex::gpu {

Surface::~Surface() { release(); }
Surface::Surface(Surface&& o) noexcept
    : instance_(o.instance_), surface_(std::exchange(o.surface_, VK_NULL_HANDLE)) {}
Surface& Surface::operator=(Surface&& o) noexcept {
    if (this != &o) {
        release();
        instance_ = o.instance_;
        surface_ = std::exchange(o.surface_, VK_NULL_HANDLE);
    }
    return *this;
}
void Surface::release() {
    if (surface_ != VK_NULL_HANDLE) vkDestroySurfaceKHR(instance_, surface_, nullptr);
    surface_ = VK_NULL_HANDLE;
}

SurfaceSupport query_surface(const Context& context, VkSurfaceKHR surface) {
    const VkPhysicalDevice pd = context.physical_device();
    SurfaceSupport s;
    VkBool32 can = VK_FALSE;
    check(vkGetPhysicalDeviceSurfaceSupportKHR(pd, context.queue_family(), surface, &can),
          "vkGetPhysicalDeviceSurfaceSupportKHR");
    s.queue_can_present = can == VK_TRUE;
    check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, surface, &s.capabilities),
          "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
    std::uint32_t n = 0;
    check(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr), "vkGetPhysicalDeviceSurfaceFormatsKHR");
    s.formats.resize(n);
    check(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, s.formats.data()),
          "vkGetPhysicalDeviceSurfaceFormatsKHR");
    s.formats.resize(n);
    n = 0;
    check(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr),
          "vkGetPhysicalDeviceSurfacePresentModesKHR");
    s.present_modes.resize(n);
    check(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, s.present_modes.data()),
          "vkGetPhysicalDeviceSurfacePresentModesKHR");
    s.present_modes.resize(n);
    return s;
}

const char* present_mode_name(VkPresentModeKHR mode) {
    switch (mode) {
        case VK_PRESENT_MODE_FIFO_KHR: return "fifo";
        case VK_PRESENT_MODE_MAILBOX_KHR: return "mailbox";
        case VK_PRESENT_MODE_IMMEDIATE_KHR: return "immediate";
        case VK_PRESENT_MODE_FIFO_RELAXED_KHR: return "fifo-relaxed";
        default: return "other";
    }
}

namespace {

// Format features an optimal-tiling image needs for `usage` filled by blits / read by copies.
VkFormatFeatureFlags needed_features(VkImageUsageFlags usage) {
    VkFormatFeatureFlags f = 0;
    if (usage & VK_IMAGE_USAGE_TRANSFER_DST_BIT) f |= VK_FORMAT_FEATURE_BLIT_DST_BIT | VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
    if (usage & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) f |= VK_FORMAT_FEATURE_TRANSFER_SRC_BIT;
    return f;
}

VkSurfaceFormatKHR choose_format(const Context& context, const std::vector<VkSurfaceFormatKHR>& formats,
                                 VkImageUsageFlags usage) {
    if (formats.empty()) throw Error("gpu: the window surface offers no image formats");
    const VkFormatFeatureFlags need = needed_features(usage);
    for (VkFormat want : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM}) {
        for (const VkSurfaceFormatKHR& f : formats) {
            if (f.format != want) continue;
            VkFormatProperties props{};
            vkGetPhysicalDeviceFormatProperties(context.physical_device(), f.format, &props);
            if ((props.optimalTilingFeatures & need) == need) return f;
        }
    }
    return formats.front();
}

VkPresentModeKHR choose_present_mode(const std::vector<VkPresentModeKHR>& modes, bool vsync) {
    if (vsync) return VK_PRESENT_MODE_FIFO_KHR;  // required by the spec on every surface
    for (VkPresentModeKHR want : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
        if (std::find(modes.begin(), modes.end(), want) != modes.end()) return want;
    return VK_PRESENT_MODE_FIFO_KHR;
}

VkCompositeAlphaFlagBitsKHR choose_alpha(VkCompositeAlphaFlagsKHR supported) {
    for (VkCompositeAlphaFlagBitsKHR a : {VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR, VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR,
                                          VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR,
                                          VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR})
        if (supported & a) return a;
    return VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
}

SwapStatus status_of(VkResult r, const char* call) {
    if (r == VK_ERROR_OUT_OF_DATE_KHR) return SwapStatus::kOutOfDate;
    if (r == VK_SUBOPTIMAL_KHR) return SwapStatus::kSuboptimal;
    if (r == VK_ERROR_SURFACE_LOST_KHR) throw Error(std::string("gpu: ") + call + ": the window surface was lost");
    check(r, call);
    return SwapStatus::kOk;
}

}  // namespace

Swapchain Swapchain::create(const Context& context, VkSurfaceKHR surface, const SwapchainOptions& options) {
    if (!context.presentation_enabled())
        throw Error("gpu: Swapchain needs a Context created with ContextOptions.presentation = true");
    if (surface == VK_NULL_HANDLE) throw Error("gpu: Swapchain: the surface is VK_NULL_HANDLE");
    if (options.layers == 0) throw Error("gpu: SwapchainOptions.layers must be at least 1");
    Swapchain s;
    s.context_ = &context;
    s.surface_ = surface;
    s.options_ = options;
    s.build(VK_NULL_HANDLE);
    return s;
}

void Swapchain::build(VkSwapchainKHR old) {
    const SurfaceSupport sup = query_surface(*context_, surface_);
    if (!sup.queue_can_present)
        throw Error("gpu: queue family " + std::to_string(context_->queue_family()) +
                    " of " + context_->device_name() + " cannot present to this window surface");
    const VkSurfaceCapabilitiesKHR& caps = sup.capabilities;
    max_layers_ = caps.maxImageArrayLayers;
    if (options_.layers > caps.maxImageArrayLayers)
        throw Error("gpu: SwapchainOptions.layers = " + std::to_string(options_.layers) +
                    " but the surface allows maxImageArrayLayers = " + std::to_string(caps.maxImageArrayLayers));
    if ((caps.supportedUsageFlags & options_.usage) != options_.usage)
        throw Error("gpu: SwapchainOptions.usage (flags " + std::to_string(options_.usage) +
                    ") is not within the surface's supportedUsageFlags (" + std::to_string(caps.supportedUsageFlags) +
                    ")");

    VkExtent2D extent = caps.currentExtent;
    if (extent.width == 0xFFFFFFFFu) {  // the surface takes the swapchain's size
        if (options_.width == 0 || options_.height == 0)
            throw Error("gpu: SwapchainOptions.width/height must be > 0 (got " + std::to_string(options_.width) + "x" +
                        std::to_string(options_.height) + ")");
        extent.width = std::clamp(options_.width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(options_.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (extent.width == 0 || extent.height == 0)
        throw Error("gpu: the window surface has size 0 (minimised?); no swapchain can be created");

    format_ = choose_format(*context_, sup.formats, options_.usage);
    present_mode_ = choose_present_mode(sup.present_modes, options_.vsync);
    std::uint32_t count = caps.minImageCount + 1;
    if (caps.maxImageCount > 0) count = std::min(count, caps.maxImageCount);

    VkSwapchainCreateInfoKHR info{};
    info.sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR;
    info.surface = surface_;
    info.minImageCount = count;
    info.imageFormat = format_.format;
    info.imageColorSpace = format_.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = options_.layers;
    info.imageUsage = options_.usage;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR)
                            ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                            : caps.currentTransform;
    info.compositeAlpha = choose_alpha(caps.supportedCompositeAlpha);
    info.presentMode = present_mode_;
    info.clipped = VK_TRUE;
    info.oldSwapchain = old;
    VkSwapchainKHR created = VK_NULL_HANDLE;
    check(vkCreateSwapchainKHR(context_->device(), &info, nullptr, &created), "vkCreateSwapchainKHR");
    if (old != VK_NULL_HANDLE) vkDestroySwapchainKHR(context_->device(), old, nullptr);
    swapchain_ = created;
    extent_ = extent;
    std::uint32_t n = 0;
    check(vkGetSwapchainImagesKHR(context_->device(), swapchain_, &n, nullptr), "vkGetSwapchainImagesKHR");
    images_.resize(n);
    check(vkGetSwapchainImagesKHR(context_->device(), swapchain_, &n, images_.data()), "vkGetSwapchainImagesKHR");
}

void Swapchain::recreate(std::uint32_t width, std::uint32_t height) {
    if (!context_) throw Error("gpu: Swapchain::recreate on an empty swapchain");
    context_->wait_idle();
    options_.width = width;
    options_.height = height;
    const VkSwapchainKHR old = std::exchange(swapchain_, VK_NULL_HANDLE);
    images_.clear();
    try {
        build(old);
    } catch (...) {
        // build() destroys `old` only after a successful create; otherwise keep nothing dangling.
        if (swapchain_ == VK_NULL_HANDLE && old != VK_NULL_HANDLE) vkDestroySwapchainKHR(context_->device(), old, nullptr);
        throw;
    }
}

SwapStatus Swapchain::acquire(VkSemaphore signal, std::uint32_t& index, std::uint64_t timeout_ns) {
    const VkResult r = vkAcquireNextImageKHR(context_->device(), swapchain_, timeout_ns, signal, VK_NULL_HANDLE, &index);
    if (r == VK_TIMEOUT || r == VK_NOT_READY)
        throw Error("gpu: vkAcquireNextImageKHR: no swapchain image became available within " +
                    std::to_string(timeout_ns / 1'000'000) + " ms");
    return status_of(r, "vkAcquireNextImageKHR");
}

SwapStatus Swapchain::present(std::uint32_t index, VkSemaphore wait) {
    VkPresentInfoKHR info{};
    info.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR;
    info.waitSemaphoreCount = wait != VK_NULL_HANDLE ? 1u : 0u;
    info.pWaitSemaphores = &wait;
    info.swapchainCount = 1;
    info.pSwapchains = &swapchain_;
    info.pImageIndices = &index;
    return status_of(context_->queue_present(info), "vkQueuePresentKHR");
}

Swapchain::~Swapchain() { release(); }
Swapchain::Swapchain(Swapchain&& o) noexcept
    : context_(o.context_),
      surface_(o.surface_),
      swapchain_(std::exchange(o.swapchain_, VK_NULL_HANDLE)),
      options_(o.options_),
      format_(o.format_),
      extent_(o.extent_),
      present_mode_(o.present_mode_),
      max_layers_(o.max_layers_),
      images_(std::move(o.images_)) {}
Swapchain& Swapchain::operator=(Swapchain&& o) noexcept {
    if (this != &o) {
        release();
        context_ = o.context_;
        surface_ = o.surface_;
        swapchain_ = std::exchange(o.swapchain_, VK_NULL_HANDLE);
        options_ = o.options_;
        format_ = o.format_;
        extent_ = o.extent_;
        present_mode_ = o.present_mode_;
        max_layers_ = o.max_layers_;
        images_ = std::move(o.images_);
    }
    return *this;
}
void Swapchain::release() {
    if (swapchain_ != VK_NULL_HANDLE) vkDestroySwapchainKHR(context_->device(), swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
    images_.clear();
}

}  // namespace tridex::gpu
