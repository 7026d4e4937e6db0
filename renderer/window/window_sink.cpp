// renderer/window/window_sink.cpp - window presentation of each stereo output; anaglyph through the GPU pass.
#include "renderer/window/window_sink.hpp"

#include "core/error.hpp"

namespace tridex::renderer {

std::unique_ptr<WindowSink> WindowSink::create(gpu::Context& context, Window& window, const SinkOptions& options,
                                               bool vsync) {
    PresenterOptions po;
    po.output = options.output;
    po.vsync = vsync;
    po.swap_eyes = options.swap_eyes;
    po.refresh_hz = options.refresh_hz;
    return std::unique_ptr<WindowSink>(new WindowSink(context, WindowPresenter::create(context, window, po), options));
}

WindowSink::WindowSink(gpu::Context& context, WindowPresenter presenter, const SinkOptions& options)
    : context_(&context), presenter_(std::move(presenter)), options_(options) {}

StereoOutput WindowSink::output() const { return options_.output; }

int WindowSink::present(const OffscreenStereoRenderer& renderer) {
    if (options_.output != StereoOutput::kAnaglyph) return presenter_.present(renderer);
    if (renderer.frames_rendered() == 0) throw Error("window sink: present() before the renderer's first frame");
    // In the swapchain's format when it is one the pass writes, so that presenting it is a copy, not a blit.
    const VkFormat format =
        presenter_.format() == VK_FORMAT_B8G8R8A8_UNORM ? VK_FORMAT_B8G8R8A8_UNORM : VK_FORMAT_R8G8B8A8_UNORM;
    if (!anaglyph_ || anaglyph_->format() != format)
        anaglyph_.emplace(AnaglyphPass::create(*context_, renderer.width(), renderer.height(), format));
    else
        anaglyph_->resize(renderer.width(), renderer.height());  // follows the render scale or the window; else nothing
    AnaglyphPass& pass = *anaglyph_;
    const bool swap = presenter_.swap_eyes();
    return presenter_.present_image(pass.image(), pass.format(), pass.width(), pass.height(),
                                    [&](VkCommandBuffer cmd) { pass.record(cmd, renderer, options_.anaglyph, swap); });
}

void WindowSink::set_swap_eyes(bool swap) { presenter_.set_swap_eyes(swap); }
std::uint64_t WindowSink::presents() const { return presenter_.presents(); }
int WindowSink::last_eye() const {
    return options_.output == StereoOutput::kFrameSequential ? presenter_.last_eye() : -1;
}
std::string WindowSink::present_mode() const { return presenter_.present_mode(); }
std::vector<std::string> WindowSink::notes() const { return {}; }
nlohmann::json WindowSink::present_timings() const {
    nlohmann::json j = presenter_.timings().to_json();
    if (options_.output == StereoOutput::kFrameSequential) {
        j["missed_refreshes"] = presenter_.sequencer().missed_refreshes();
        j["late_presents"] = presenter_.sequencer().late_presents();
    }
    return j;
}

std::vector<std::string> WindowSink::finish(const OffscreenStereoRenderer&, const std::string&) { return {}; }

WindowPresenter& WindowSink::presenter() { return presenter_; }

}  // namespace tridex::renderer
