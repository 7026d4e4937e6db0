// renderer/output/stereo_sink.hpp - where stereo frames go (offscreen images, a window): each output's policy in
// one place.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/pose.hpp"
#include "renderer/timing/frame_stats.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/output/stereo_output.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::renderer {

/// The off-axis stereo camera of one frame (metres, the renderer's world frame).
struct StereoCamera {
    Screen screen;                  ///< screen corners, m
    Pose head;                      ///< head pose, m
    double eye_separation_m = 0.0;  ///< interpupillary distance, m (a mono sink draws the head centre: 0)
    double near_m = 0.05;           ///< near plane, m
    double far_m = 20.0;            ///< far plane, m
};

/// What every sink is made with.
struct SinkOptions {
    StereoOutput output = StereoOutput::kSideBySide;
    /// Exchange the eyes (every output but mono); see ComposeOptions::swap_eyes.
    bool swap_eyes = false;
    /// The anaglyph mixing (kAnaglyph only).
    AnaglyphMethod anaglyph = AnaglyphMethod::kDubois;
    /// The display's present rate, Hz (frame-sequential sequencing: each eye at refresh_hz / 2).
    double refresh_hz = 60.0;
};

/// A stereo output seam: a sink takes each frame from an OffscreenStereoRenderer and shows it the way its
/// StereoOutput needs, owning that output's policy: which eyes are rendered (mono: one, at the head centre),
/// frame-sequential sequencing (FrameSequencer: two presents per frame, shutter order, swap), eye swapping,
/// the composition (side-by-side, top-bottom, their halves, anaglyph on the GPU, mono, quad layers), present
/// counting and the eye shown last. A frame is draw() (the renderer reads the scene's buffers) then present()
/// (only the renderer's own images are read), so that the caller may release the scene's buffers in between;
/// finish() writes what the sink keeps of the run. One thread at a time (the render thread); the renderer
/// passed must be the same for every call.
class StereoSink {
public:
    virtual ~StereoSink() = default;

    /// The output shown.
    virtual StereoOutput output() const = 0;
    /// Eyes rendered per frame: 2, or 1 for mono.
    int eye_count() const { return needs_both_eyes(output()) ? 2 : 1; }
    /// Display presents per rendered frame: 2 for frame-sequential (one per eye), 1 otherwise.
    int presents_per_frame() const { return output() == StereoOutput::kFrameSequential ? 2 : 1; }

    /// Renders one frame of `scene` seen by `camera` with the sink's eye count (SceneView::eye_count is
    /// overridden; mono draws one eye at the head, eye separation 0). Returns the frame's statistics.
    /// Throws what OffscreenStereoRenderer::draw throws.
    FrameStats draw(OffscreenStereoRenderer& renderer, const SceneView& scene, const StereoCamera& camera);
    /// Shows the renderer's last frame: composes and presents (window) or counts presents (offscreen).
    /// Returns the number of images presented for it (0 while a window is minimised). Throws tridex::Error
    /// before the renderer's first frame or on a Vulkan failure.
    virtual int present(const OffscreenStereoRenderer& renderer) = 0;
    /// Exchanges the eyes from the next present on.
    virtual void set_swap_eyes(bool swap) = 0;
    /// Images presented so far.
    virtual std::uint64_t presents() const = 0;
    /// Frame-sequential: the eye shown by the last present (0 left, 1 right; -1 before the first). Every
    /// other output: -1 (both eyes shown together, one view for mono, or quad's two layers at once).
    virtual int last_eye() const = 0;
    /// How frames are presented: "offscreen", or the swapchain's present mode ("fifo", ...).
    virtual std::string present_mode() const = 0;
    /// Lines for the run report about how this output is shown (may be empty).
    virtual std::vector<std::string> notes() const = 0;
    /// Present timings (WindowPresenter::timings().to_json()); null when the sink has none.
    virtual nlohmann::json present_timings() const = 0;
    /// Ends the run: writes the sink's files of the renderer's last frame into the existing folder `out_dir`
    /// (offscreen: left.png, right.png, output.png; a window: none) and returns their paths. Throws
    /// tridex::Error when a file cannot be written, or when a sink that writes files is called before the
    /// renderer's first frame.
    virtual std::vector<std::string> finish(const OffscreenStereoRenderer& renderer, const std::string& out_dir) = 0;
};

}  // namespace tridex::renderer
