// gpu/context.cpp - instance, validation messenger, device selection, queue and one-shot submits.
#include "gpu/context.hpp"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

#include "core/error.hpp"
#include "gpu/check.hpp"
#include "gpu/device_clock.hpp"
#include "gpu/driver_threads.hpp"

namespace tridex::gpu {

struct Context::Impl {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    std::uint32_t family = 0;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties properties{};
    VkPhysicalDeviceMemoryProperties memory{};
    DeviceFeatures features;
    bool validation = false;
    bool presentation = false;
    int spread_threads = 0;  // driver worker threads pinned one per core (CPU devices)
    std::vector<std::string> instance_extensions;
    std::function<bool(VkInstance, VkPhysicalDevice, std::uint32_t)> can_present;
    std::atomic<std::uint32_t> messages{0};
    mutable std::mutex queue_mutex;  // guards queue and pool

    ~Impl() {
        if (device != VK_NULL_HANDLE) {
            vkDeviceWaitIdle(device);
            if (pool != VK_NULL_HANDLE) vkDestroyCommandPool(device, pool, nullptr);
            vkDestroyDevice(device, nullptr);
        }
        if (messenger != VK_NULL_HANDLE) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            if (destroy) destroy(instance, messenger, nullptr);
        }
        if (instance != VK_NULL_HANDLE) vkDestroyInstance(instance, nullptr);
    }
};

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr std::uint64_t kSubmitTimeoutNs = 60'000'000'000ull;

VKAPI_ATTR VkBool32 VKAPI_CALL on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                                const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                void* user) {
    auto* impl = static_cast<Context::Impl*>(user);
    impl->messages.fetch_add(1, std::memory_order_relaxed);
    const char* level = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "error" : "warning";
    std::fprintf(stderr, "[vulkan %s] %s\n", level, data && data->pMessage ? data->pMessage : "(no text)");
    return VK_FALSE;
}

VkDebugUtilsMessengerCreateInfoEXT messenger_info(Context::Impl* impl) {
    VkDebugUtilsMessengerCreateInfoEXT info{};
    info.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
    info.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    info.pfnUserCallback = on_debug_message;
    info.pUserData = impl;
    return info;
}

bool env_validation() {
    const char* v = std::getenv("TRIDEX_VALIDATION");
    return v && std::strcmp(v, "1") == 0;
}

// True when environment variable `name` is set to "0" (a switch turned off).
bool env_off(const char* name) {
    const char* v = std::getenv(name);
    return v && std::strcmp(v, "0") == 0;
}

bool has_layer(const char* name) {
    std::uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (const auto& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return true;
    return false;
}

bool has_instance_extension(const char* name, const char* layer) {
    std::uint32_t n = 0;
    vkEnumerateInstanceExtensionProperties(layer, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateInstanceExtensionProperties(layer, &n, exts.data());
    for (const auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

void create_instance(Context::Impl& impl) {
    std::uint32_t loader_version = 0;
    if (vkEnumerateInstanceVersion(&loader_version) != VK_SUCCESS || loader_version < VK_API_VERSION_1_2)
        throw Error("gpu: the Vulkan loader is older than 1.2 or not usable (install libvulkan1 >= 1.2)");

    std::vector<const char*> layers, extensions;
    if (impl.validation) {
        if (!has_layer(kValidationLayer))
            throw Error("gpu: validation requested (ContextOptions::validation or TRIDEX_VALIDATION=1) but "
                        "VK_LAYER_KHRONOS_validation is not installed");
        layers.push_back(kValidationLayer);
        if (!has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME, nullptr) &&
            !has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME, kValidationLayer))
            throw Error("gpu: validation requested but the instance lacks VK_EXT_debug_utils");
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }

    for (const std::string& name : impl.instance_extensions) {
        if (!has_instance_extension(name.c_str(), nullptr))
            throw Error("gpu: ContextOptions.instance_extensions: the Vulkan loader does not offer " + name);
        bool listed = false;
        for (const char* e : extensions) listed = listed || name == e;
        if (!listed) extensions.push_back(name.c_str());
    }

    VkApplicationInfo app{};

    app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
    app.pApplicationName = "tridex";
    app.applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
    app.pEngineName = "tridex";
    app.engineVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
    app.apiVersion = VK_API_VERSION_1_2;

    VkDebugUtilsMessengerCreateInfoEXT debug = messenger_info(&impl);
    VkInstanceCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
    info.pNext = impl.validation ? &debug : nullptr;  // also report messages from instance creation
    info.pApplicationInfo = &app;
    info.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    const VkResult r = vkCreateInstance(&info, nullptr, &impl.instance);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw Error("gpu: no Vulkan driver is installed or usable (for Mesa lavapipe set "
                    "VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json)");
    check(r, "vkCreateInstance");

    if (impl.validation) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(impl.instance, "vkCreateDebugUtilsMessengerEXT"));
        if (!create) throw Error("gpu: vkCreateDebugUtilsMessengerEXT is not available");
        check(create(impl.instance, &debug, nullptr, &impl.messenger), "vkCreateDebugUtilsMessengerEXT");
    }
}

// Preference of a device type: lower is better.
int type_rank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
    }
}

// True when `device` offers the device extension `name`.
bool has_device_extension(VkPhysicalDevice device, const char* name) {
    std::uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(device, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> exts(n);
    vkEnumerateDeviceExtensionProperties(device, nullptr, &n, exts.data());
    for (const auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

// Index of a queue family with graphics and compute (and, for presentation with a filter, one that can
// present), or -1.
int graphics_compute_family(const Context::Impl& impl, VkPhysicalDevice device) {
    std::uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &n, families.data());
    const VkQueueFlags want = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    for (std::uint32_t i = 0; i < n; ++i) {
        if ((families[i].queueFlags & want) != want || families[i].queueCount == 0) continue;
        if (impl.presentation && impl.can_present && !impl.can_present(impl.instance, device, i)) continue;
        return static_cast<int>(i);
    }
    return -1;
}

void select_physical_device(Context::Impl& impl) {
    std::uint32_t n = 0;
    check(vkEnumeratePhysicalDevices(impl.instance, &n, nullptr), "vkEnumeratePhysicalDevices");
    if (n == 0)
        throw Error("gpu: no Vulkan device found (for Mesa lavapipe set "
                    "VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json)");
    std::vector<VkPhysicalDevice> devices(n);
    check(vkEnumeratePhysicalDevices(impl.instance, &n, devices.data()), "vkEnumeratePhysicalDevices");

    int best_rank = 1 << 30;
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(d, &p);
        if (p.apiVersion < VK_API_VERSION_1_2) continue;
        if (impl.presentation && !has_device_extension(d, VK_KHR_SWAPCHAIN_EXTENSION_NAME)) continue;
        const int family = graphics_compute_family(impl, d);
        if (family < 0) continue;
        const int rank = type_rank(p.deviceType);
        if (rank < best_rank) {
            best_rank = rank;
            impl.physical = d;
            impl.family = static_cast<std::uint32_t>(family);
            impl.properties = p;
        }
    }
    if (impl.physical == VK_NULL_HANDLE)
        throw Error(impl.presentation
                        ? "gpu: no Vulkan device offers Vulkan 1.2, VK_KHR_swapchain and a graphics+compute queue "
                          "that can present to the window system"
                        : "gpu: no Vulkan device offers Vulkan 1.2 with a graphics+compute queue");
    vkGetPhysicalDeviceMemoryProperties(impl.physical, &impl.memory);
}

void create_device(Context::Impl& impl) {
    VkPhysicalDeviceVulkan12Features have12{};
    have12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
    VkPhysicalDeviceVulkan11Features have11{};
    have11.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES;
    have11.pNext = &have12;
    VkPhysicalDeviceFeatures2 have{};
    have.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    have.pNext = &have11;
    vkGetPhysicalDeviceFeatures2(impl.physical, &have);

    VkPhysicalDeviceVulkan12Features use12{};

    use12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
    VkPhysicalDeviceVulkan11Features use11{};
    use11.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES;
    use11.pNext = &use12;
    VkPhysicalDeviceFeatures2 use{};
    use.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    use.pNext = &use11;
    use11.multiview = have11.multiview;
    use12.shaderOutputLayer = have12.shaderOutputLayer;
    use12.timelineSemaphore = have12.timelineSemaphore;
    use12.hostQueryReset = have12.hostQueryReset;
    use.features.shaderInt64 = have.features.shaderInt64;
    use.features.shaderFloat64 = have.features.shaderFloat64;
    use.features.fragmentStoresAndAtomics = have.features.fragmentStoresAndAtomics;
    // Enabled whenever offered (renderer::DrawBatcher relies on that): indirect multi-draws of per-tile meshes.
    use.features.multiDrawIndirect = have.features.multiDrawIndirect;
    use.features.drawIndirectFirstInstance = have.features.drawIndirectFirstInstance;
    // Enabled whenever offered (compute::GpuSculptor relies on that): one dispatch reaches all three ray sets' slabs.
    use.features.shaderStorageBufferArrayDynamicIndexing = have.features.shaderStorageBufferArrayDynamicIndexing;

    DeviceFeatures& f = impl.features;
    f.multiview = use11.multiview;
    f.shader_output_layer = use12.shaderOutputLayer;
    f.timeline_semaphore = use12.timelineSemaphore;
    f.host_query_reset = use12.hostQueryReset;
    f.shader_int64 = use.features.shaderInt64;
    f.shader_float64 = use.features.shaderFloat64;
    f.fragment_stores_and_atomics = use.features.fragmentStoresAndAtomics;
    f.timestamps = impl.properties.limits.timestampComputeAndGraphics == VK_TRUE;
    f.multi_draw_indirect = use.features.multiDrawIndirect == VK_TRUE;
    f.draw_indirect_first_instance = use.features.drawIndirectFirstInstance == VK_TRUE;
    f.storage_buffer_array_dynamic_indexing = use.features.shaderStorageBufferArrayDynamicIndexing == VK_TRUE;

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{};
    queue.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
    queue.queueFamilyIndex = impl.family;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;

    VkDeviceCreateInfo info{};

    info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
    info.pNext = &use;
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue;
    std::vector<const char*> extensions;
    if (impl.presentation) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    f.calibrated_timestamps = f.timestamps &&
                              has_device_extension(impl.physical, VK_EXT_CALIBRATED_TIMESTAMPS_EXTENSION_NAME) &&
                              can_calibrate_timestamps(impl.instance, impl.physical);
    if (f.calibrated_timestamps) extensions.push_back(VK_EXT_CALIBRATED_TIMESTAMPS_EXTENSION_NAME);
    info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.empty() ? nullptr : extensions.data();
    check(vkCreateDevice(impl.physical, &info, nullptr, &impl.device), "vkCreateDevice");
    vkGetDeviceQueue(impl.device, impl.family, 0, &impl.queue);

    VkCommandPoolCreateInfo pool{};

    pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT | VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = impl.family;
    check(vkCreateCommandPool(impl.device, &pool, nullptr, &impl.pool), "vkCreateCommandPool");
}

}  // namespace

Context Context::create(const ContextOptions& options) {
    auto impl = std::make_unique<Impl>();
    impl->validation = options.validation || env_validation();
    impl->presentation = options.presentation;
    impl->instance_extensions = options.instance_extensions;
    impl->can_present = options.can_present;
    // Threads before and after: a CPU driver (lavapipe) starts its worker threads with the device.
    const std::string creator = current_thread_name();
    const std::vector<ProcessThread> before = process_threads();
    create_instance(*impl);
    select_physical_device(*impl);
    impl->can_present = nullptr;  // only needed for the selection; drop what it holds (e.g. a window library)
    create_device(*impl);
    if (impl->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU && options.spread_cpu_driver_threads && !env_off("TRIDEX_DRIVER_AFFINITY")) {
        const std::vector<ProcessThread> after = process_threads();
        impl->spread_threads = spread_over_cpus(new_worker_threads(before, after, creator));
    }
    return Context(std::move(impl));
}

Context::Context(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Context::~Context() = default;
Context::Context(Context&&) noexcept = default;
Context& Context::operator=(Context&&) noexcept = default;

std::string Context::device_name() const { return impl_->properties.deviceName; }
std::uint32_t Context::validation_messages() const { return impl_->messages.load(std::memory_order_relaxed); }
bool Context::validation_enabled() const { return impl_->validation; }
bool Context::presentation_enabled() const { return impl_->presentation; }
int Context::spread_driver_threads() const { return impl_->spread_threads; }
VkInstance Context::instance() const { return impl_->instance; }
VkPhysicalDevice Context::physical_device() const { return impl_->physical; }
VkDevice Context::device() const { return impl_->device; }
VkQueue Context::queue() const { return impl_->queue; }
std::uint32_t Context::queue_family() const { return impl_->family; }
const VkPhysicalDeviceProperties& Context::properties() const { return impl_->properties; }
const DeviceFeatures& Context::features() const { return impl_->features; }

std::uint32_t Context::memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                                   VkMemoryPropertyFlags preferred) const {
    const VkPhysicalDeviceMemoryProperties& m = impl_->memory;
    int fallback = -1;
    for (std::uint32_t i = 0; i < m.memoryTypeCount; ++i) {
        if (!(type_bits & (1u << i))) continue;
        const VkMemoryPropertyFlags flags = m.memoryTypes[i].propertyFlags;
        if ((flags & required) != required) continue;
        if ((flags & preferred) == preferred) return i;
        if (fallback < 0) fallback = static_cast<int>(i);
    }
    if (fallback < 0) {
        char text[128];
        std::snprintf(text, sizeof text, "gpu: no memory type with property flags 0x%x among allowed types 0x%x",
                      static_cast<unsigned>(required), static_cast<unsigned>(type_bits));
        throw Error(text);
    }
    return static_cast<std::uint32_t>(fallback);
}

void Context::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const {
    Impl& impl = *impl_;
    // The lock guards the shared command pool and the queue: held to record and submit, released while
    // waiting for the fence (so another thread's submission, e.g. a frame, is not held behind this one),
    // taken again to free the command buffer.
    std::unique_lock<std::mutex> lock(impl.queue_mutex);
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = impl.pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    check(vkAllocateCommandBuffers(impl.device, &alloc, &cmd), "vkAllocateCommandBuffers");
    VkFence fence = VK_NULL_HANDLE;
    // Frees the command buffer and fence on every exit path.
    struct Cleanup {
        VkDevice device;
        VkCommandPool pool;
        VkCommandBuffer& cmd;
        VkFence& fence;
        std::unique_lock<std::mutex>& lock;
        ~Cleanup() {
            if (!lock.owns_lock()) lock.lock();
            if (fence != VK_NULL_HANDLE) vkDestroyFence(device, fence, nullptr);
            vkFreeCommandBuffers(device, pool, 1, &cmd);
        }
    } cleanup{impl.device, impl.pool, cmd, fence, lock};

    VkCommandBufferBeginInfo begin{};

    begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
    record(cmd);
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");

    VkFenceCreateInfo fence_info{};

    fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    check(vkCreateFence(impl.device, &fence_info, nullptr, &fence), "vkCreateFence");
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    check(vkQueueSubmit(impl.queue, 1, &submit, fence), "vkQueueSubmit");
    lock.unlock();
    const VkResult r = check(vkWaitForFences(impl.device, 1, &fence, VK_TRUE, kSubmitTimeoutNs), "vkWaitForFences");
    if (r == VK_TIMEOUT) {
        lock.lock();
        vkDeviceWaitIdle(impl.device);  // the command buffer must not be freed while pending
        throw Error("gpu: a submitted command buffer did not finish within 60 s");
    }
}

void Context::queue_submit(const VkSubmitInfo& submit, VkFence fence) const {
    std::lock_guard<std::mutex> lock(impl_->queue_mutex);
    check(vkQueueSubmit(impl_->queue, 1, &submit, fence), "vkQueueSubmit");
}

VkResult Context::queue_present(const VkPresentInfoKHR& present) const {
    if (!impl_->presentation)
        throw Error("gpu: queue_present needs a Context created with ContextOptions.presentation = true");
    std::lock_guard<std::mutex> lock(impl_->queue_mutex);
    const VkResult r = vkQueuePresentKHR(impl_->queue, &present);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) return r;
    return check(r, "vkQueuePresentKHR");
}

void Context::wait_idle() const {
    std::lock_guard<std::mutex> lock(impl_->queue_mutex);
    check(vkDeviceWaitIdle(impl_->device), "vkDeviceWaitIdle");
}

}  // namespace tridex::gpu
