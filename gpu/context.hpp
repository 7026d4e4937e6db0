// gpu/context.hpp - the Vulkan instance, device and queue every GPU module shares.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace tridex::gpu {

/// How to create a Context.
struct ContextOptions {
    /// Enable VK_LAYER_KHRONOS_validation and count its messages. Also switched on when the
    /// environment variable TRIDEX_VALIDATION=1 (the test helper sets it).
    bool validation = false;
    /// Extra instance extensions to enable, e.g. the surface extensions a window system needs
    /// (glfwGetRequiredInstanceExtensions(): VK_KHR_surface + VK_KHR_xcb_surface on X11). create() throws
    /// tridex::Error naming the first one the loader does not offer.
    std::vector<std::string> instance_extensions{};
    /// Presentation to a window: only devices offering VK_KHR_swapchain are accepted and the extension is
    /// enabled on the device. With `can_present` set, the queue family must also pass it.
    bool presentation = false;
    /// Optional filter (used with presentation = true): true when queue family `family` of `device` can
    /// present to the window system, e.g. glfwGetPhysicalDevicePresentationSupport. Called during create().
    std::function<bool(VkInstance instance, VkPhysicalDevice device, std::uint32_t family)> can_present{};
    /// On a CPU device (Mesa lavapipe), pin the worker threads the driver starts with the device one per
    /// core, in turn (gpu/driver_threads.hpp: Linux often queues two of lavapipe's compute threads on one
    /// core while another idles; pinned, GPU sculpting ran about 1.6x faster on 2 cores). Also switched
    /// off by the environment variable TRIDEX_DRIVER_AFFINITY=0. No effect on other device types.
    bool spread_cpu_driver_threads = true;
};

/// Optional device features, each true when the device supports it and the Context enabled it.
struct DeviceFeatures {
    bool multiview = false;             ///< Vulkan 1.1 multiview (render passes with a view mask)
    bool shader_output_layer = false;   ///< Vulkan 1.2: vertex shaders may write gl_Layer
    bool timeline_semaphore = false;    ///< Vulkan 1.2 timeline semaphores
    bool host_query_reset = false;      ///< Vulkan 1.2 vkResetQueryPool from the host
    bool shader_int64 = false;          ///< 64-bit integers in shaders
    bool shader_float64 = false;        ///< 64-bit floats in shaders
    bool fragment_stores_and_atomics = false;  ///< storage writes/atomics in fragment shaders
    bool timestamps = false;            ///< timestamp queries on graphics and compute queues
    /// VK_EXT_calibrated_timestamps against CLOCK_MONOTONIC: timestamps convert to the host's steady clock
    /// (gpu/device_clock.hpp)
    bool calibrated_timestamps = false;
    bool multi_draw_indirect = false;   ///< vkCmdDrawIndexedIndirect with drawCount > 1
    bool draw_indirect_first_instance = false;  ///< indirect commands with firstInstance != 0
    bool storage_buffer_array_dynamic_indexing = false;  ///< shaders index arrays of storage buffers at run time
};

/// Vulkan 1.2+ instance, the first suitable physical device (prefers a discrete GPU, then integrated,
/// virtual, CPU - so Mesa lavapipe is accepted), one queue family with graphics + compute, one queue,
/// and, with validation on, a debug-utils messenger that counts every warning or error message
/// (validation, general or performance) and prints it to stderr.
///
/// Move-only RAII: destroying it waits for the device to go idle and then destroys device, messenger
/// and instance. Every object created from it must be destroyed first.
/// Thread safety: the const accessors may be called from any thread; submit_and_wait() and
/// queue_submit() lock an internal mutex, so several threads may share one Context for submissions
/// (submit_and_wait() holds it while recording and submitting, not while waiting for its fence).
class Context {
public:
    /// Creates instance, device and queue. Throws tridex::Error with a one-line reason when no
    /// Vulkan loader/driver is usable, no device offers Vulkan 1.2 with a graphics+compute queue,
    /// or validation was requested but VK_LAYER_KHRONOS_validation is not installed.
    static Context create(const ContextOptions& options = {});

    ~Context();
    Context(Context&&) noexcept;
    Context& operator=(Context&&) noexcept;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    /// Name the driver reports for the selected device, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string device_name() const;
    /// Number of validation/debug messages (warning or error severity) seen so far; 0 when
    /// validation is off.
    std::uint32_t validation_messages() const;
    /// True when the validation layer and the message counter are active.
    bool validation_enabled() const;
    /// True when the device was created for presentation (VK_KHR_swapchain enabled, ContextOptions::presentation).
    bool presentation_enabled() const;
    /// Driver worker threads pinned one per core at creation (ContextOptions::spread_cpu_driver_threads);
    /// 0 on a GPU, with the option off, or with fewer than 2 usable cores.
    int spread_driver_threads() const;

    VkInstance instance() const;              ///< the instance
    VkPhysicalDevice physical_device() const; ///< the selected physical device
    VkDevice device() const;                  ///< the logical device
    VkQueue queue() const;                    ///< the graphics+compute queue (externally synchronised: use queue_submit)
    std::uint32_t queue_family() const;       ///< family index of queue()
    const VkPhysicalDeviceProperties& properties() const;  ///< limits, API version, timestampPeriod
    const DeviceFeatures& features() const;   ///< optional features that are enabled

    /// Index of a memory type allowed by `type_bits` (from VkMemoryRequirements) with all of
    /// `required` property flags; among those, one that also has `preferred` flags if any.
    /// Throws tridex::Error when no allowed type has the required flags.
    std::uint32_t memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                              VkMemoryPropertyFlags preferred = 0) const;

    /// Records a one-shot primary command buffer with `record`, submits it to queue() and waits
    /// (at most 60 s) until the GPU has finished. Exceptions from `record` propagate after the
    /// command buffer is freed. Throws tridex::Error on a Vulkan failure or on the timeout.
    void submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const;

    /// vkQueueSubmit under the Context's queue mutex (for callers that manage their own command
    /// buffers and fences). Throws tridex::Error on failure.
    void queue_submit(const VkSubmitInfo& submit, VkFence fence) const;

    /// vkQueuePresentKHR on queue() under the Context's queue mutex. Returns VK_SUCCESS, VK_SUBOPTIMAL_KHR or
    /// VK_ERROR_OUT_OF_DATE_KHR (the caller recreates its swapchain); throws tridex::Error on any other
    /// failure or when the Context was not created with presentation = true.
    VkResult queue_present(const VkPresentInfoKHR& present) const;

    /// Waits until the device is idle. Throws tridex::Error on device loss.
    void wait_idle() const;

    struct Impl;

private:
    explicit Context(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace tridex::gpu
