// app/run_pipeline.cpp - `tridex run`: the session's parts opened in order, the frame loop, the outputs.
#include "app/run_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "app/dtrack_head.hpp"
#include "app/dtrack_wand.hpp"
#include "app/elastic_view.hpp"
#include "app/report.hpp"
#include "app/run_head.hpp"
#include "app/run_input.hpp"
#include "app/run_mouse.hpp"
#include "app/run_report.hpp"
#include "app/run_sculpt.hpp"
#include "app/run_view.hpp"
#include "app/session_recording.hpp"
#include "app/session_report.hpp"
#include "app/stop_signal.hpp"
#include "app/study/study_recording.hpp"
#include "app/study/study_view.hpp"
#include "app/tile_view.hpp"
#include "app/workpiece_source.hpp"
#include "compute/mesh/mesh_export.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "app/device_lost.hpp"
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

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Force arrow scale: 2 cm per N, so the 3.3 N peak of the simulated Omni-class device is a 6.6 cm arrow.
constexpr double kForceMetresPerNewton = 0.02;
// How often the stylus's pick surface is read back from the GPU contour at most, s.
constexpr double kPickRefreshS = 0.1;

// The overlay's lines about saving: what the last Ctrl+S did, and loudly what is no longer being kept.
std::string saving_lines(const SaveStatus& s) {
    std::string out;
    auto line = [&out](const std::string& l) { out += (out.empty() ? "" : "\n") + l; };
    if (!s.journal_error.empty()) line("NOT BEING SAVED: journal stopped: " + s.journal_error);
    if (!s.checkpoint_error.empty()) line("checkpoints stopped: " + s.checkpoint_error);
    if (!s.message.empty()) line(s.ok ? s.message : "save failed: " + s.message);
    return out;
}

// An empty result of the run set up as `setup`.
RunResult result_for(RunSetup setup) {
    RunResult r;
    r.setup = std::move(setup);
    return r;
}

}  // namespace

// Every part of the session, declared in the order it is made, so that it is destroyed in the reverse order (the
// sculpting threads before the renderer, the sink, the window, the Context and GLFW).
struct RunPipeline::Parts {
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
    // 3. Sculpting threads and what draws beside them.
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
    std::vector<renderer::SceneObject> frame_objects;  // this frame's study and scene objects
    // 4. Frame loop state.
    bool swap = false, ao = true;
    RateMeter haptic_rate{1.0}, sculpt_rate{1.0};  // overlay: haptic ticks/s (loop time), sculpt steps/s (wall time)
    double prev_frame_ms = -1.0;
    TileView tiles;  // this frame's view of the published tiles and their levels of detail
    std::string ended = "the window was closed";
    std::size_t next_key = 0;     // scene.keys not yet pressed
    bool journal_warned = false;  // said once that the journal stopped
    Clock::time_point t_render{}, prev_start{};
    std::optional<Pose> last_good_head;   // the newest head pose whose eyes saw the screen
    std::uint64_t head_frames_held = 0;   // frames drawn from last_good_head instead of the head provider's pose

    explicit Parts(const RunOptions& options)
        : r(result_for(resolve_run(options))),
          su(r.setup),
          scene(su.scene),
          dc(scene.display),
          offscreen(su.display == DisplayKind::kOffscreen),
          eye_w(dc.width_px),
          eye_h(dc.height_px),
          mouse(renderer::MouseNavigation::for_screen(dc.screen, dc.width_px)) {
        open_display();
        open_inputs();
        open_backend();
    }

    void open_display();
    void open_inputs();
    void open_backend();
    void frame_loop();
    void take_input();
    bool end_of_run(std::uint64_t frame);
    renderer::SceneView frame_view(const MeshFrame& mesh, const haptics::LoopView& lv, const SaveStatus& saving);
    void draw(std::uint64_t frame, const MeshFrame& mesh, const haptics::LoopView& lv, renderer::SceneView& view,
              std::unique_lock<std::mutex>& contour_lock);
    void collect();
    void write_outputs();
};

// 1. GPU, window and stereo sink: refuses what the display cannot show before any other work. GLFW stays initialised
// from the first query (window_context_options) until `glfw_scope` ends, after the Context and the window: one X
// connection for every Vulkan instance that asked about it.
void RunPipeline::Parts::open_display() {
    const renderer::StereoOutput output = dc.stereo;
    if (!offscreen) glfw_scope.emplace();
    gpu::ContextOptions gopt;
    gopt.validation = su.validate;
    ctx.emplace(gpu::Context::create(offscreen ? gopt : renderer::window_context_options(gopt)));
    if (!offscreen) {
        renderer::WindowOptions wo;
        wo.title = "tridex run - " + std::string(renderer::to_string(output));
        const auto [w, h] = renderer::output_size(output, eye_w, eye_h);
        wo.width = w;
        wo.height = h;
        wo.fullscreen = su.display == DisplayKind::kFullscreen;
        wo.monitor_index = su.monitor_index;
        wo.monitor_name = su.monitor_name;
        window.emplace(renderer::Window::create(wo));
    }
    // The stereo output's policy (eyes, sequencing, composition, presents, files); destroyed before the Context.
    const renderer::SinkOptions sink_options{output, su.swap_eyes, dc.anaglyph, dc.refresh_hz};
    sink = offscreen ? std::unique_ptr<renderer::StereoSink>(std::make_unique<renderer::OffscreenSink>(*ctx, sink_options))
                     : renderer::WindowSink::create(*ctx, *window, sink_options);
    r.present_mode = sink->present_mode();
    for (const std::string& note : sink->notes()) r.notes.push_back(note);
    rend.emplace(renderer::OffscreenStereoRenderer::create(*ctx, eye_w, eye_h));
    r.device = ctx->device_name();
    r.eye_strategy = rend->strategy_note();
}

// 2. Head, scene navigation, input, the navigation wand.
void RunPipeline::Parts::open_inputs() {
    head = make_run_head(scene, !offscreen, &km, &tracker, &dtrack);
    mouse.pivot_m = scene.spec.workpiece_centre_m;
    input.emplace(km, nav, mouse);
    if (scene.wand_dtrack) {
        const DTrackWandSettings ws{scene.wand_port, scene.wand_flystick, scene.wand_bind,
                                    scene.display.tracker_to_wall, scene.wand_timeout_s};
        const bool share = dtrack && scene.dtrack_port == scene.wand_port;
        wand = std::make_unique<DTrackWand>(ws, share ? dtrack->receiver() : nullptr);
        WandNavigationSettings wn;
        wn.pivot_m = mouse.pivot_m;
        wand_nav.emplace(wn);
    }
}

// 3. The sculpting threads. One Context for both threads: with a GPU sculpt path the sculpt thread contours into
// buffers this thread draws (unless --cpu-contour).
void RunPipeline::Parts::open_backend() {
    SculptOptions sculpt_options{su.cpu, su.validate, su.cpu_contour, su.gpu_contour, su.journal};
    sculpt_options.checkpoint_s = su.checkpoint_s;
    sculpt_options.tile_lod = su.lod && su.tiles;
    sculpt_options.gpu_clay = su.gpu_clay;
    // Ctrl+S writes the --save file, or model.tdx in the output folder.
    sculpt_options.save_path = !su.save.empty() ? su.save : (fs::path(su.out) / "model.tdx").string();
    // A tracked tool reads the head's or the wand's receiver when it listens on the same port.
    std::shared_ptr<devices::DTrackReceiver> tool_dtrack;
    if (scene.spec.device_driver == "flystick" || scene.spec.device_driver == "tracked-body") {
        if (dtrack && scene.dtrack_port == scene.tracked_port)
            tool_dtrack = dtrack->receiver();
        else if (wand && scene.wand_port == scene.tracked_port)
            tool_dtrack = wand->receiver();
    }
    backend.emplace(scene, 1.0 / 60.0, su.tiles ? MeshForm::kTiles : MeshForm::kWhole, sculpt_options, &*ctx,
                    tool_dtrack);
    SessionRuntime& rt = backend->runtime();
    r.sculpt_path = rt.booleans().backend->path();
    r.sculpt_device = rt.booleans().backend->device();
    r.clay_path = rt.booleans().backend->clay_path();
    // Where clay would run only matters to a session that can use it: a clay op, or the mouse's keys 4, 5, 6.
    const bool clay_possible = compute::is_clay_op(parse_tool_op(scene.spec.op)) || scene.spec.device_driver == "mouse";
    if (clay_possible && !rt.booleans().backend->clay_reason().empty())
        r.notes.push_back("clay path cpu: " + rt.booleans().backend->clay_reason());
    if (!rt.booleans().reason.empty()) r.notes.push_back("sculpt path cpu: " + rt.booleans().reason);
    r.sculpt_path_reason = rt.booleans().reason;
    r.clay_path_reason = rt.booleans().backend->clay_reason();
    r.workpiece = workpiece_report_json(rt.workpiece());
    r.scan_s = rt.workpiece().scan_s;
    r.tiles_total = rt.workpiece().model.tiles.count();
    r.contour_path = rt.contour_path();
    r.contour_tiles_initial = rt.tiles_initial();
    r.contour_initial_s = rt.contour_s();
    r.contour_reason = rt.contour_reason();
    if (!r.contour_reason.empty()) r.notes.push_back("contour path cpu: " + r.contour_reason);
    gpu_contour = rt.gpu_contour();
    r.volume_before_m3 = rt.workpiece().volume_dexel_m3;
    if (devices::MouseDevice* md = backend->mouse()) {
        mouse_stylus.emplace(*md, rt, scene.spec.tool, backend->start_tool_m());
        input->use_stylus(&mouse_stylus->stylus());
    }
    // Offscreen with a scripted cursor and no limits: the run ends half a second (device time) after the cursor
    // script and the scripted keys.
    script_end_s = scene.cursor.empty()
                       ? 0.0
                       : std::max(scene.cursor.end_s(), scene.keys.empty() ? 0.0 : scene.keys.back().t_s) + 0.5;
    const double path_s = static_cast<double>(backend->stroke_ticks()) * scene.spec.period_s;  // a study's path
    safety_s = scene.has_stroke     ? 3.0 * scene.stroke.duration_s + 10.0
               : script_end_s > 0.0 ? 3.0 * script_end_s + 10.0
               : path_s > 0.0       ? 3.0 * path_s + 10.0
                                    : 0.0;
    if (scene.study.enabled) study_view.emplace(scene.study);
    if (!scene.objects.empty())
        elastic_view.emplace(scene.objects, rt.config().tool_points, rt.config().tool.radius_m);
}

// Window events, the scene's scripted keys (at their device times, through the same handler as a window's), the
// requests they made of the sculpt thread, and the toggles of the eyes and ambient occlusion.
void RunPipeline::Parts::take_input() {
    SessionRuntime& rt = backend->runtime();
    if (window) {
        window->poll_events();
        renderer::InputEvent e;
        while (window->input().pop(e)) input->handle(e);
    }
    for (const double t_dev = rt.latest_view().t_s; next_key < scene.keys.size() && scene.keys[next_key].t_s <= t_dev;
         ++next_key)
        for (const renderer::InputEvent& e : chord_events(scene.keys[next_key].chord, t_dev)) input->handle(e);
    for (const SculptRequest q : input->take_requests()) {
        if (rt.request(q)) {
            ++r.requests_sent;
            if (q == SculptRequest::kSave) ++r.save_requests_sent;
        } else {
            r.notes.push_back("a key's request was dropped: the sculpt thread's queue was full");
        }
    }
    if (window) {
        for (int k = input->take_swap_toggles(); k > 0; --k) swap = !swap;
        for (int k = input->take_occlusion_toggles(); k > 0; --k) ao = !ao;
        sink->set_swap_eyes(swap);
    }
}

// True when this frame is the last one; `ended` then says why.
bool RunPipeline::Parts::end_of_run(std::uint64_t frame) {
    const double t = seconds_since(t_render);
    const bool unlimited = su.frames == 0 && su.seconds == 0.0;
    if (su.frames > 0 && frame + 1 >= static_cast<std::uint64_t>(su.frames))
        ended = "--frames " + std::to_string(su.frames) + " rendered";
    else if (su.seconds > 0.0 && t >= su.seconds)
        ended = "--seconds " + format_number(su.seconds) + " passed";
    else if (offscreen && unlimited && backend->stroke_done())
        ended = "the stroke ended";
    else if (offscreen && unlimited && script_end_s > 0.0 && backend->runtime().latest_view().t_s >= script_end_s)
        ended = "the scripted cursor ended";
    else if (study_view && scene.study.end_at_end_cap && study_view->trial_done())
        ended = "the wand reached the end cap";
    else if (stop_requested())
        ended = std::string(stop_signal_name()) + " received";
    else if (backend->runtime().loop_stats().device_lost)
        ended = "the device was lost";
    else if (safety_s > 0.0 && offscreen && unlimited && t >= safety_s)
        ended = "the wall-time safety net (" + format_number(safety_s) + " s) stopped the run";
    else
        return false;
    return true;
}

// What this frame draws: the newest mesh (or GPU contour), the tool, the workspace, the study's and the scene's
// objects, and the overlay.
renderer::SceneView RunPipeline::Parts::frame_view(const MeshFrame& mesh, const haptics::LoopView& lv,
                                                   const SaveStatus& saving) {
    SessionRuntime& rt = backend->runtime();
    tile_view_of(mesh.tiles, mesh.groups, su.lod, tiles);
    // The tool the loop uses now (its size changes with [ and ] at the desk).
    const ToolShape tool_now = lv.tool.radius_m > 0.0 ? lv.tool : scene.spec.tool;
    renderer::SceneView view = scene_view_from(lv, mesh.tiled ? nullptr : &mesh.mesh, tool_now.radius_m,
                                               backend->start_tool_m(), backend->start_box_m());
    view.tool_shape = tool_now;
    view.tool_mesh = rt.tool_mesh();
    view.tool_orientation = lv.tool_world.orientation;
    if (!mesh.tiled) view.workpiece_materials = &mesh.materials;
    view.tiles = tiles.tiles;
    view.tile_groups = tiles.groups;
    view.lod = su.lod;
    if (gpu_contour) view.indirect_workpiece = &indirect;
    view.cull_tiles = su.cull;
    view.occlusion_strength = ao ? 1.0 : 0.0;
    if (study_view) {
        view.workpiece = nullptr;
        view.tiles = {};
        view.indirect_workpiece = nullptr;
        view.objects = study_view->frame(lv);
    }
    if (elastic_view) {
        const std::vector<renderer::SceneObject>& o = elastic_view->frame(lv);
        frame_objects.assign(view.objects.begin(), view.objects.end());
        frame_objects.insert(frame_objects.end(), o.begin(), o.end());
        view.objects = frame_objects;
    }
    if (su.items) {
        if (lv.tick > 0) haptic_rate.add(lv.t_s, lv.tick);
        sculpt_rate.add(std::chrono::duration<double>(Clock::now().time_since_epoch()).count(), mesh.sculpt_steps);
        // The proxy of a mesh tool's tip: a marker a tenth of the tool's size, not its bounding sphere.
        const double proxy_r = scene.spec.tool.kind == ToolKind::kMesh ? 0.1 * scene.spec.tool_size_m : tool_now.radius_m;
        std::string status = saving_lines(saving);
        if (mouse_stylus) status = mouse_stylus->stylus().status() + (status.empty() ? "" : "\n" + status);
        if (study_view) status = study_view->status() + (status.empty() ? "" : "\n" + status);
        add_run_items(view, lv, proxy_r, kForceMetresPerNewton,
                      RunOverlay{haptic_rate.rate_hz(), sculpt_rate.rate_hz(), prev_frame_ms, status});
    }
    return view;
}

// Moves the wand's navigation and the mouse stylus to this frame, then draws and presents it through the sink.
void RunPipeline::Parts::draw(std::uint64_t frame, const MeshFrame& mesh, const haptics::LoopView& lv,
                              renderer::SceneView& view, std::unique_lock<std::mutex>& contour_lock) {
    const double t = seconds_since(t_render);
    if (wand) {
        wand_nav->update(wand->sample(), t - wand_prev_t, nav);
        wand_prev_t = t;
    }
    // A head the eyes cannot be drawn from (a tracker glitch: at or behind the screen, or not finite) holds the last
    // good head pose for this frame, counted, instead of ending the session.
    const Pose head_pose = head->head_at(t);
    RunCamera cam = navigated_camera(dc.screen, head_pose, dc.eye_separation_m, nav);
    if (eyes_see_screen(cam)) {
        last_good_head = head_pose;
    } else {
        ++head_frames_held;
        cam = navigated_camera(dc.screen, last_good_head.value_or(scene.head_pose), dc.eye_separation_m, nav);
    }
    const auto t0 = Clock::now();
    if (mouse_stylus) {
        if (!window) mouse_stylus->apply_script(scene.cursor, lv.t_s);
        // The cursor is in one eye's image (side by side: either half; top-bottom: either half).
        double w_px = eye_w, h_px = eye_h;
        if (window) {
            const VkExtent2D fb = window->framebuffer_size();
            const auto [ow, oh] = renderer::output_size(dc.stereo, eye_w, eye_h);
            w_px = static_cast<double>(fb.width) * eye_w / ow;
            h_px = static_cast<double>(fb.height) * eye_h / oh;
        }
        if (gpu_contour) mouse_stylus->frame(cam.screen, cam.head.position, w_px, h_px, gpu_pick, lv, t0);
        else mouse_stylus->frame(cam.screen, cam.head.position, w_px, h_px, mesh, lv, t0);
    }
    if (frame > 0) r.interval_ms.add(ms_between(prev_start, t0));
    prev_start = t0;
    sink->draw(*rend, view, renderer::StereoCamera{cam.screen, cam.head, cam.eye_separation_m, cam.near_m, cam.far_m});
    if (contour_lock) contour_lock.unlock();
    r.presents += sink->present(*rend);
    r.last_eye = sink->last_eye();
    if (mouse_stylus) mouse_stylus->shown(lv, Clock::now());
    prev_frame_ms = ms_between(t0, Clock::now());
    r.frame_ms.add(prev_frame_ms);
    r.gpu_ms.add(rend->last_gpu_ms());
    for (const renderer::FrameStats& fs : rend->take_finished_frames()) r.render.add(fs);
    r.frames = frame + 1;
}

// 4. The render loop, on this thread, at the display's rate (offscreen: paced unless --no-pace).
void RunPipeline::Parts::frame_loop() {
    SessionRuntime& rt = backend->runtime();
    const double frame_period_s = sink->presents_per_frame() / dc.refresh_hz;
    swap = su.swap_eyes;
    ao = su.ao;
    r.force_m_per_newton = su.items ? kForceMetresPerNewton : 0.0;
    t_render = Clock::now();
    if (dtrack) dtrack->set_session_origin(t_render);
    for (std::uint64_t frame = 0;; ++frame) {
        take_input();
        const SaveStatus saving = rt.save_status();
        if (!saving.journal_error.empty() && !journal_warned) {
            journal_warned = true;
            std::fprintf(stderr, "tridex: this session is no longer being saved: journal: %s; the model stays in memory "
                                 "(Ctrl+S or --save writes it elsewhere)\n", saving.journal_error.c_str());
        }
        if (window && (window->should_close() || input->close_requested())) break;
        const bool last = end_of_run(frame);
        const MeshFrame& mesh = rt.latest_mesh();
        if (mesh.version != r.last_mesh_version) {
            ++r.mesh_versions_drawn;
            r.last_mesh_version = mesh.version;
        }
        // The mouse stylus picks on the CPU: with the GPU contour (no CPU meshes published) the contour is read back
        // when it changed, at most every kPickRefreshS, and not while the left button holds the surface anyway.
        if (mouse_stylus && gpu_contour && !mouse_stylus->stylus().left()) {
            const std::uint64_t updates = gpu_contour->updates();
            if (!gpu_pick.whole || (updates != gpu_pick_updates && seconds_since(gpu_pick_at) >= kPickRefreshS)) {
                gpu_pick.whole = std::make_shared<const TriMesh>(gpu_contour->download());
                gpu_pick_updates = updates;
                gpu_pick_at = Clock::now();
                ++gpu_pick_reads;
            }
        }
        // GPU contour: the buffers stay locked (the sculpt thread cannot re-contour) until the frame is done.
        std::unique_lock<std::mutex> contour_lock;
        if (gpu_contour) contour_lock = gpu_contour->lock_frame(indirect);
        r.triangles = gpu_contour ? indirect.triangles : mesh.triangles;
        r.tiled = mesh.tiled;
        r.tiles_last = gpu_contour ? indirect.tiles.size() : mesh.tiles.size();
        const haptics::LoopView& lv = rt.latest_view();
        renderer::SceneView view = frame_view(mesh, lv, saving);
        draw(frame, mesh, lv, view, contour_lock);
        if (last) break;
        if (offscreen && su.pace)
            std::this_thread::sleep_until(t_render + std::chrono::duration_cast<Clock::duration>(
                                                         std::chrono::duration<double>((frame + 1) * frame_period_s)));
    }
    rend->finish();  // the frames still in flight
    for (const renderer::FrameStats& fs : rend->take_finished_frames()) r.render.add(fs);
}

// After the frames: stop the threads and collect every counter the report needs.
void RunPipeline::Parts::collect() {
    SessionRuntime& rt = backend->runtime();
    r.render_s = seconds_since(t_render);
    r.stroke_completed = scene.has_stroke && backend->stroke_done() && rt.loop_stats().ticks >= backend->stroke_ticks();
    rt.stop();
    r.loop = rt.loop_stats();
    if (r.loop.device_lost && !stop_requested()) {
        r.device_lost_at_s = rt.records().empty() ? 0.0 : rt.records().back().t_s;
        ended = "the device was lost at " + format_number(*r.device_lost_at_s) + " s";
    }
    r.notes.insert(r.notes.begin(), "ended: " + ended);
    if (tracker) r.notes.push_back("tracker: " + tracker->status().note);
    r.head = nlohmann::json{{"provider", to_string(scene.head)}};
    if (dtrack) {
        r.head = dtrack->report_json();
        r.notes.push_back("head: " + dtrack->note());
    }
    r.head["frames_held"] = head_frames_held;
    if (head_frames_held > 0)
        r.notes.push_back("head: " + std::to_string(head_frames_held) +
                          " frames held the last good head pose (the head was at or behind the screen, or not finite)");
    if (wand) {
        r.wand = wand_report_json(*wand, *wand_nav, nav);
        r.notes.push_back("wand: " + wand->note());
    }
    r.spilled_intervals = rt.booleans().backend->spilled_intervals();
    r.model_bytes = rt.booleans().backend->model_bytes();
    r.sculpt_validation_messages = rt.booleans().backend->validation_messages();
    if (stop_requested()) r.stopped_by = stop_signal_name();
    if (gpu_contour) {
        r.gpu_contour = gpu_contour->stats();
        r.contour_lock_wait_ms_total = gpu_contour->lock_wait_ms_total();
        r.contour_lock_wait_ms_max = gpu_contour->lock_wait_ms_max();
    }
    r.sculpt = rt.sculpt_stats();
    r.journal = journal_report_json(rt.journal_stats(), r.sculpt, rt.session_s());
    r.saves = rt.save_status();
    if (r.saves.failures > 0) r.notes.push_back("a save during the session failed: " + r.saves.message);
    if (!r.saves.checkpoint_error.empty()) r.notes.push_back("checkpoints stopped: " + r.saves.checkpoint_error);
    if (const compute::JournalStats* j = rt.journal_stats(); j && !j->error.empty())
        r.notes.push_back("journal stopped: " + j->error);
    r.session_s = rt.session_s();
    if (mouse_stylus) {
        r.mouse = mouse_stylus->report_json();
        r.mouse["pick_surface"] = gpu_contour ? "gpu contour, read back" : "cpu contour";
        r.mouse["pick_reads"] = gpu_pick_reads;
    }
    if (study_view) r.study = study_view->report_json();
    if (elastic_view) r.deformation = elastic_view->report_json();
    r.volume_after_m3 = compute::dexel_volume_m3(rt.workpiece().model);
    r.present_timings = sink->present_timings();
    r.spec = rt.spec();
    r.tool = tool_json(r.spec);
    r.ticks = rt.records().size();
    const std::array<nlohmann::json, 2> tick_summaries = tick_summary_json(rt.records());
    r.period_us = tick_summaries[0];
    r.tick_compute_us = tick_summaries[1];
    r.haptics = haptics_report_json(rt.spec(), r.loop, rt.records(), r.session_s, rt.profile().name,
                                    rt.profile().max_force_n, rt.device_status());
    r.haptics["stiffness_n_per_m"] = rt.config().contact.stiffness_n_per_m;
    r.haptics["device_link"] = device_link_json(rt.device_link());
    r.haptics["link"] = link_json(rt.device_link());
}

// 5. Outputs. Every output is tried, each failure noted; one that fails (a full disk) costs none of the others, and
// the report says which failed. The first failure is then the command's error.
void RunPipeline::Parts::write_outputs() {
    SessionRuntime& rt = backend->runtime();
    fs::create_directories(su.out);
    const fs::path out(su.out);
    std::vector<std::string> failed;
    auto attempt = [&](const char* what, const auto& write) {
        try {
            write();
        } catch (const Error& e) {
            failed.push_back(e.what());
            r.notes.push_back(std::string(what) + " failed: " + e.what());
        }
    };
    attempt("images", [&] {
        for (std::string& file : sink->finish(*rend, out.string())) r.files.push_back(std::move(file));
    });
    // The carved model as a closed mesh (the CPU contour of the final model, as demo and replay write it), and
    // the recording.
    attempt("sculpted.ply", [&] {
        const SessionRuntime::FinalMesh carved = rt.final_mesh();
        r.carved_mesh = carved_mesh_report_json(carved.mesh);
        compute::write_ply((out / "sculpted.ply").string(), carved.mesh, carved.materials);
        r.files.push_back((out / "sculpted.ply").string());
    });
    if (!su.record.empty()) {
        if (rt.records().size() < rt.loop_stats().ticks)
            r.notes.push_back("record: only the first " + std::to_string(rt.records().size()) + " of " +
                              std::to_string(rt.loop_stats().ticks) + " ticks were kept; a replay carves less");
        attempt("record", [&] {
            std::string notes;  // a protocol's test trial: tagged for `tridex study analyze`
            if (const RunStudy& st = scene.study; st.enabled && !st.participant.empty())
                notes = study::tag_notes(spec_to_json(rt.spec()),
                                         study::StudyTag{st.participant, st.group, st.trial, st.model,
                                                         st.scene.tube.name, study::tube_id(st.scene.tube)});
            write_session_recording(su.record, rt.spec(), rt.records(), notes, r.sculpt.marks);
            r.files.push_back(su.record);
        });
    }
    if (!su.save.empty()) {
        attempt("save", [&] {
            save_session_model(su.save, rt.workpiece(), rt.spec());
            r.files.push_back(su.save);
        });
    }
    // The render context's messages plus the sculpting device's (its own context on the GPU path).
    r.validation_messages = ctx->validation_messages() + rt.booleans().backend->validation_messages();
    r.wall_s = seconds_since(t_start);
    r.files.push_back((out / "report.json").string());
    write_run_report(r.files.back(), r);
    if (!failed.empty())
        throw Error(failed.front() +
                    (failed.size() > 1 ? " (and " + std::to_string(failed.size() - 1) + " more)" : std::string()) +
                    "; the other outputs and report.json were written to " + su.out);
}

RunPipeline::RunPipeline(const RunOptions& options) : p_(std::make_unique<Parts>(options)) {}

RunPipeline::~RunPipeline() = default;

RunResult RunPipeline::run() {
    Parts& p = *p_;
    p.backend->runtime().start();
    try {
        p.frame_loop();
    } catch (...) {
        try {
            p.backend->runtime().stop();
        } catch (...) {  // the render failure is the one to report
        }
        throw;
    }
    p.collect();
    p.write_outputs();
    if (p.r.device_lost_at_s) {
        const RunSetup& su = p.r.setup;
        std::string kept = su.out + " (images, sculpted.ply, report.json)";
        if (!su.journal.empty()) kept += ", the journal " + su.journal;
        if (!su.record.empty()) kept += ", the recording " + su.record;
        if (!su.save.empty()) kept += ", the model " + su.save;
        throw DeviceLostError("device '" + su.scene.spec.device_driver + "': the " +
                              p.backend->runtime().profile().name + " was lost " +
                              format_number(*p.r.device_lost_at_s) +
                              " s into the session; the session ended there and kept its work: " + kept);
    }
    return p.r;
}

RunResult run_stereo_session(const RunOptions& options) { return RunPipeline(options).run(); }

}  // namespace tridex::app
