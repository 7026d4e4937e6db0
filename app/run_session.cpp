// app/run_session.cpp - `tridex run`: GPU and display set-up, the render loop, the outputs.
#include "app/run_session.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "app/dtrack_head.hpp"
#include "app/dtrack_wand.hpp"
#include "app/output_dir.hpp"
#include "app/run_input.hpp"
#include "app/run_mouse.hpp"
#include "app/run_report.hpp"
#include "app/run_sculpt.hpp"
#include "app/run_view.hpp"
#include "app/report.hpp"
#include "app/session_report.hpp"
#include "app/session_recording.hpp"
#include "app/study/study_recording.hpp"
#include "app/study/study_view.hpp"
#include "app/elastic_view.hpp"
#include "app/workpiece_source.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "app/tile_view.hpp"
#include "app/stop_signal.hpp"
#include "compute/mesh/mesh_export.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "devices/net/enet_link.hpp"
#include "devices/net/link_wire.hpp"
#include "gpu/context.hpp"
#include "renderer/camera/head_pose.hpp"
#include "renderer/output/offscreen_sink.hpp"
#include "renderer/camera/scene_navigation.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "renderer/output/stereo_sink.hpp"
#include "renderer/window/window_glfw.hpp"
#include "renderer/window/window_sink.hpp"

namespace tridex::app {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using renderer::StereoOutput;

double ms_between(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }
// Force arrow scale: 2 cm per N, so the 3.3 N peak of the simulated Omni-class device is a 6.6 cm arrow.
constexpr double kForceMetresPerNewton = 0.02;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The overlay's lines about saving: what the last Ctrl+S did, and loudly what is no longer being kept.
std::string saving_lines(const SaveStatus& s) {
    std::string out;
    auto line = [&out](const std::string& l) { out += (out.empty() ? "" : "\n") + l; };
    if (!s.journal_error.empty()) line("NOT BEING SAVED: journal stopped: " + s.journal_error);
    if (!s.checkpoint_error.empty()) line("checkpoints stopped: " + s.checkpoint_error);
    if (!s.message.empty()) line(s.ok ? s.message : "save failed: " + s.message);
    return out;
}

// The head provider of the run: in a window a fixed head becomes a keyboard-and-mouse head (same home pose).
std::unique_ptr<renderer::HeadPoseProvider> make_head(const RunScene& s, bool interactive,
                                                     renderer::KeyboardMouseHead** km, renderer::TrackerHead** tracker,
                                                     DTrackHead** dtrack) {
    *km = nullptr;
    *tracker = nullptr;
    *dtrack = nullptr;
    switch (s.head) {
        case HeadMode::kDTrack: {
            DTrackHeadSettings ds;
            ds.port = s.dtrack_port;
            ds.body = s.dtrack_body;
            ds.bind_address = s.dtrack_bind;
            ds.tracker_to_wall = s.display.tracker_to_wall;
            ds.head_to_eyes = s.display.head_to_eyes;
            ds.fallback = s.head_pose;
            ds.timeout_s = s.tracker_timeout_s;
            auto d = std::make_unique<DTrackHead>(ds);
            *dtrack = d.get();
            return d;
        }
        case HeadMode::kScripted:
            return std::make_unique<renderer::ScriptedHead>(s.head_waypoints, s.head_loop);
        case HeadMode::kTracker: {
            auto t = std::make_unique<renderer::TrackerHead>(s.head_pose, s.tracker_timeout_s);
            *tracker = t.get();
            return t;
        }
        case HeadMode::kFixed:
            break;
    }
    if (interactive) {
        auto k = std::make_unique<renderer::KeyboardMouseHead>(s.head_pose);
        *km = k.get();
        return k;
    }
    return std::make_unique<renderer::FixedHead>(s.head_pose);
}

}  // namespace

RunSetup resolve_run(const RunOptions& o) {
    RunSetup s;
    s.display = parse_display_kind(o.display);
    if (o.frames < 0) throw Error("--frames: must be >= 0, got " + std::to_string(o.frames));
    if (!std::isfinite(o.seconds) || o.seconds < 0.0 || o.seconds > 86400.0)
        throw Error("--seconds: must be between 0 and 86400, got " + format_number(o.seconds));
    s.frames = o.frames;
    s.seconds = o.seconds;
    s.out = o.out;
    prepare_output_dir(s.out, "--out");
    s.validate = o.validate;
    s.cpu = o.cpu;
    s.cpu_contour = o.cpu_contour;
    s.gpu_contour = o.gpu_contour;
    s.gpu_clay = o.gpu_clay;
    if (s.cpu_contour && s.gpu_contour) throw Error("--cpu-contour, --gpu-contour: choose one");
    s.pace = o.pace;
    s.items = o.items;
    s.tiles = o.tiles;
    s.cull = o.cull;
    if (o.lod != "on" && o.lod != "off") throw Error("--lod: must be on or off, got '" + o.lod + "'");
    s.lod = o.lod == "on";
    if (!o.ao.empty() && o.ao != "on" && o.ao != "off") throw Error("--ao: must be on or off, got '" + o.ao + "'");
    s.record = o.record;
    if (!s.record.empty()) check_output_file(s.record, "--record");
    s.save = o.save;
    if (!s.save.empty()) check_output_file(s.save, "--save");
    s.journal = o.no_journal ? "" : o.journal.empty() ? (fs::path(s.out) / "session.tdj").string() : o.journal;
    if (!(o.checkpoint_s >= 0.0 && o.checkpoint_s <= 86400.0))
        throw Error("--checkpoint-s: must be between 0 (none) and 86400, got " + format_number(o.checkpoint_s));
    s.checkpoint_s = o.checkpoint_s;
    if (!o.journal.empty() && o.no_journal) throw Error("--journal, --no-journal: choose one");
    if (!o.journal.empty()) check_output_file(o.journal, "--journal");
    s.scene = load_run_scene(o.scene);
    check_distinct_files({{"--out's sculpted.ply", (fs::path(s.out) / "sculpted.ply").string()},
                          {"--out's report.json", (fs::path(s.out) / "report.json").string()},
                          {s.save.empty() ? "the Ctrl+S model (--out's model.tdx)" : "--save",
                           s.save.empty() ? (fs::path(s.out) / "model.tdx").string() : s.save},
                          {"--record", s.record},
                          {o.journal.empty() ? "the journal (--out's session.tdj)" : "--journal", s.journal}},
                         {{"the scene", o.scene},
                          {"the scene's workpiece model", s.scene.spec.model_path},
                          {"the scene's workpiece mesh", s.scene.spec.model_path.empty() ? s.scene.spec.mesh_path : ""}});
    if (o.history_mib != 0.0) {
        if (!(o.history_mib >= 1.0 && o.history_mib <= 1048576.0))
            throw Error("--history-mib: must be between 1 and 1048576, got " + format_number(o.history_mib));
        s.scene.spec.history_budget_bytes = static_cast<std::size_t>(o.history_mib * 1048576.0);
    }
    if (!o.falcon_firmware.empty()) s.scene.spec.device_firmware = o.falcon_firmware;
    if (!o.display_config.empty()) s.scene.display = renderer::load_display_config(o.display_config);
    if (!o.stereo.empty()) {
        try {
            s.scene.display.stereo = renderer::parse_stereo_output(o.stereo);
        } catch (const Error& e) {
            throw Error(std::string("--stereo: ") + e.what());
        }
    }
    if (o.head.rfind("dtrack:", 0) == 0) {
        s.scene.head = HeadMode::kDTrack;
        parse_dtrack_head_option(o.head, s.scene.dtrack_port, s.scene.dtrack_body);
    } else if (!o.head.empty()) {
        s.scene.head = parse_head_mode(o.head, "--head");
        if (s.scene.head == HeadMode::kScripted && s.scene.head_waypoints.empty())
            throw Error("--head scripted: the scene " + s.scene.source + " has no head.waypoints");
    }
    if (o.wand == "none") {
        s.scene.wand_dtrack = false;
    } else if (!o.wand.empty()) {
        s.scene.wand_dtrack = true;
        parse_dtrack_wand_option(o.wand, s.scene.wand_port, s.scene.wand_flystick);
    }
    s.swap_eyes = o.swap_eyes || s.scene.display.swap_eyes;
    s.ao = o.ao.empty() ? s.scene.display.ambient_occlusion : o.ao == "on";
    if (!o.monitor.empty()) {
        const bool digits = std::all_of(o.monitor.begin(), o.monitor.end(), [](unsigned char c) { return std::isdigit(c); });
        if (digits && o.monitor.size() < 4)
            s.monitor_index = std::stoi(o.monitor);
        else
            s.monitor_name = o.monitor;
    }
    std::string tracked;
    if (o.device.rfind("net:", 0) == 0) {
        std::string host;
        std::uint16_t port = 0;
        devices::net::split_host_port(o.device.substr(4), "--device " + o.device, host, port);
        s.scene.spec.device_driver = "net";
        s.scene.spec.device_serial = o.device.substr(4);
    } else if (!o.device.empty() && parse_tracked_tool_option(o.device, tracked, s.scene.tracked_port, s.scene.tracked_id)) {
        s.scene.spec.device_driver = tracked;
        s.scene.spec.device = "tracked";
    } else if (!o.device.empty()) {
        if (o.device != "mouse" && o.device != "simulated" && o.device != "spacemouse")
            throw Error("--device: '" + o.device +
                        "' is not one of simulated, mouse, spacemouse, flystick[:PORT[:ID]], tracked-body[:PORT[:ID]], "
                        "net:HOST:PORT");
        s.scene.spec.device_driver = o.device;
    }
    if (!o.haptic_rendering.empty()) {
        if (s.scene.spec.device_driver != "net")
            throw Error("--haptic-rendering " + o.haptic_rendering + ": only with --device net:HOST:PORT (a device server)");
        (void)devices::net::rendering_mode_from(o.haptic_rendering);  // "... is not distributed or local"
        s.scene.spec.haptic_rendering = o.haptic_rendering;
    }
    const std::string& driver = s.scene.spec.device_driver;
    if (driver == "net" && s.scene.spec.haptic_rendering == "local" && !s.scene.objects.empty())
        throw Error(s.scene.source + ": field 'objects': scene objects are felt by the session's own contact loop; a "
                    "device server renders only the workpiece in local haptic rendering: use distributed rendering");
    if (driver == "mouse" || driver == "spacemouse" || driver == "flystick" || driver == "tracked-body")
        s.scene.has_stroke = false;  // the person is the hand
    if (driver == "flystick" && s.scene.wand_dtrack && s.scene.wand_port == s.scene.tracked_port &&
        s.scene.wand_flystick == s.scene.tracked_id)
        throw Error("--device flystick: Flystick " + std::to_string(s.scene.tracked_id) +
                    " navigates the scene already (--wand); give the tool another Flystick");
    const bool scripted_study = s.scene.study.enabled && scripted_hand_driver(driver);  // the scripted participant's path
    if (s.display == DisplayKind::kOffscreen && s.frames == 0 && s.seconds == 0.0 && !s.scene.has_stroke &&
        s.scene.cursor.empty() && !scripted_study)
        throw Error("--frames/--seconds: an offscreen run of a scene without a stroke or a scripted cursor needs "
                    "--frames N or --seconds S");
    return s;
}

RunResult run_stereo_session(const RunOptions& options) {
    const auto t_start = Clock::now();
    RunResult r;
    r.setup = resolve_run(options);
    const RunSetup& su = r.setup;
    const RunScene& scene = su.scene;
    const renderer::DisplayConfig& dc = scene.display;
    const StereoOutput output = dc.stereo;
    const bool offscreen = su.display == DisplayKind::kOffscreen;
    const int eye_w = dc.width_px, eye_h = dc.height_px;

    // 1. GPU, window and stereo sink: refuses what the display cannot show before any other work.
    // GLFW stays initialised from the first query (window_context_options) until `glfw_scope` ends, after
    // the Context and the window: one X connection for every Vulkan instance that asked about it.
    std::optional<renderer::WindowSystemScope> glfw_scope;
    if (!offscreen) glfw_scope.emplace();
    gpu::ContextOptions gopt;
    gopt.validation = su.validate;
    gpu::Context ctx = gpu::Context::create(offscreen ? gopt : renderer::window_context_options(gopt));
    std::optional<renderer::Window> window;  // none offscreen (the images are read back on the last frame)
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
    const std::unique_ptr<renderer::StereoSink> sink =
        offscreen ? std::unique_ptr<renderer::StereoSink>(std::make_unique<renderer::OffscreenSink>(ctx, sink_options))
                  : renderer::WindowSink::create(ctx, *window, sink_options);
    r.present_mode = sink->present_mode();
    for (const std::string& note : sink->notes()) r.notes.push_back(note);
    renderer::OffscreenStereoRenderer rend = renderer::OffscreenStereoRenderer::create(ctx, eye_w, eye_h);
    r.device = ctx.device_name();
    r.eye_strategy = rend.strategy_note();

    // 2. Head, scene navigation, input.
    renderer::KeyboardMouseHead* km = nullptr;
    renderer::TrackerHead* tracker = nullptr;
    DTrackHead* dtrack = nullptr;
    const std::unique_ptr<renderer::HeadPoseProvider> head = make_head(scene, !offscreen, &km, &tracker, &dtrack);
    renderer::SceneNavigation nav;
    renderer::MouseNavigation mouse = renderer::MouseNavigation::for_screen(dc.screen, eye_w);
    mouse.pivot_m = scene.spec.workpiece_centre_m;
    RunInput input(km, nav, mouse);
    std::unique_ptr<DTrackWand> wand;
    std::optional<WandNavigator> wand_nav;
    if (scene.wand_dtrack) {
        const DTrackWandSettings ws{scene.wand_port, scene.wand_flystick, scene.wand_bind,
                                    scene.display.tracker_to_wall, scene.wand_timeout_s};
        const bool share = dtrack && scene.dtrack_port == scene.wand_port;
        wand = std::make_unique<DTrackWand>(ws, share ? dtrack->receiver() : nullptr);
        WandNavigationSettings wn;
        wn.pivot_m = mouse.pivot_m;
        wand_nav.emplace(wn);
    }
    double wand_prev_t = 0.0;

    // 3. The sculpting threads.
    // One Context for both threads: with a GPU sculpt path the sculpt thread contours into buffers this
    // thread draws (unless --cpu-contour).
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
    SculptBackend backend(scene, 1.0 / 60.0, su.tiles ? MeshForm::kTiles : MeshForm::kWhole, sculpt_options, &ctx,
                          tool_dtrack);
    r.sculpt_path = backend.runtime().booleans().backend->path();
    r.sculpt_device = backend.runtime().booleans().backend->device();
    r.clay_path = backend.runtime().booleans().backend->clay_path();
    // Where clay would run only matters to a session that can use it: a clay op, or the mouse's keys 4, 5, 6.
    const bool clay_possible = compute::is_clay_op(parse_tool_op(scene.spec.op)) || scene.spec.device_driver == "mouse";
    if (clay_possible && !backend.runtime().booleans().backend->clay_reason().empty())
        r.notes.push_back("clay path cpu: " + backend.runtime().booleans().backend->clay_reason());
    if (!backend.runtime().booleans().reason.empty()) r.notes.push_back("sculpt path cpu: " + backend.runtime().booleans().reason);
    r.sculpt_path_reason = backend.runtime().booleans().reason;
    r.clay_path_reason = backend.runtime().booleans().backend->clay_reason();
    r.workpiece = workpiece_report_json(backend.runtime().workpiece());
    r.scan_s = backend.runtime().workpiece().scan_s;
    r.tiles_total = backend.runtime().workpiece().model.tiles.count();
    r.contour_path = backend.runtime().contour_path();
    r.contour_tiles_initial = backend.runtime().tiles_initial();
    r.contour_initial_s = backend.runtime().contour_s();
    r.contour_reason = backend.runtime().contour_reason();
    if (!r.contour_reason.empty()) r.notes.push_back("contour path cpu: " + r.contour_reason);
    GpuContourShare* const gpu_contour = backend.runtime().gpu_contour();
    renderer::IndirectWorkpiece indirect;  // this frame's view of the GPU contour
    r.volume_before_m3 = backend.runtime().workpiece().volume_dexel_m3;
    // The mouse stylus (--device mouse): the cursor drives the device; navigation moves to Alt.
    std::optional<RunMouse> mouse_stylus;
    if (devices::MouseDevice* md = backend.mouse()) {
        mouse_stylus.emplace(*md, backend.runtime(), scene.spec.tool, backend.start_tool_m());
        input.use_stylus(&mouse_stylus->stylus());
    }
    PickSurface gpu_pick;                 // the GPU contour read back for the stylus's picks
    std::uint64_t gpu_pick_updates = 0;   // gpu_contour->updates() when it was read
    Clock::time_point gpu_pick_at{};
    constexpr double kPickRefreshS = 0.1;
    std::uint64_t gpu_pick_reads = 0;
    // Offscreen with a scripted cursor and no limits: the run ends half a second (device time) after the cursor
    // script and the scripted keys.
    const double script_end_s =
        scene.cursor.empty() ? 0.0
                             : std::max(scene.cursor.end_s(), scene.keys.empty() ? 0.0 : scene.keys.back().t_s) + 0.5;
    const double path_s = static_cast<double>(backend.stroke_ticks()) * scene.spec.period_s;  // a study's scripted path
    const double safety_s = scene.has_stroke ? 3.0 * scene.stroke.duration_s + 10.0
                            : script_end_s > 0.0 ? 3.0 * script_end_s + 10.0
                            : path_s > 0.0 ? 3.0 * path_s + 10.0 : 0.0;
    // A study scene: its objects are drawn instead of the workpiece (the felt walls stay invisible).
    std::optional<study::StudyView> study_view;
    if (scene.study.enabled) study_view.emplace(scene.study);
    // Scene objects: drawn beside the workpiece, the elastic ones dented where the loop feels them.
    std::optional<ElasticView> elastic_view;
    std::vector<renderer::SceneObject> frame_objects;  // this frame's study and scene objects
    if (!scene.objects.empty())
        elastic_view.emplace(scene.objects, backend.runtime().config().tool_points,
                             backend.runtime().config().tool.radius_m);
    backend.runtime().start();

    // 4. The render loop, on this thread.
    const double frame_period_s = sink->presents_per_frame() / dc.refresh_hz;
    bool swap = su.swap_eyes;
    bool ao = su.ao;
    // Overlay numbers: haptic ticks/s over the last second of loop time, sculpt steps/s over the last second
    // of wall time (from the published frames), and the previous frame's wall time.
    RateMeter haptic_rate(1.0), sculpt_rate(1.0);
    double prev_frame_ms = -1.0;
    TileView tiles;  // this frame's view of the published tiles and their levels of detail
    r.force_m_per_newton = su.items ? kForceMetresPerNewton : 0.0;
    std::string ended = "the window was closed";
    std::size_t next_key = 0;     // scene.keys not yet pressed
    bool journal_warned = false;  // said once that the journal stopped
    const auto t_render = Clock::now();
    if (dtrack) dtrack->set_session_origin(t_render);
    Clock::time_point prev_start{};
    try {
        for (std::uint64_t frame = 0;; ++frame) {
            if (window) {
                window->poll_events();
                renderer::InputEvent e;
                while (window->input().pop(e)) input.handle(e);
            }
            // The scene's scripted keys, at their device times, through the same handler as a window's.
            for (const double t_dev = backend.runtime().latest_view().t_s;
                 next_key < scene.keys.size() && scene.keys[next_key].t_s <= t_dev; ++next_key)
                for (const renderer::InputEvent& e : chord_events(scene.keys[next_key].chord, t_dev)) input.handle(e);
            for (const SculptRequest q : input.take_requests()) {
                if (backend.runtime().request(q)) {
                    ++r.requests_sent;
                    if (q == SculptRequest::kSave) ++r.save_requests_sent;
                } else r.notes.push_back("a key's request was dropped: the sculpt thread's queue was full");
            }
            const SaveStatus saving = backend.runtime().save_status();
            if (!saving.journal_error.empty() && !journal_warned) {
                journal_warned = true;
                std::fprintf(stderr, "tridex: this session is no longer being saved: journal: %s; the model stays in memory "
                                     "(Ctrl+S or --save writes it elsewhere)\n", saving.journal_error.c_str());
            }
            if (window) {
                for (int k = input.take_swap_toggles(); k > 0; --k) swap = !swap;
                for (int k = input.take_occlusion_toggles(); k > 0; --k) ao = !ao;
                sink->set_swap_eyes(swap);
                if (window->should_close() || input.close_requested()) break;
            }
            const double t = seconds_since(t_render);
            bool last = false;
            if (su.frames > 0 && frame + 1 >= static_cast<std::uint64_t>(su.frames)) {
                last = true;
                ended = "--frames " + std::to_string(su.frames) + " rendered";
            } else if (su.seconds > 0.0 && t >= su.seconds) {
                last = true;
                ended = "--seconds " + format_number(su.seconds) + " passed";
            } else if (offscreen && su.frames == 0 && su.seconds == 0.0 && backend.stroke_done()) {
                last = true;
                ended = "the stroke ended";
            } else if (offscreen && su.frames == 0 && su.seconds == 0.0 && script_end_s > 0.0 &&
                       backend.runtime().latest_view().t_s >= script_end_s) {
                last = true;
                ended = "the scripted cursor ended";
            } else if (study_view && scene.study.end_at_end_cap && study_view->trial_done()) {
                last = true;
                ended = "the wand reached the end cap";
            } else if (stop_requested()) {
                last = true;
                ended = std::string(stop_signal_name()) + " received";
            } else if (safety_s > 0.0 && offscreen && su.frames == 0 && su.seconds == 0.0 && t >= safety_s) {
                last = true;
                ended = "the wall-time safety net (" + format_number(safety_s) + " s) stopped the run";
            }

            const MeshFrame& mesh = backend.runtime().latest_mesh();
            if (mesh.version != r.last_mesh_version) {
                ++r.mesh_versions_drawn;
                r.last_mesh_version = mesh.version;
            }
            // The mouse stylus picks on the CPU: with the GPU contour (no CPU meshes published) the contour is read
            // back when it changed, at most every kPickRefreshS, and not while the left button holds the surface of
            // the press anyway.
            if (mouse_stylus && gpu_contour && !mouse_stylus->stylus().left()) {
                const std::uint64_t updates = gpu_contour->updates();
                const double since = seconds_since(gpu_pick_at);
                if (!gpu_pick.whole || (updates != gpu_pick_updates && since >= kPickRefreshS)) {
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
            tile_view_of(mesh.tiles, mesh.groups, su.lod, tiles);
            const haptics::LoopView& lv = backend.runtime().latest_view();
            // The tool the loop uses now (its size changes with [ and ] at the desk).
            const ToolShape tool_now = lv.tool.radius_m > 0.0 ? lv.tool : scene.spec.tool;
            renderer::SceneView view = scene_view_from(lv, mesh.tiled ? nullptr : &mesh.mesh, tool_now.radius_m,
                                                       backend.start_tool_m(), backend.start_box_m());
            view.tool_shape = tool_now;
            view.tool_mesh = backend.runtime().tool_mesh();
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
                sculpt_rate.add(std::chrono::duration<double>(Clock::now().time_since_epoch()).count(),
                                mesh.sculpt_steps);
                // The proxy of a mesh tool's tip: a marker a tenth of the tool's size, not its bounding sphere.
                const double proxy_r =
                    scene.spec.tool.kind == ToolKind::kMesh ? 0.1 * scene.spec.tool_size_m : tool_now.radius_m;
                std::string status = saving_lines(saving);
                if (mouse_stylus) status = mouse_stylus->stylus().status() + (status.empty() ? "" : "\n" + status);
                if (study_view) status = study_view->status() + (status.empty() ? "" : "\n" + status);
                add_run_items(view, lv, proxy_r, kForceMetresPerNewton,
                              RunOverlay{haptic_rate.rate_hz(), sculpt_rate.rate_hz(), prev_frame_ms, status});
            }
            if (wand) {
                wand_nav->update(wand->sample(), t - wand_prev_t, nav);
                wand_prev_t = t;
            }
            const RunCamera cam = navigated_camera(dc.screen, head->head_at(t), dc.eye_separation_m, nav);

            const auto t0 = Clock::now();
            if (mouse_stylus) {
                if (!window) mouse_stylus->apply_script(scene.cursor, lv.t_s);
                // The cursor is in one eye's image (side by side: either half; top-bottom: either half).
                double w_px = eye_w, h_px = eye_h;
                if (window) {
                    const VkExtent2D fb = window->framebuffer_size();
                    const auto [ow, oh] = renderer::output_size(output, eye_w, eye_h);
                    w_px = static_cast<double>(fb.width) * eye_w / ow;
                    h_px = static_cast<double>(fb.height) * eye_h / oh;
                }
                if (gpu_contour) mouse_stylus->frame(cam.screen, cam.head.position, w_px, h_px, gpu_pick, lv, t0);
                else mouse_stylus->frame(cam.screen, cam.head.position, w_px, h_px, mesh, lv, t0);
            }
            if (frame > 0) r.interval_ms.add(ms_between(prev_start, t0));
            prev_start = t0;
            sink->draw(rend, view,
                       renderer::StereoCamera{cam.screen, cam.head, cam.eye_separation_m, cam.near_m, cam.far_m});
            if (contour_lock) contour_lock.unlock();
            r.presents += sink->present(rend);
            r.last_eye = sink->last_eye();
            if (mouse_stylus) mouse_stylus->shown(lv, Clock::now());
            prev_frame_ms = ms_between(t0, Clock::now());
            r.frame_ms.add(prev_frame_ms);
            r.gpu_ms.add(rend.last_gpu_ms());
            for (const renderer::FrameStats& fs : rend.take_finished_frames()) r.render.add(fs);
            r.frames = frame + 1;
            if (last) break;
            if (offscreen && su.pace)
                std::this_thread::sleep_until(t_render + std::chrono::duration_cast<Clock::duration>(
                                                             std::chrono::duration<double>((frame + 1) * frame_period_s)));
        }
        rend.finish();  // the frames still in flight
        for (const renderer::FrameStats& fs : rend.take_finished_frames()) r.render.add(fs);
    } catch (...) {
        try {
            backend.runtime().stop();
        } catch (...) {  // the render failure is the one to report
        }
        throw;
    }
    r.render_s = seconds_since(t_render);
    r.stroke_completed = scene.has_stroke && backend.stroke_done() && backend.runtime().loop_stats().ticks >= backend.stroke_ticks();
    backend.runtime().stop();
    r.notes.insert(r.notes.begin(), "ended: " + ended);
    if (tracker) r.notes.push_back("tracker: " + tracker->status().note);
    r.head = nlohmann::json{{"provider", to_string(scene.head)}};
    if (dtrack) {
        r.head = dtrack->report_json();
        r.notes.push_back("head: " + dtrack->note());
    }
    if (wand) {
        r.wand = wand_report_json(*wand, *wand_nav, nav);
        r.notes.push_back("wand: " + wand->note());
    }
    r.loop = backend.runtime().loop_stats();
    r.spilled_intervals = backend.runtime().booleans().backend->spilled_intervals();
    r.model_bytes = backend.runtime().booleans().backend->model_bytes();
    r.sculpt_validation_messages = backend.runtime().booleans().backend->validation_messages();
    if (stop_requested()) r.stopped_by = stop_signal_name();
    if (gpu_contour) {
        r.gpu_contour = gpu_contour->stats();
        r.contour_lock_wait_ms_total = gpu_contour->lock_wait_ms_total();
        r.contour_lock_wait_ms_max = gpu_contour->lock_wait_ms_max();
    }
    r.sculpt = backend.runtime().sculpt_stats();
    r.journal = journal_report_json(backend.runtime().journal_stats(), r.sculpt, backend.runtime().session_s());
    r.saves = backend.runtime().save_status();
    if (r.saves.failures > 0) r.notes.push_back("a save during the session failed: " + r.saves.message);
    if (!r.saves.checkpoint_error.empty()) r.notes.push_back("checkpoints stopped: " + r.saves.checkpoint_error);
    if (const compute::JournalStats* j = backend.runtime().journal_stats(); j && !j->error.empty())
        r.notes.push_back("journal stopped: " + j->error);
    r.session_s = backend.runtime().session_s();
    if (mouse_stylus) {
        r.mouse = mouse_stylus->report_json();
        r.mouse["pick_surface"] = gpu_contour ? "gpu contour, read back" : "cpu contour";
        r.mouse["pick_reads"] = gpu_pick_reads;
    }
    if (study_view) r.study = study_view->report_json();
    if (elastic_view) r.deformation = elastic_view->report_json();
    r.volume_after_m3 = compute::dexel_volume_m3(backend.runtime().workpiece().model);
    r.present_timings = sink->present_timings();
    r.spec = backend.runtime().spec();
    r.tool = tool_json(r.spec);
    r.ticks = backend.runtime().records().size();
    const std::array<nlohmann::json, 2> tick_summaries = tick_summary_json(backend.runtime().records());
    r.period_us = tick_summaries[0];
    r.tick_compute_us = tick_summaries[1];
    r.haptics = haptics_report_json(backend.runtime().spec(), r.loop, backend.runtime().records(), r.session_s, backend.runtime().profile().name,
                                    backend.runtime().profile().max_force_n, backend.runtime().device_status());
    r.haptics["stiffness_n_per_m"] = backend.runtime().config().contact.stiffness_n_per_m;
    r.haptics["device_link"] = device_link_json(backend.runtime().device_link());
    r.haptics["link"] = link_json(backend.runtime().device_link());

    // 5. Outputs.
    fs::create_directories(su.out);
    const fs::path out(su.out);
    // Every output is tried, each failure noted; one that fails (a full disk) costs none of the others, and the
    // report says which failed. The first failure is then the command's error.
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
        for (std::string& file : sink->finish(rend, out.string())) r.files.push_back(std::move(file));
    });
    // The carved model as a closed mesh (the CPU contour of the final model, as demo and replay write it), and
    // the recording.
    attempt("sculpted.ply", [&] {
        const SessionRuntime::FinalMesh carved = backend.runtime().final_mesh();
        r.carved_mesh = carved_mesh_report_json(carved.mesh);
        compute::write_ply((out / "sculpted.ply").string(), carved.mesh, carved.materials);
        r.files.push_back((out / "sculpted.ply").string());
    });
    if (!su.record.empty()) {
        if (backend.runtime().records().size() < backend.runtime().loop_stats().ticks)
            r.notes.push_back("record: only the first " + std::to_string(backend.runtime().records().size()) + " of " +
                              std::to_string(backend.runtime().loop_stats().ticks) + " ticks were kept; a replay carves less");
        attempt("record", [&] {
            std::string notes;  // a protocol's test trial: tagged for `tridex study analyze`
            if (const RunStudy& st = scene.study; st.enabled && !st.participant.empty())
                notes = study::tag_notes(spec_to_json(backend.runtime().spec()),
                                         study::StudyTag{st.participant, st.group, st.trial, st.model,
                                                         st.scene.tube.name, study::tube_id(st.scene.tube)});
            write_session_recording(su.record, backend.runtime().spec(), backend.runtime().records(), notes, r.sculpt.marks);
            r.files.push_back(su.record);
        });
    }
    if (!su.save.empty()) {
        attempt("save", [&] {
            save_session_model(su.save, backend.runtime().workpiece(), backend.runtime().spec());
            r.files.push_back(su.save);
        });
    }
    // The render context's messages plus the sculpting device's (its own context on the GPU path).
    r.validation_messages = ctx.validation_messages() + backend.runtime().booleans().backend->validation_messages();
    r.wall_s = seconds_since(t_start);
    r.files.push_back((out / "report.json").string());
    write_run_report(r.files.back(), r);
    if (!failed.empty())
        throw Error(failed.front() + (failed.size() > 1 ? " (and " + std::to_string(failed.size() - 1) + " more)" : std::string()) +
                    "; the other outputs and report.json were written to " + su.out);
    return r;
}

}  // namespace tridex::app
