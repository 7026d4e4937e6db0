// gpu/swapchain.hpp - a window surface and its swapchain (vsync'd presentation, recreated on resize).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"

namespace tridex::gpu {

/// Owns a VkSurfaceKHR created on an instance (by a window system, e.g. glfwCreateWindowSurface) and
/// destroys it with vkDestroySurfaceKHR. Move-only; the instance (Context) must outlive it, and every
/// swapchain made on it must be destroyed first.
class Surface {
public:
    Surface() = default;
    /// Takes ownership of `surface` (may be VK_NULL_HANDLE) created on `instance`.
    Surface(VkInstance instance, VkSurfaceKHR surface) : instance_(instance), surface_(surface) {}
    ~Surface();
    Surface(Surface&& o) noexcept;
    Surface& operator=(Surface&& o) noexcept;
    Surface(const Surface&) = delete;
    Surface& operator=(const Surface&) = delete;

    VkSurfaceKHR handle() const { return surface_; }  ///< the surface (VK_NULL_HANDLE when empty)

private:
    void release();
    VkInstance instance_ = VK_NULL_HANDLE;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
};

/// What a surface offers the Context's device: capabilities (image counts, extents,
/// maxImageArrayLayers - 2 or more is needed for quad-buffered stereo), formats and present modes.
struct SurfaceSupport {
    bool queue_can_present = false;  ///< the Context's queue family can present to this surface
    VkSurfaceCapabilitiesKHR capabilities{};
    std::vector<VkSurfaceFormatKHR> formats;
    std::vector<VkPresentModeKHR> present_modes;
};

/// Queries `surface` for the Context's physical device and queue family. Throws tridex::Error on a
/// Vulkan failure (e.g. a lost surface).
SurfaceSupport query_surface(const Context& context, VkSurfaceKHR surface);

/// "fifo", "mailbox", "immediate", "fifo-relaxed" or "other".
const char* present_mode_name(VkPresentModeKHR mode);

/// How to create a swapchain.
struct SwapchainOptions {
    std::uint32_t width = 0;   ///< wanted size in pixels (the window's framebuffer size); clamped to the surface's range
    std::uint32_t height = 0;  ///< when the surface dictates its size (currentExtent), that size is used instead
    /// Image array layers: 1 for mono and every packed stereo layout, 2 for quad-buffered stereo
    /// (layer 0 = left, layer 1 = right). Must be <= the surface's maxImageArrayLayers.
    std::uint32_t layers = 1;
    /// true: FIFO (present at the display's refresh, never tears; always available). false: MAILBOX, else
    /// IMMEDIATE, else FIFO.
    bool vsync = true;
    /// Image usage; TRANSFER_DST (images are filled by blits/copies) by default. Add TRANSFER_SRC to read
    /// presented images back. Every bit must be in the surface's supportedUsageFlags.
    VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
};

/// What acquire() and present() report.
enum class SwapStatus {
    kOk,          ///< done
    kSuboptimal,  ///< done, but the swapchain no longer matches the surface: recreate soon
    kOutOfDate,   ///< not done: the swapchain must be recreated before use (e.g. after a resize)
};

/// A VkSwapchainKHR on a Surface with its images. Format: the first of B8G8R8A8_UNORM, R8G8B8A8_UNORM
/// (UNORM, so that blitted RGBA8 bytes reach the screen unchanged, as in the offscreen PNGs) the surface
/// offers with the usage's format features (BLIT_DST for TRANSFER_DST), else the surface's first format.
/// Image count: minImageCount + 1 (within maxImageCount). Composite alpha: opaque if offered.
/// Move-only RAII; the Context and the Surface must outlive it. acquire() / present() from one thread.
class Swapchain {
public:
    Swapchain() = default;
    /// Creates the swapchain. Throws tridex::Error (one line naming the field) when the Context was not
    /// created with presentation, the queue family cannot present to the surface, the size is 0,
    /// `layers` is 0 or above maxImageArrayLayers, a usage bit is not supported, or on a Vulkan failure.
    static Swapchain create(const Context& context, VkSurfaceKHR surface, const SwapchainOptions& options);

    ~Swapchain();
    Swapchain(Swapchain&& o) noexcept;
    Swapchain& operator=(Swapchain&& o) noexcept;
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    /// Waits for the device to go idle and replaces the swapchain by one of width x height pixels (same
    /// options otherwise), handing the old one over as oldSwapchain. Same errors as create().
    void recreate(std::uint32_t width, std::uint32_t height);

    /// vkAcquireNextImageKHR: on kOk / kSuboptimal, `index` is the image to fill and `signal` will be signalled
    /// when it may be written. Throws tridex::Error on a timeout (`timeout_ns`) or a Vulkan failure.
    SwapStatus acquire(VkSemaphore signal, std::uint32_t& index, std::uint64_t timeout_ns = 5'000'000'000ull);
    /// Queues image `index` for presentation after `wait` is signalled (Context::queue_present).
    SwapStatus present(std::uint32_t index, VkSemaphore wait);

    VkSwapchainKHR handle() const { return swapchain_; }            ///< the swapchain
    VkFormat format() const { return format_.format; }              ///< image format
    VkColorSpaceKHR colour_space() const { return format_.colorSpace; }  ///< image colour space
    VkExtent2D extent() const { return extent_; }                   ///< image size, pixels
    std::uint32_t layers() const { return options_.layers; }        ///< image array layers
    VkPresentModeKHR present_mode() const { return present_mode_; }  ///< the mode chosen
    VkImageUsageFlags usage() const { return options_.usage; }      ///< image usage
    const std::vector<VkImage>& images() const { return images_; }  ///< swapchain images (owned by it)
    /// The surface's maxImageArrayLayers at the last (re)creation.
    std::uint32_t max_image_array_layers() const { return max_layers_; }

private:
    void build(VkSwapchainKHR old);
    void release();
    const Context* context_ = nullptr;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    SwapchainOptions options_;
    VkSurfaceFormatKHR format_{};
    VkExtent2D extent_{};
    VkPresentModeKHR present_mode_ = VK_PRESENT_MODE_FIFO_KHR;
    std::uint32_t max_layers_ = 0;
    std::vector<VkImage> images_;
};

}  // namespace tridex::gpu
