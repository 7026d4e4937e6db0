// app/session/run/run_pipeline_parts.hpp - the parts of a run session (RunPipeline::Parts), shared by the files that define its
// steps: app/session/run/run_pipeline.cpp (open, collect, outputs) and app/session/run/run_frame.cpp (the frame loop). Private to them.
#pragma once

#include "app/session/run/run_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <deque>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "app/input/dtrack_head.hpp"
#include "app/input/dtrack_wand.hpp"
#include "app/input/run_input.hpp"
#include "app/menu/menu_frame.hpp"
#include "app/menu/pie_menu_mesh.hpp"
#include "app/scene/study_recording.hpp"
#include "app/scene/test_pattern.hpp"
#include "app/scene/workpiece_source.hpp"
#include "app/session/view/elastic_view.hpp"
#include "app/session/view/more_view.hpp"
#include "app/session/view/presence_view.hpp"
#include "app/session/view/symmetry_view.hpp"
#include "app/session/view/frame_budget.hpp"
#include "app/session/runtime/frame_loop.hpp"
#include "app/session/view/gpu_tile_split.hpp"
#include "app/session/report/report.hpp"
#include "app/session/run/run_head.hpp"
#include "app/session/run/run_actions.hpp"
#include "app/session/run/run_mouse.hpp"
#include "app/session/run/run_report.hpp"
#include "app/session/run/run_sculpt.hpp"
#include "app/session/view/run_view.hpp"
#include "app/session/record/session_recording.hpp"
#include "app/session/report/session_report.hpp"
#include "app/session/view/study_view.hpp"
#include "app/session/view/tile_view.hpp"
#include "app/support/device_lost.hpp"
#include "app/support/stop_signal.hpp"
#include "compute/mesh/mesh_export.hpp"
#include "compute/runtime/detail_requests.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "gpu/context.hpp"
#include "renderer/camera/head_pose.hpp"
#include "renderer/camera/scene_navigation.hpp"
#include "renderer/output/offscreen_sink.hpp"
#include "renderer/output/stereo_sink.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "renderer/window/window_glfw.hpp"
#include "renderer/window/window_sink.hpp"

namespace tridex::app {

namespace run_detail {

using Clock = std::chrono::steady_clock;

/// Milliseconds from a to b.
inline double ms_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}
/// Seconds since t0.
inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Force arrow scale, m per N: 2 cm per N, so the 3.3 N peak of the simulated Omni-class device is a 6.6 cm arrow.
inline constexpr double kForceMetresPerNewton = 0.02;

/// An empty result of the run set up as `setup`.
inline RunResult result_for(RunSetup setup) {
    RunResult r;
    r.setup = std::move(setup);
    return r;
}

}  // namespace run_detail

using run_detail::Clock;

// Every part of the session, declared in the order it is made, so that it is destroyed in the reverse order (the
// sculpting threads before the renderer, the sink, the window, the Context and GLFW).
struct RunPipeline::Parts final : FrameSteps {
    Clock::time_point t_start = Clock::now();
    RunResult r;
    const RunSetup& su;
    const RunScene& scene;
    const renderer::DisplayConfig& dc;
    const bool offscreen;
    const int eye_w, eye_h;

    // 1. Display.
    std::optional<renderer::WindowSystemScope> glfw_scope;
    std::optional<gpu::Context> ctx;
    std::optional<renderer::Window> window;  // none offscreen (the images are read back on the last frame)
    std::unique_ptr<renderer::StereoSink> sink;
    std::optional<renderer::OffscreenStereoRenderer> rend;
    // 2. Head, navigation, wand.
    renderer::KeyboardMouseHead* km = nullptr;
    renderer::TrackerHead* tracker = nullptr;
    DTrackHead* dtrack = nullptr;
    std::unique_ptr<renderer::HeadPoseProvider> head;
    renderer::SceneNavigation nav;
    renderer::MouseNavigation mouse;
    std::optional<RunInput> input;
    std::unique_ptr<DTrackWand> wand;
    std::optional<WandNavigator> wand_nav;
    double wand_prev_t = 0.0;
    WandSample wand_now;  // this frame's wand, read once by take_input()
    // 3. Sculpting threads and what draws beside them.
    compute::DetailRequests detail;  // the groups the frames want at full resolution, for a coarse-first start-up
    compute::DrawnGroups drawn;      // the groups the frames drew at a level, for a stroke's coarse levels
    std::optional<SculptBackend> backend;
    GpuContourShare* gpu_contour = nullptr;
    renderer::IndirectWorkpiece indirect;  // this frame's view of the GPU contour
    std::optional<RunMouse> mouse_stylus;  // --device mouse: the cursor drives the device; navigation moves to Alt
    PickSurface gpu_pick;                  // the GPU contour read back for the stylus's picks
    std::uint64_t gpu_pick_updates = 0;    // gpu_contour->updates() when it was read
    Clock::time_point gpu_pick_at{};
    std::uint64_t gpu_pick_reads = 0;
    double script_end_s = 0.0;  // offscreen, scripted cursor: the run ends this long (device time) after its start
    double safety_s = 0.0;      // offscreen without limits: the wall-time safety net, s (0 = none)
    std::optional<study::StudyView> study_view;    // a study scene's objects, drawn instead of the workpiece
    std::optional<ElasticView> elastic_view;       // scene objects, dented where the loop feels them
    std::vector<renderer::SceneObject> reference_objects;  // the scene's reference objects, placed by their poses
    MoreWorkpiecesView more_view;                  // the further workpieces, through the poses the loop holds
    std::vector<PlacedMesh> reference_placed;      // the reference objects the mouse stylus picks beside the workpiece
    std::optional<SymmetryGhosts> ghosts;          // the symmetric tools and the mirror planes, while symmetry is on
    std::optional<compute::TriDexel> clay_start;   // a clay session's model before it (deformation.max_displacement_m)
    std::vector<renderer::SceneObject> frame_objects;  // this frame's study and scene objects
    std::vector<SitePresence> others_now;             // the other sites the companions know of, this frame
    PresenceView presence_view;                       // draws them (keeps their meshes)
    std::vector<PatternPiece> pattern;                 // --test-pattern: its pieces (world m), drawn as objects
    std::vector<renderer::SceneObject> pattern_objects;
    Vec3 last_head_m{0.0};                             // the head position the last frame was drawn from, world m
    Vec3 last_eye_scene_m{0.0};                        // ... the cyclopean eye in the scene's frame, scene m
    // The hands' controls: what actions do, the bindings and the pie menu, and the open menu's meshes and objects.
    std::optional<RunActions> actions;
    std::optional<HandControls> controls;
    MenuDrawing menu_drawing;  // the menu's meshes, rebuilt when it changes
    MenuFrame menu_now;     // what this frame's menu shows
    MenuTrack menu_track;   // every change of it, by device time (a recording's menu track)
    bool menu_detent_refused = false;  // the loop refused the menu's detent (said once in the notes)
    std::optional<Ray> pointer_ray;    // the desk: the cursor's ray at the last frame (scene m)
    double pointer_m_per_px = 0.0;     // ... a pixel's size one metre from the eye along it (0: unknown)
    // 4. Frame loop state.
    bool swap = false, ao = true;
    bool sculpting = false;    // this frame is drawn within kSculptingHoldS of a sculpted change
    bool final_frame = false;  // last_frame() named this frame
    std::optional<FrameBudget> budget;             // occlusion, levels' error and render scale on the frame-time budget
    std::uint64_t sculpt_steps_drawn = 0;          // the sculpt steps of the last mesh a frame drew
    Clock::time_point sculpted_drawn_at{};         // when a frame last drew a mesh with more sculpt steps
    RateMeter haptic_rate{1.0}, sculpt_rate{1.0};  // overlay: haptic ticks/s (loop time), sculpt steps/s (wall time)
    double prev_frame_ms = -1.0;
    // Frames that first drew a sculpted change and have not finished on the device: the renderer's frame number,
    // the change's oldest tool sample and when the frame was submitted (steady clock, s).
    struct ChangeDrawn {
        std::uint64_t frame = 0;
        double sample_s = 0.0;
        double submitted_s = 0.0;
    };
    std::deque<ChangeDrawn> changes_in_flight;
    std::uint64_t sculpted_seen = 0;  // the runtime's sculpted_changes() count before the last frame took its mesh
    TileView tiles;  // this frame's view of the published tiles and their levels of detail
    GpuTileSplit gpu_split;  // GPU contour with levels: the read-back tiles this frame draws instead of the buffers
    std::string ended = "the window was closed";
    std::size_t next_key = 0;     // scene.keys not yet pressed
    double script_t_s = 0.0;      // the device time this frame's scripted keys and cursor use, read once per frame
    bool journal_warned = false;  // said once that the journal stopped
    Clock::time_point t_render{}, prev_start{};
    std::optional<Pose> last_good_head;   // the newest head pose whose eyes saw the screen
    std::uint64_t head_frames_held = 0;   // frames drawn from last_good_head instead of the head provider's pose
    SaveStatus saving;                    // this frame's save status, read once by take_input()
    std::string model_save_path;          // where Ctrl+S writes the model (SculptOptions::save_path)
    std::uint64_t scene_saves = 0;        // the saves whose scene of models (saved_scene.hpp) was written
    renderer::Screen screen_now{};        // the screen this frame is drawn through (follow_window)
    renderer::Screen base_screen{};       // the screen at the renderer's first size (a desk window: the framing)
    int base_w = 0, base_h = 0;           // the renderer's first size, px
    int window_eye_w = 0, window_eye_h = 0;  // a desk window's eye size before the render scale, px (follow_window)
    std::uint64_t render_scale_changes = 0;  // eye images resized by the budget's render scale
    std::uint64_t window_resizes = 0;     // times the eye images followed the window to a new size

    std::vector<SessionCompanion*> companions;  // beside the frames (a cluster's rank 0)
    std::string companion_failure;              // the first companion's failure; ends the session
    FrameShown shown;                           // the last frame as the companions saw it

    explicit Parts(const RunOptions& options, std::vector<SessionCompanion*> with)
        : r(run_detail::result_for(resolve_run(options))),
          su(r.setup),
          scene(su.scene),
          dc(scene.display),
          offscreen(su.display == DisplayKind::kOffscreen),
          eye_w(dc.width_px),
          eye_h(dc.height_px),
          mouse(renderer::MouseNavigation::for_screen(dc.screen, dc.width_px)),
          companions(std::move(with)) {
        if (!companions.empty() && !scene.spec.more_workpieces.empty())  // their wires carry one model
            throw Error(scene.source + ": field 'workpieces': a shared session or a cluster wall takes one workpiece; "
                        "this scene has " + std::to_string(1 + scene.spec.more_workpieces.size()) + " (docs/workpieces.md)");
        screen_now = dc.screen;
        open_display();
        open_inputs();
        open_backend();
        frame_desk_window();
    }

    void open_display();
    void open_inputs();
    void open_backend();
    void frame_loop();
    // The frame's steps (FrameSteps), driven by run_frames.
    bool take_input() override;
    bool last_frame(std::uint64_t frame) override;
    void draw(std::uint64_t frame) override;
    bool wait_for_news(Clock::time_point deadline) override;
    void frame_desk_window();
    renderer::Screen follow_window();
    renderer::SceneView frame_view(const MeshFrame& mesh, const haptics::LoopView& lv, const SaveStatus& saving);
    void add_menu(renderer::SceneView& view, const haptics::LoopView& lv, const SaveStatus& saving);
    /// A frame's camera and its start (after the head and window, before the mouse stylus).
    struct FrameAim {
        RunCamera camera;
        Clock::time_point t0;
    };
    FrameAim aim(const MeshFrame& mesh);
    /// Takes the renderer's finished frames into the report, and the sample-to-drawn time of those that first drew
    /// a sculpted change (at the later of the device's end of the frame, when its timestamps are calibrated, and the
    /// end of its submit and present).
    void take_finished_frames();
    void present(std::uint64_t frame, const FrameAim& aim, const haptics::LoopView& lv, renderer::SceneView& view,
                 std::unique_lock<std::mutex>& contour_lock);
    void collect();
    void write_outputs();
};


}  // namespace tridex::app
