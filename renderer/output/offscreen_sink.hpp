// renderer/output/offscreen_sink.hpp - a stereo sink without a display: counts presents, writes the last frame as PNGs.
#pragma once

#include <optional>

#include "gpu/context.hpp"
#include "renderer/output/anaglyph_pass.hpp"
#include "renderer/output/frame_sequencer.hpp"
#include "renderer/output/stereo_sink.hpp"

namespace tridex::renderer {

/// The offscreen StereoSink: present() shows nothing but counts what a display would be sent (frame-sequential:
/// two presents per frame through a FrameSequencer, with the eye order and swap of a window); finish() writes
/// the last frame's left.png and right.png (each eye; mono: the one view in both; quad: layer 0 and layer 1)
/// and output.png, what the display shows: compose() of the eyes (frame-sequential: the eye of the last present;
/// quad: layer 0), and for anaglyph the GPU AnaglyphPass. The Context must outlive it.
class OffscreenSink final : public StereoSink {
public:
    /// Throws tridex::Error when options.refresh_hz is not in (0, 1000] Hz.
    OffscreenSink(gpu::Context& context, const SinkOptions& options);

    StereoOutput output() const override;
    int present(const OffscreenStereoRenderer& renderer) override;
    void set_swap_eyes(bool swap) override;
    std::uint64_t presents() const override;
    int last_eye() const override;
    std::string present_mode() const override;   ///< "offscreen"
    std::vector<std::string> notes() const override;  ///< quad: how its two layers are written
    nlohmann::json present_timings() const override;  ///< null
    std::vector<std::string> finish(const OffscreenStereoRenderer& renderer, const std::string& out_dir) override;

private:
    gpu::Context* context_;
    SinkOptions options_;
    FrameSequencer sequencer_;
    std::optional<AnaglyphPass> anaglyph_;
    std::uint64_t presents_ = 0;
    int last_eye_ = -1;
};

}  // namespace tridex::renderer
