// app/session/run/run_session.hpp - `tridex run`: one stereo session, one code path for a window, fullscreen or offscreen.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/actions/bindings.hpp"
#include "app/scene/run_scene.hpp"
#include "app/session/run/run_options.hpp"
#include "compute/gpu/gpu_contourer.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/duration_histogram.hpp"
#include "haptics/haptic_loop.hpp"
#include "renderer/output/stereo_output.hpp"
#include "renderer/timing/frame_stats.hpp"
#include "renderer/window/window_frame_timing.hpp"

namespace tridex::app {

/// RunOptions checked and merged with the scene they name.
struct RunSetup {
    DisplayKind display = DisplayKind::kWindow;
    RunScene scene;                 ///< the scene, its display replaced by --display-config and --stereo applied
    bool swap_eyes = false;         ///< --swap-eyes or the display config's swap_eyes
    int frames = 0;                 ///< frame limit (0 = none)
    double seconds = 0.0;           ///< wall-time limit, s (0 = none)
    std::string out;                ///< output folder
    int monitor_index = -1;         ///< fullscreen monitor by index, -1 = by name / primary
    std::string monitor_name;       ///< fullscreen monitor by (part of its) name
    bool validate = false;          ///< Vulkan validation layer
    bool cpu = false;               ///< sculpt on the CPU pool (--cpu)
    bool gpu = false;               ///< sculpt on the GPU compute path (--gpu)
    bool cpu_contour = false;       ///< contour on the CPU even when sculpting on the GPU (--cpu-contour)
    bool gpu_contour = false;       ///< contour on the GPU even on a CPU Vulkan device (--gpu-contour)
    bool gpu_clay = false;          ///< clay on the GPU kernel even on a CPU Vulkan device (--gpu-clay)
    bool pace = true;               ///< offscreen: frames paced at the display's rate
    bool early_frames = true;       ///< offscreen and paced: a sculpted change starts a frame early
    bool items = true;              ///< proxy, force arrow and overlay drawn
    bool overlay_stats = false;     ///< the overlay also counts tiles drawn and skipped per eye
    bool test_pattern = false;      ///< the wall's test pattern instead of the workpiece (RunOptions::test_pattern)
    bool tiles = true;              ///< workpiece as per-tile meshes (false: whole mesh)
    bool cull = true;               ///< tiles culled per eye
    bool lod = true;                ///< tile levels of detail (--lod on|off|coarse|simplified, on by default; docs/design/lod.md)
    /// Groups of tiles take their levels from the model read at coarser strides from this many cells along the
    /// model's longest side (compute::LodWorkerOptions::coarse_groups_from_cells; --lod coarse: 1, simplified: 0).
    int coarse_groups_from_cells = compute::kCoarseGroupsFromCells;
    /// With coarse groups: the tiles are contoured after a first mesh of coarse levels (--startup coarse, default).
    bool coarse_first = true;
    /// With coarse groups: a stroke's tiles wait while it is open, drawn by the coarse levels (--stroke-contour).
    bool stroke_coarse = true;
    bool ao = true;                 ///< ambient occlusion at the start (--ao, else the display config's; key O toggles)
    std::string ao_sculpting = "auto";  ///< --ao-while-sculpting: on | off | auto (RunOptions::ao_sculpting)
    double frame_target_ms = 25.0;  ///< the frame-time budget's target, ms (--frame-target-ms; 0 = none)
    double min_render_scale = 0.75;  ///< a desk window's lowest render scale on the budget (--min-render-scale)
    double max_lod_px = 2.0;         ///< the coarsest levels' error on screen on the budget, px (--max-lod-px)
    std::string record;             ///< recording file ("" = none)
    std::string save;               ///< the final model's file (.tdx; "" = none)
    std::string journal;            ///< session journal file ("" = none)
    double checkpoint_s = 120.0;    ///< wall time between checkpoint models, s (0 = none)
    /// The tool's and the wand's buttons and axes: the drivers' defaults, the scene's "bindings", then --bindings.
    Bindings bindings;
    std::function<void(const RunFrameProbe&)> frame_probe;  ///< RunOptions::frame_probe (empty = none)
};

/// The renderer's FrameStats of a run's frames, kept for report.json in bounded memory: sums and histograms over
/// every frame, and the per-frame tile counts of the first kTileFramesKept frames.
struct RenderLog {
    static constexpr std::size_t kTileFramesKept = 1000;  ///< frames whose tile counts `tiles` keeps
    std::uint64_t frames = 0;                             ///< frames added
    /// Per frame of the first kTileFramesKept, per eye (0 left, 1 right): workpiece tiles drawn and skipped.
    std::vector<std::array<renderer::EyeTileCounts, 2>> tiles;
    /// Per eye: workpiece tiles drawn and skipped, summed over every frame.
    std::array<std::uint64_t, 2> tiles_drawn{}, tiles_skipped{};
    std::uint64_t tile_uploads = 0;  ///< tile meshes uploaded, summed over frames
    /// Workpiece tile triangles drawn per eye (FrameStats::tile_triangles), summed over frames.
    std::array<std::uint64_t, 2> tile_triangles{};
    /// The last frame's workpiece tile triangles and groups drawn, per eye.
    std::array<std::uint64_t, 2> tile_triangles_last{}, groups_drawn_last{};
    /// Per eye, summed over frames: groups drawn at a level (FrameStats::groups_drawn), and those drawn with their own
    /// triangles only (FrameStats::groups_own_only).
    std::array<std::uint64_t, 2> groups_drawn{}, groups_own_only{};
    /// Frames that drew a group over its pixel bound because nothing under it could stand in yet
    /// (FrameStats::groups_wanting_detail not empty).
    std::uint64_t frames_over_bound = 0;
    /// Per pass and eye, e.g. "opaque.left", "translucent.right", "overlay" (one pass for both eyes), or
    /// "frame" (CPU clock): that pass's time in every frame, ms (DurationHistogram::fine bins).
    std::map<std::string, DurationHistogram> pass_ms;
    std::string timing_note;         ///< the last frame's FrameStats::timing_note
    /// Adds one frame's statistics.
    void add(const renderer::FrameStats& stats);
};

/// Loads the scene and applies the options. Throws tridex::Error naming the option (--display, --stereo,
/// --frames, --seconds, --head, --monitor) or the file (scene, display config) at fault; offscreen runs need a
/// way to end: --frames, --seconds or a scene with a stroke (else "--frames/--seconds: ...").
RunSetup resolve_run(const RunOptions& options);

/// What a run did (SI units; histograms in ms).
struct RunResult {
    RunSetup setup;                              ///< what was run
    std::uint64_t frames = 0;                    ///< stereo frames rendered
    std::uint64_t presents = 0;                  ///< images shown (frame-sequential: 2 per frame)
    int last_eye = -1;                           ///< frame-sequential / quad: the eye shown last (0/1); else -1
    std::uint64_t window_resizes = 0;            ///< times the eye images followed a desk window to a new size
    std::uint64_t render_scale_changes = 0;      ///< times the budget's render scale resized a desk window's eyes
    std::pair<int, int> eye_resolution_last{0, 0};  ///< per-eye image size of the last frame, px
    /// The per-eye size the display gives at the end before the render scale (a desk window's framebuffer), px.
    std::pair<int, int> eye_resolution_window{0, 0};
    DurationHistogram frame_ms;                     ///< per frame: CPU wall time of draw + readback/present, ms
    DurationHistogram interval_ms;                  ///< between successive frame starts (the display period), ms
    DurationHistogram gpu_ms;                       ///< per frame: GPU time of the stereo render (timestamps), ms
    nlohmann::json present_timings;              ///< window: WindowPresenter::timings().to_json(); null offscreen
    std::uint64_t mesh_versions_drawn = 0;       ///< distinct MeshFrame versions the renderer drew
    /// How offscreen frames were paced: "early" (the refresh grid, and early for a sculpted change), "fixed" (the
    /// grid only), "none" (--no-pace), or "display" (a window's present waits for the display).
    std::string pacing;
    std::uint64_t frames_early = 0;              ///< frames started early for a sculpted change (pacing "early")
    std::uint64_t last_mesh_version = 0;         ///< the newest MeshFrame version drawn
    /// Per new mesh version drawn that carried a sculpted change: from its oldest changing tool sample being made
    /// (MeshFrame::oldest_sample_s) to the frame that first drew it being done: the later of the device's end of
    /// the frame (renderer::FrameStats::gpu_end_s) and the end of its submit and present on this thread; the latter
    /// alone without calibrated timestamps, ms.
    /// Samples made before the first frame, or (device time) before a scripted stroke's start, are not counted.
    DurationHistogram sample_to_drawn_ms = DurationHistogram::latency();
    /// The same frames, to the end of their submit and present on the frame thread (the device may still be
    /// drawing them), ms.
    DurationHistogram sample_to_submitted_ms = DurationHistogram::latency();
    std::uint64_t drawn_on_gpu_clock = 0;     ///< sample_to_drawn_ms entries that read the device's clock
    std::uint64_t drawn_on_submit_clock = 0;  ///< entries timed at the submit alone (no calibrated timestamps)
    /// The same frames' sculpt-side share: from the oldest changing tool sample to the mesh's publish
    /// (MeshFrame::published_s; queue wait, the Booleans or clay, re-contouring and publishing), ms.
    DurationHistogram sample_to_published_ms = DurationHistogram::latency();
    bool stroke_completed = false;               ///< the haptic loop played the whole stroke before the end
    double wall_s = 0.0;                         ///< whole run, s
    double render_s = 0.0;                       ///< from the first frame to the end of the last, s
    double first_frame_s = -1.0;                 ///< steady-clock time of the first frame's start, s (-1: none)
    double loaded_s = -1.0;                      ///< steady-clock time the workpiece was ready (scan-converted), s
    bool coarse_first = false;                   ///< the tiles were contoured after a first mesh of coarse levels
    /// Steady-clock time the first frame was done (the device finished it, else its present returned), s (-1: none).
    double first_frame_done_s = -1.0;
    std::size_t first_frame_triangles = 0;       ///< workpiece triangles the first frame drew, both eyes
    std::size_t first_frame_groups = 0;          ///< groups of tiles the first frame drew at a level, both eyes
    haptics::LoopStats loop{};                   ///< haptic loop counters
    SculptStats sculpt;                          ///< sculpt thread counters (mesh publishes included)
    double session_s = 0.0;                      ///< haptic + sculpt threads running, s
    double volume_before_m3 = 0.0;               ///< tri-dexel volume after scan conversion, m^3
    double volume_after_m3 = 0.0;                ///< tri-dexel volume at the end, m^3
    std::size_t triangles = 0;                   ///< of the last mesh drawn
    bool tiled = false;                          ///< the workpiece was drawn as tiles (false: the whole mesh)
    std::size_t tiles_last = 0;                  ///< tiles in the last mesh drawn (0 for the whole mesh)
    RenderLog render;                            ///< per-frame tiles drawn / skipped and per-pass GPU times
    nlohmann::json frame_budget;                 ///< FrameBudget::to_json() at the end (null: no frame)
    double force_m_per_newton = 0.0;             ///< force arrow scale, m per N (0 without items)
    std::string device;                          ///< Vulkan device name
    std::string eye_strategy;                    ///< the renderer's eye strategy note
    bool ao_sculpting = true;                    ///< the occlusion is drawn on sculpting frames (--ao-while-sculpting)
    std::string ao_sculpting_reason;             ///< why, e.g. "auto: off on a CPU implementation of Vulkan (...)"
    /// Frames drawn without the occlusion because they were drawn while sculpting (the occlusion being on).
    std::uint64_t frames_occlusion_held = 0;
    std::string present_mode;                    ///< window: "fifo" with vsync; offscreen: "offscreen"
    std::uint32_t validation_messages = 0;       ///< Vulkan validation messages (0 expected)
    std::string sculpt_path;                     ///< "gpu" or "cpu": where the swept Booleans ran
    std::string clay_path;                       ///< "gpu" or "cpu": where push, smooth and pull ran
    std::string sculpt_device;                   ///< Vulkan device that sculpted ("" on the CPU path)
    std::uint64_t spilled_intervals = 0;         ///< GPU spill-pool intervals at the end
    std::string contour_path;                    ///< "gpu" (GpuContourer, indirect draws) or "cpu" (tile meshes)
    std::string contour_reason;                  ///< why the contour ran on the CPU (empty on the GPU path)
    std::size_t contour_tiles_initial = 0;       ///< tiles contoured before the session
    double contour_initial_s = 0.0;              ///< wall time of that initial contouring, s
    /// GPU path: the GpuContourer's counters at the end (tiles on the GPU / host, pool grows, ...).
    compute::GpuContourStats gpu_contour{};
    /// GPU path: time the sculpt thread waited for a frame to finish before re-contouring, summed / longest, ms
    /// (included in SculptStats::contour_ms).
    double contour_lock_wait_ms_total = 0.0, contour_lock_wait_ms_max = 0.0;
    SessionSpec spec;                            ///< what decided the model (the scene's, device_origin_m set)
    nlohmann::json tool;                         ///< report.json `tool` (tool_json of the session's spec)
    nlohmann::json haptics;                      ///< report.json `haptics` (haptics_report_json, as the demo's)
    nlohmann::json mouse;                        ///< report.json `mouse` (RunMouse::report_json); null without
    nlohmann::json journal;                      ///< report.json `journal` (journal_report_json); null = no journal
    std::uint64_t requests_sent = 0;             ///< undo / redo / save requests handed to the sculpt thread
    std::uint64_t save_requests_sent = 0;        ///< of those, save requests (Ctrl+S)
    SaveStatus saves;                            ///< saves during the session (Ctrl+S), journal and checkpoint errors
    /// report.json `head`: {provider}; with DTrack DTrackHead::report_json() (frames tracked / stale, latency, ...).
    nlohmann::json head;
    nlohmann::json wand;  ///< null without a wand; else app/input/dtrack_wand.hpp wand_report_json
    /// report.json `controls`: the bindings, the menu's opens, flicks, cancels and choices per action, and every
    /// action done per source (key, button, menu, axis): HandControls::report_json.
    nlohmann::json controls;
    nlohmann::json study; ///< null without a study scene; else app/session/view/study_view.hpp StudyView::report_json
    /// The session companions' reports (SessionCompanion::report), each under its report_key(); e.g. `cluster`.
    nlohmann::json companions = nlohmann::json::object();
    /// null without scene objects; else app/session/view/elastic_view.hpp ElasticView::report_json (report.json `deformation`).
    nlohmann::json deformation;
    /// null without reference objects; else app/scene/reference_objects.hpp references_report_json (report.json
    /// `references`).
    nlohmann::json references;
    /// null with one workpiece; else run_report.hpp more_workpieces_report_json (report.json `more_workpieces`).
    nlohmann::json more_workpieces;
    std::size_t ticks = 0;                       ///< haptic tick records kept
    nlohmann::json period_us;                    ///< report.json `period_us` (tick_summary_json)
    nlohmann::json tick_compute_us;              ///< report.json `tick_compute_us` (tick_summary_json)
    nlohmann::json workpiece;                    ///< report.json `workpiece` (workpiece_report_json)
    nlohmann::json carved_mesh;                  ///< report.json `mesh` (carved_mesh_report_json); null if not written
    std::string sculpt_path_reason;              ///< why the Booleans ran on the CPU ("" on the GPU path)
    std::string sculpt_backend_reason;           ///< why this backend, either path (BackendChoice::reason)
    std::string clay_path_reason;                ///< why clay ran on the CPU on the GPU path ("" otherwise)
    std::array<std::size_t, 3> model_bytes{};    ///< model bytes per ray set on the sculpting path
    std::uint32_t sculpt_validation_messages = 0;  ///< Vulkan validation messages of the sculpting backend
    std::string stopped_by;                      ///< "SIGINT" / "SIGTERM" when a signal ended the run, else ""
    /// When the device went away during the run (its read failed): the device time of its last good tick, s.
    std::optional<double> device_lost_at_s;
    double scan_s = 0.0;                         ///< scan conversion (or model loading) wall time, s
    std::size_t tiles_total = 0;                 ///< tiles in the model's tile grid
    std::vector<std::string> notes;              ///< one line each: how the run ended, quad offscreen, tracker state
    std::vector<std::string> files;              ///< files written, full paths
};

/// Runs the session (app/session/run/run_pipeline.hpp, RunPipeline): GPU (and window) first, so that an output the surface cannot show (quad with
/// maxImageArrayLayers < 2) is refused before any work, then the workpiece, the haptic loop and sculpt thread
/// (SculptBackend), and the render loop on the calling thread (GLFW needs the main thread) at the display's
/// rate: per frame the newest mesh and LoopView, the head pose at session time, the navigated off-axis camera,
/// and the stereo sink (renderer/output/stereo_sink.hpp), which owns the output's policy (window: WindowSink, vsync,
/// anaglyph composed on the GPU; offscreen: OffscreenSink, the same passes, frame-sequential eyes sequenced by a
/// FrameSequencer). The loop ends on Esc / window close,
/// --frames, --seconds, or (offscreen without limits) the end of the stroke. Writes report.json (run_report.hpp)
/// into the output folder, and offscreen left.png, right.png (each eye's last frame; mono: the one view in both;
/// quad: the two layers) and output.png (what the display shows: compose(), anaglyph from the GPU pass;
/// frame-sequential: the last presented eye; quad: layer 0). Throws tridex::Error on bad options or scene, no usable Vulkan device or
/// display, an unsupported output, or a sculpt-thread failure.
RunResult run_stereo_session(const RunOptions& options);

}  // namespace tridex::app
