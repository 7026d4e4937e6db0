// renderer/output/offscreen_sink.cpp - present counting, frame-sequential order and the PNGs of an offscreen run.
#include "renderer/output/offscreen_sink.hpp"

#include <filesystem>

#include "core/error.hpp"

namespace tridex::renderer {

OffscreenSink::OffscreenSink(gpu::Context& context, const SinkOptions& options)
    : context_(&context), options_(options), sequencer_(options.refresh_hz, options.swap_eyes) {}

StereoOutput OffscreenSink::output() const { return options_.output; }

int OffscreenSink::present(const OffscreenStereoRenderer& renderer) {
    if (renderer.frames_rendered() == 0) throw Error("offscreen sink: present() before the renderer's first frame");
    if (options_.output != StereoOutput::kFrameSequential) {
        ++presents_;
        return 1;
    }
    for (int k = 0; k < 2; ++k) last_eye_ = sequencer_.present();
    presents_ += 2;
    return 2;
}

void OffscreenSink::set_swap_eyes(bool swap) {
    options_.swap_eyes = swap;
    sequencer_.set_swap_eyes(swap);
}

std::uint64_t OffscreenSink::presents() const { return presents_; }
int OffscreenSink::last_eye() const { return last_eye_; }
std::string OffscreenSink::present_mode() const { return "offscreen"; }

std::vector<std::string> OffscreenSink::notes() const {
    if (options_.output != StereoOutput::kQuad) return {};
    return {"quad offscreen: the two layers are written as left.png (layer 0) and right.png (layer 1); output.png "
            "shows layer 0"};
}

nlohmann::json OffscreenSink::present_timings() const { return nullptr; }

std::vector<std::string> OffscreenSink::finish(const OffscreenStereoRenderer& renderer, const std::string& out_dir) {
    const StereoImages eyes = renderer.last_images();
    Image shown;
    if (options_.output == StereoOutput::kAnaglyph) {
        if (!anaglyph_) anaglyph_.emplace(AnaglyphPass::create(*context_, renderer.width(), renderer.height()));
        shown = anaglyph_->compose(renderer, options_.anaglyph, options_.swap_eyes);
    } else {
        ComposeOptions co;
        co.swap_eyes = options_.swap_eyes;
        if (options_.output == StereoOutput::kFrameSequential && sequencer_.presents() > 0)
            co.eye_slot = sequencer_.shutter_for_present(sequencer_.presents() - 1);
        shown = compose(options_.output, eyes.left, eyes.right, co);
    }
    const std::filesystem::path out(out_dir);
    std::vector<std::string> files;
    for (const auto& [name, img] : {std::pair<const char*, const Image*>{"left.png", &eyes.left},
                                    {"right.png", &eyes.right}, {"output.png", &shown}}) {
        files.push_back((out / name).string());
        write_png(files.back(), *img);
    }
    return files;
}

}  // namespace tridex::renderer
