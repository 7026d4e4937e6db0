// renderer/window/window_sink.hpp - a stereo sink presenting in a GLFW window through a WindowPresenter.
#pragma once

#include <memory>
#include <optional>

#include "gpu/context.hpp"
#include "renderer/output/anaglyph_pass.hpp"
#include "renderer/output/stereo_sink.hpp"
#include "renderer/window/window_glfw.hpp"
#include "renderer/window/window_presenter.hpp"

namespace tridex::renderer {

/// The window StereoSink: every output through its WindowPresenter (vsync'd swapchain; GPU blits of the eye
/// layers laid out per output; frame-sequential as two presents in the sequencer's eye order), and anaglyph
/// composed on the GPU by an AnaglyphPass recorded into the present's command buffer, then blitted. No CPU
/// readback. The Context and the Window must outlive it. Main thread only (GLFW).
class WindowSink final : public StereoSink {
public:
    /// Creates the presenter (PresenterOptions from `options`, `vsync`). Throws tridex::Error as
    /// WindowPresenter::create does (quad on a surface without 2 layers, minimised window, Vulkan failure).
    static std::unique_ptr<WindowSink> create(gpu::Context& context, Window& window, const SinkOptions& options,
                                              bool vsync = true);

    StereoOutput output() const override;
    int present(const OffscreenStereoRenderer& renderer) override;
    void set_swap_eyes(bool swap) override;
    std::uint64_t presents() const override;
    int last_eye() const override;
    std::string present_mode() const override;        ///< the swapchain's ("fifo" with vsync)
    std::vector<std::string> notes() const override;  ///< none
    nlohmann::json present_timings() const override;  ///< WindowPresenter::timings().to_json()
    std::vector<std::string> finish(const OffscreenStereoRenderer& renderer, const std::string& out_dir) override;

    /// The presenter (captures, sequencer hook, extent).
    WindowPresenter& presenter();

private:
    WindowSink(gpu::Context& context, WindowPresenter presenter, const SinkOptions& options);
    gpu::Context* context_;
    WindowPresenter presenter_;
    SinkOptions options_;
    std::optional<AnaglyphPass> anaglyph_;
};

}  // namespace tridex::renderer
