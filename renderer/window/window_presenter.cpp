// renderer/window/window_presenter.cpp - acquire, blit eyes (or upload a composed image), capture, present.
#include "renderer/window/window_presenter.hpp"

#include <array>
#include <chrono>
#include <cstring>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "gpu/barrier.hpp"
#include "gpu/buffer.hpp"
#include "gpu/check.hpp"
#include "gpu/command_pool.hpp"
#include "gpu/image_array.hpp"
#include "gpu/swapchain.hpp"
#include "gpu/unique_handle.hpp"
#include "renderer/stereo/stereo_pipeline.hpp"
#include "renderer/window/window_blit_layout.hpp"

namespace tridex::renderer {
namespace {

using UniqueSemaphore = gpu::UniqueHandle<VkSemaphore, vkDestroySemaphore>;
using gpu::UniqueCommandPool;
constexpr std::uint64_t kFenceTimeoutNs = 10'000'000'000ull;

UniqueSemaphore make_semaphore(VkDevice device) {
    VkSemaphoreCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO;
    VkSemaphore s = VK_NULL_HANDLE;
    gpu::check(vkCreateSemaphore(device, &info, nullptr, &s), "vkCreateSemaphore");
    return UniqueSemaphore(device, s);
}

// Blits the whole of layer `src_layer` (src_w x src_h) into a rectangle of layer `dst_layer`; nearest
// filtering for a 1:1 copy, linear when scaling.
void blit(VkCommandBuffer cmd, VkImage src, int src_w, int src_h, std::uint32_t src_layer, VkImage dst,
          std::uint32_t dst_layer, int x0, int y0, int x1, int y1) {
    VkImageBlit region{};
    region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, src_layer, 1};
    region.srcOffsets[1] = {src_w, src_h, 1};
    region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, dst_layer, 1};
    region.dstOffsets[0] = {x0, y0, 0};
    region.dstOffsets[1] = {x1, y1, 1};
    const bool same = (x1 - x0) == src_w && (y1 - y0) == src_h;
    vkCmdBlitImage(cmd, src, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                   &region, same ? VK_FILTER_NEAREST : VK_FILTER_LINEAR);
}

bool is_bgra(VkFormat f) { return f == VK_FORMAT_B8G8R8A8_UNORM || f == VK_FORMAT_B8G8R8A8_SRGB; }
bool is_rgba(VkFormat f) { return f == VK_FORMAT_R8G8B8A8_UNORM || f == VK_FORMAT_R8G8B8A8_SRGB; }

}  // namespace

struct WindowPresenter::Impl {
    gpu::Context* context = nullptr;
    Window* window = nullptr;
    PresenterOptions options;
    gpu::Surface surface;
    gpu::Swapchain swapchain;
    UniqueCommandPool pool;
    // Two presents in flight: each slot's command buffer, fence, acquire semaphore and timestamp queries are
    // reused only after the GPU has finished the present that last used them.
    struct Slot {
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        gpu::UniqueFence fence;
        UniqueSemaphore acquired;
        gpu::UniqueQueryPool timestamps;  // 2 queries around the present pass (empty without timestamps)
        bool pending = false;             // submitted, not yet seen finished
    };
    std::array<Slot, 2> slots;
    std::size_t next_slot = 0;
    std::vector<UniqueSemaphore> ready;  // one per swapchain image: the present pass finished
    std::uint64_t timestamp_mask = 0;
    gpu::Buffer staging;                 // present_composed: the image's bytes
    gpu::ImageArray upload;              // present_composed: RGBA8 image blitted from
    gpu::Buffer capture_buffer;          // capture: swapchain image bytes
    std::vector<Image> captures;
    std::unique_ptr<FrameSequencer> sequencer;
    FrameTimings timings;
    std::optional<std::chrono::steady_clock::time_point> last_present;
    std::uint64_t presents = 0, recreations = 0;
    int last_eye = -1;
    bool stale = false;  // presentation reported suboptimal/out of date: recreate before the next present

    ~Impl() {
        try {
            if (context) context->wait_idle();
        } catch (const Error&) {
            // destruction must not throw; the device is lost anyway
        }
    }

    void make_per_image_semaphores() {
        ready.clear();
        for (std::size_t i = 0; i < swapchain.images().size(); ++i) ready.push_back(make_semaphore(context->device()));
    }

    void make_capture_buffer() {
        if (!options.capture) return;
        const VkExtent2D e = swapchain.extent();
        capture_buffer = gpu::Buffer::create(*context, VkDeviceSize{e.width} * e.height * 4 * swapchain.layers(),
                                             VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryDomain::kHost);
        captures.assign(swapchain.layers(), Image{});
    }

    // Waits for the slot's present pass (if any) and records its GPU time.
    void finish(Slot& slot) {
        if (!slot.pending) return;
        const VkFence f = slot.fence.get();
        if (gpu::check(vkWaitForFences(context->device(), 1, &f, VK_TRUE, kFenceTimeoutNs), "vkWaitForFences") ==
            VK_TIMEOUT)
            throw Error("window: the present pass did not finish within 10 s");
        slot.pending = false;
        timings.blit_gpu_ms.add(read_timestamps_ms(slot));
    }
    void finish_all() {
        for (Slot& slot : slots) finish(slot);
    }

    void recreate(VkExtent2D size) {
        finish_all();
        swapchain.recreate(size.width, size.height);
        make_per_image_semaphores();
        make_capture_buffer();
        ++recreations;
        stale = false;
    }

    // Brings the swapchain to the window's size; false while minimised.
    bool fit_window() {
        const VkExtent2D fb = window->framebuffer_size();
        if (fb.width == 0 || fb.height == 0) return false;
        const VkExtent2D cur = swapchain.extent();
        if (stale || fb.width != cur.width || fb.height != cur.height) recreate(fb);
        return true;
    }

    double read_timestamps_ms(const Slot& slot) const {
        if (slot.timestamps.get() == VK_NULL_HANDLE) return -1.0;
        std::uint64_t t[2] = {0, 0};
        if (vkGetQueryPoolResults(context->device(), slot.timestamps.get(), 0, 2, sizeof t, t, sizeof t[0],
                                  VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
            return -1.0;
        const std::uint64_t ticks = ((t[1] & timestamp_mask) - (t[0] & timestamp_mask)) & timestamp_mask;
        return static_cast<double>(ticks) * context->properties().limits.timestampPeriod * 1e-6;
    }

    void read_captures() {
        const VkExtent2D e = swapchain.extent();
        const std::size_t bytes = std::size_t{e.width} * e.height * 4;
        const bool bgra = is_bgra(swapchain.format());
        for (std::uint32_t layer = 0; layer < swapchain.layers(); ++layer) {
            Image& img = captures[layer];
            img.width = static_cast<int>(e.width);
            img.height = static_cast<int>(e.height);
            img.rgba.resize(bytes);
            capture_buffer.read(img.rgba.data(), bytes, bytes * layer);
            if (bgra) swap_red_blue(img.rgba);
        }
    }

    // One acquire -> record (the caller's fill of the swapchain image) -> submit -> present. `before_present`
    // runs right before the image is queued (the frame-sequential hook). Returns false while minimised.
    bool present_one(const std::function<void(VkCommandBuffer, VkImage, VkExtent2D)>& fill,
                     const std::function<void()>& before_present) {
        if (!fit_window()) return false;
        Slot& slot = slots[next_slot];
        finish(slot);  // the present two before this one
        const VkCommandBuffer cmd = slot.cmd;
        const gpu::UniqueQueryPool& timestamps = slot.timestamps;
        std::uint32_t index = 0;
        gpu::SwapStatus s = swapchain.acquire(slot.acquired.get(), index);
        if (s == gpu::SwapStatus::kOutOfDate) {
            stale = true;
            if (!fit_window()) return false;
            s = swapchain.acquire(slot.acquired.get(), index);
            if (s == gpu::SwapStatus::kOutOfDate) {
                stale = true;
                return false;
            }
        }
        if (s == gpu::SwapStatus::kSuboptimal) stale = true;
        const VkImage image = swapchain.images().at(index);
        const VkExtent2D extent = swapchain.extent();
        const std::uint32_t layers = swapchain.layers();

        gpu::check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
        VkCommandBufferBeginInfo begin{};
        begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        gpu::check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
        if (timestamps.get() != VK_NULL_HANDLE) {
            vkCmdResetQueryPool(cmd, timestamps.get(), 0, 2);
            vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timestamps.get(), 0);
        }
        // The acquire semaphore is waited at the transfer stage; the transition chains after it.
        gpu::image_barrier(cmd, image, layers, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                      VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
        fill(cmd, image, extent);
        if (options.capture) {
            gpu::image_barrier(cmd, image, layers, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                          VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
                          VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
            VkBufferImageCopy copy{};
            copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, layers};
            copy.imageExtent = {extent.width, extent.height, 1};
            vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, capture_buffer.handle(), 1, &copy);
            VkMemoryBarrier host{};
            host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
            host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &host, 0,
                                 nullptr, 0, nullptr);
            gpu::image_barrier(cmd, image, layers, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, 0,
                          0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
        } else {
            gpu::image_barrier(cmd, image, layers, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                          VK_ACCESS_TRANSFER_WRITE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT,
                          VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
        }
        if (timestamps.get() != VK_NULL_HANDLE)
            vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps.get(), 1);
        gpu::check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");

        const VkSemaphore wait = slot.acquired.get();
        const VkSemaphore signal = ready.at(index).get();
        const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
        VkSubmitInfo submit{};
        submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
        submit.waitSemaphoreCount = 1;
        submit.pWaitSemaphores = &wait;
        submit.pWaitDstStageMask = &wait_stage;
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &cmd;
        submit.signalSemaphoreCount = 1;
        submit.pSignalSemaphores = &signal;
        const VkFence f = slot.fence.get();
        gpu::check(vkResetFences(context->device(), 1, &f), "vkResetFences");
        context->queue_submit(submit, f);
        slot.pending = true;
        next_slot = (next_slot + 1) % slots.size();
        if (options.capture) {  // the captured pixels are read now: wait for this present pass
            finish(slot);
            read_captures();
        }

        if (before_present) before_present();
        const gpu::SwapStatus p = swapchain.present(index, signal);
        if (p != gpu::SwapStatus::kOk) stale = true;
        const auto now = std::chrono::steady_clock::now();
        if (last_present) timings.interval_ms.add(std::chrono::duration<double, std::milli>(now - *last_present).count());
        last_present = now;
        ++presents;
        return true;
    }
};

WindowPresenter WindowPresenter::create(gpu::Context& context, Window& window, const PresenterOptions& options) {
    if (!context.presentation_enabled())
        throw Error("window: WindowPresenter needs a Context created with window_context_options()");
    auto impl = std::make_unique<Impl>();
    impl->context = &context;
    impl->window = &window;
    impl->options = options;
    impl->sequencer = std::make_unique<FrameSequencer>(options.refresh_hz, options.swap_eyes);
    impl->surface = window.create_surface(context);

    const gpu::SurfaceSupport support = gpu::query_surface(context, impl->surface.handle());
    const OutputSupport ok = check_output_support(options.output, support.capabilities.maxImageArrayLayers);
    if (!ok.supported) throw Error("window: " + ok.message);
    const VkExtent2D fb = window.framebuffer_size();
    if (fb.width == 0 || fb.height == 0)
        throw Error("window: the window's framebuffer has size 0 (minimised?); cannot create a swapchain");

    gpu::SwapchainOptions so;
    so.width = fb.width;
    so.height = fb.height;
    so.layers = swapchain_layers(options.output);
    so.vsync = options.vsync;
    so.usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    if (options.capture) so.usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    impl->swapchain = gpu::Swapchain::create(context, impl->surface.handle(), so);
    const VkFormat format = impl->swapchain.format();
    if (options.capture && !is_bgra(format) && !is_rgba(format))
        throw Error("window: PresenterOptions.capture needs a B8G8R8A8 or R8G8B8A8 swapchain; the surface gave format " +
                    std::to_string(static_cast<int>(format)));
    VkFormatProperties src{};
    vkGetPhysicalDeviceFormatProperties(context.physical_device(), kStereoColourFormat, &src);
    const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_BLIT_SRC_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
    if ((src.optimalTilingFeatures & need) != need)
        throw Error("window: " + context.device_name() + " cannot blit the RGBA8 eye images with a linear filter");

    const VkDevice device = context.device();
    impl->pool = gpu::make_command_pool(context, VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT);
    const VkCommandPool p = impl->pool.get();
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = p;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    for (Impl::Slot& slot : impl->slots) {
        gpu::check(vkAllocateCommandBuffers(device, &alloc, &slot.cmd), "vkAllocateCommandBuffers");
        VkFenceCreateInfo fi{};
        fi.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
        VkFence f = VK_NULL_HANDLE;
        gpu::check(vkCreateFence(device, &fi, nullptr, &f), "vkCreateFence");
        slot.fence = gpu::UniqueFence(device, f);
        slot.acquired = make_semaphore(device);
    }
    impl->make_per_image_semaphores();
    impl->make_capture_buffer();

    std::uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(context.physical_device(), &families, nullptr);
    std::vector<VkQueueFamilyProperties> props(families);
    vkGetPhysicalDeviceQueueFamilyProperties(context.physical_device(), &families, props.data());
    const std::uint32_t bits = props.at(context.queue_family()).timestampValidBits;
    if (context.features().timestamps && bits > 0) {
        impl->timestamp_mask = bits >= 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << bits) - 1);
        VkQueryPoolCreateInfo q{};
        q.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
        q.queryType = VK_QUERY_TYPE_TIMESTAMP;
        q.queryCount = 2;
        for (Impl::Slot& slot : impl->slots) {
            VkQueryPool qp = VK_NULL_HANDLE;
            gpu::check(vkCreateQueryPool(device, &q, nullptr, &qp), "vkCreateQueryPool");
            slot.timestamps = gpu::UniqueQueryPool(device, qp);
        }
    }
    return WindowPresenter(std::move(impl));
}

WindowPresenter::WindowPresenter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
WindowPresenter::~WindowPresenter() = default;
WindowPresenter::WindowPresenter(WindowPresenter&&) noexcept = default;
WindowPresenter& WindowPresenter::operator=(WindowPresenter&&) noexcept = default;

int WindowPresenter::present(const OffscreenStereoRenderer& renderer) {
    Impl& im = *impl_;
    if (im.options.output == StereoOutput::kAnaglyph)
        throw Error("window: the anaglyph output mixes pixels: record an AnaglyphPass with present_image(), or "
                    "compose(StereoOutput::kAnaglyph, left, right) on the CPU and call present_composed()");
    if (renderer.frames_rendered() == 0)
        throw Error("window: present() before the renderer has rendered a frame (call render() or draw() first)");
    im.timings.render_gpu_ms.add(renderer.last_gpu_ms());
    const VkImage src = renderer.colour_image();
    const int w = renderer.width(), h = renderer.height();
    const auto blit_plan = [&](const BlitPlan& plan, VkCommandBuffer cmd, VkImage dst) {
        for (int i = 0; i < plan.count; ++i) {
            const EyeBlit& b = plan.blits[static_cast<std::size_t>(i)];
            blit(cmd, src, w, h, static_cast<std::uint32_t>(b.eye), dst, static_cast<std::uint32_t>(b.dst_layer), b.x0,
                 b.y0, b.x1, b.y1);
        }
    };

    if (im.options.output != StereoOutput::kFrameSequential) {
        const bool swap = im.sequencer->swap_eyes();
        const bool shown = im.present_one(
            [&](VkCommandBuffer cmd, VkImage dst, VkExtent2D e) {
                blit_plan(plan_blits(im.options.output, static_cast<int>(e.width), static_cast<int>(e.height), swap),
                          cmd, dst);
            },
            {});
        if (shown) im.last_eye = im.options.output == StereoOutput::kMono ? 0 : -1;
        return shown ? 1 : 0;
    }
    int shown = 0;
    for (int k = 0; k < 2; ++k) {
        const int eye = im.sequencer->next_eye();  // the shutter open at the refresh this present is expected on
        const bool ok = im.present_one(
            [&](VkCommandBuffer cmd, VkImage dst, VkExtent2D e) {
                blit_plan(plan_blits(StereoOutput::kFrameSequential, static_cast<int>(e.width),
                                     static_cast<int>(e.height), false, eye),
                          cmd, dst);
            },
            [&] { im.sequencer->present(); });
        if (!ok) break;
        // When the present call returned (under vsync, the refresh it went out on): a late one moves the
        // sequencer's refresh count on, so the next present shows the eye whose shutter is open then.
        if (im.last_present)
            im.sequencer->presented(std::chrono::duration<double>(im.last_present->time_since_epoch()).count());
        im.last_eye = eye;
        ++shown;
    }
    return shown;
}

int WindowPresenter::present_composed(const Image& image) {
    Impl& im = *impl_;
    if (image.width < 1 || image.height < 1 ||
        image.rgba.size() != static_cast<std::size_t>(image.width) * image.height * 4)
        throw Error("window: present_composed: the image is empty or its rgba size is not width * height * 4");
    const std::size_t bytes = image.rgba.size();
    if (im.staging.size() != bytes) {
        im.context->wait_idle();
        im.staging = gpu::Buffer::create(*im.context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, gpu::MemoryDomain::kHost);
    }
    if (im.upload.handle() == VK_NULL_HANDLE || im.upload.info().width != static_cast<std::uint32_t>(image.width) ||
        im.upload.info().height != static_cast<std::uint32_t>(image.height)) {
        im.context->wait_idle();
        gpu::ImageArrayInfo info;
        info.width = static_cast<std::uint32_t>(image.width);
        info.height = static_cast<std::uint32_t>(image.height);
        info.layers = 1;
        info.format = kStereoColourFormat;
        // SAMPLED only because ImageArray always makes views (a view needs a view-capable usage).
        info.usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        im.upload = gpu::ImageArray::create(*im.context, info);
    }
    im.finish_all();  // earlier presents may still blit from `upload`, filled from `staging`
    im.staging.write(image.rgba.data(), bytes);
    const VkImage up = im.upload.handle();
    return present_image(up, kStereoColourFormat, image.width, image.height, [&](VkCommandBuffer cmd) {
        // Earlier blits from `up` are complete (finish_all() above), so its old contents may be discarded.
        gpu::image_barrier(cmd, up, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                      VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.imageExtent = {static_cast<std::uint32_t>(image.width), static_cast<std::uint32_t>(image.height), 1};
        vkCmdCopyBufferToImage(cmd, im.staging.handle(), up, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
        gpu::image_barrier(cmd, up, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT);
    });
}

int WindowPresenter::present_image(VkImage image, VkFormat format, int width, int height,
                                   const std::function<void(VkCommandBuffer)>& record_first) {
    Impl& im = *impl_;
    if (image == VK_NULL_HANDLE || width < 1 || height < 1)
        throw Error("window: present_image: the image is null or its size " + std::to_string(width) + "x" +
                    std::to_string(height) + " is below 1x1");
    if (format != VK_FORMAT_R8G8B8A8_UNORM && format != VK_FORMAT_B8G8R8A8_UNORM)
        throw Error("window: present_image: format " + std::to_string(static_cast<int>(format)) +
                    " is neither R8G8B8A8_UNORM nor B8G8R8A8_UNORM");
    const bool shown = im.present_one(
        [&](VkCommandBuffer cmd, VkImage dst, VkExtent2D e) {
            if (record_first) record_first(cmd);
            const bool same = format == im.swapchain.format() && static_cast<std::uint32_t>(width) == e.width &&
                              static_cast<std::uint32_t>(height) == e.height;
            for (std::uint32_t layer = 0; layer < im.swapchain.layers(); ++layer) {
                if (same) {
                    VkImageCopy region{};
                    region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                    region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, layer, 1};
                    region.extent = {e.width, e.height, 1};
                    vkCmdCopyImage(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst,
                                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
                } else {
                    blit(cmd, image, width, height, 0, dst, layer, 0, 0, static_cast<int>(e.width),
                         static_cast<int>(e.height));
                }
            }
        },
        {});
    if (shown) im.last_eye = -1;
    return shown ? 1 : 0;
}

StereoOutput WindowPresenter::output() const { return impl_->options.output; }
FrameSequencer& WindowPresenter::sequencer() { return *impl_->sequencer; }
const FrameSequencer& WindowPresenter::sequencer() const { return *impl_->sequencer; }
void WindowPresenter::set_swap_eyes(bool swap) { impl_->sequencer->set_swap_eyes(swap); }
bool WindowPresenter::swap_eyes() const { return impl_->sequencer->swap_eyes(); }
VkExtent2D WindowPresenter::extent() const { return impl_->swapchain.extent(); }
VkFormat WindowPresenter::format() const { return impl_->swapchain.format(); }
const char* WindowPresenter::present_mode() const { return gpu::present_mode_name(impl_->swapchain.present_mode()); }
std::uint32_t WindowPresenter::max_image_array_layers() const { return impl_->swapchain.max_image_array_layers(); }
std::uint64_t WindowPresenter::presents() const { return impl_->presents; }
std::uint64_t WindowPresenter::recreations() const { return impl_->recreations; }
int WindowPresenter::last_eye() const { return impl_->last_eye; }
const FrameTimings& WindowPresenter::timings() const { return impl_->timings; }
void WindowPresenter::finish() { impl_->finish_all(); }

const Image& WindowPresenter::last_capture(int layer) const {
    static const Image empty;
    if (layer < 0 || layer >= static_cast<int>(impl_->swapchain.layers()))
        throw Error("window: last_capture layer " + std::to_string(layer) + " is outside the swapchain's " +
                    std::to_string(impl_->swapchain.layers()) + " layer(s)");
    if (!impl_->options.capture) return empty;
    return impl_->captures.at(static_cast<std::size_t>(layer));
}

}  // namespace tridex::renderer
