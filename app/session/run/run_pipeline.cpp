// app/session/run/run_pipeline.cpp - `tridex run`: the session's parts opened in order, collected after the frames, and the
// outputs (the frame loop: app/session/run/run_frame.cpp).
#include "app/session/run/run_pipeline.hpp"

#include "app/scene/saved_scene.hpp"
#include "app/scene/workpiece_list.hpp"
#include "app/support/output_dir.hpp"

#include "app/scene/session_spec.hpp"
#include "app/session/run/run_pipeline_parts.hpp"
#include "app/session/view/framing.hpp"
#include "compute/tools/clay_field.hpp"

#include <tuple>

namespace tridex::app {

namespace {

namespace fs = std::filesystem;
using run_detail::seconds_since;

// The share of its monitor's work area (each way) a desk window opens at when the display config names no resolution.
constexpr double kDeskWindowFill = 0.8;

// What a session that ended early kept, for its error: the output folder and the journal, recording and model files.
std::string kept_work(const RunSetup& su) {
    std::string kept = su.out + " (images, sculpted.ply, report.json)";
    if (!su.journal.empty()) kept += ", the journal " + su.journal;
    if (!su.record.empty()) kept += ", the recording " + su.record;
    if (!su.save.empty()) kept += ", the model " + su.save;
    return kept;
}

// What a desk window frames: the workpiece's placed lattice and every reference object's placed mesh, world m.
Aabb scene_bounds(const SessionRuntime& rt) {
    Aabb box = placed(rt.workpiece().model.lattice.bounds(), rt.config().workpiece_pose);
    for (const PreparedReference& r : rt.references())
        for (const Vec3& p : r.mesh_m.positions) box.add(r.object.pose.apply(p));
    return box;
}

}  // namespace

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
        // A desk window without a resolution of its own opens sized to its monitor (the eye images follow it).
        if (!dc.resolution_given) wo.fill_monitor = kDeskWindowFill;
        window.emplace(renderer::Window::create(wo));
    }
    // The stereo output's policy (eyes, sequencing, composition, presents, files); destroyed before the Context.
    const renderer::SinkOptions sink_options{output, su.swap_eyes, dc.anaglyph, dc.refresh_hz};
    sink = offscreen ? std::unique_ptr<renderer::StereoSink>(std::make_unique<renderer::OffscreenSink>(*ctx, sink_options))
                     : renderer::WindowSink::create(*ctx, *window, sink_options);
    r.present_mode = sink->present_mode();
    for (const std::string& note : sink->notes()) r.notes.push_back(note);
    // A desk window's eye images take the window's size from the first frame (follow_window).
    int rw = eye_w, rh = eye_h;
    if (window && su.display == DisplayKind::kWindow) {
        const VkExtent2D fb = window->framebuffer_size();
        if (fb.width > 0 && fb.height > 0)
            std::tie(rw, rh) = renderer::eye_size_for_output(output, static_cast<int>(fb.width), static_cast<int>(fb.height));
    }
    rend.emplace(renderer::OffscreenStereoRenderer::create(*ctx, rw, rh));
    base_w = window_eye_w = rw;
    base_h = window_eye_h = rh;
    base_screen = dc.screen;
    r.device = ctx->device_name();
    r.eye_strategy = rend->strategy_note();
}

// 2. Head, scene navigation, input, the navigation wand.
void RunPipeline::Parts::open_inputs() {
    head = make_run_head(scene, !offscreen, &km, &tracker, &dtrack);
    // The workpiece's centre where it is placed (a model's centre is only known once loaded: its scene position).
    mouse.pivot_m = scene.spec.workpiece_position_m.value_or(workpiece_pose(scene.spec).apply(scene.spec.workpiece_centre_m));
    input.emplace(km, nav, mouse);
    if (scene.wand_dtrack) {
        const DTrackWandSettings ws{scene.wand_port, scene.wand_flystick, scene.wand_bind,
                                    scene.display.tracker_to_wall, scene.wand_timeout_s};
        const bool share = dtrack && scene.dtrack_port == scene.wand_port;
        wand = std::make_unique<DTrackWand>(ws, share ? dtrack->receiver() : nullptr);
        WandNavigationSettings wn;
        wn.pivot_m = mouse.pivot_m;
        // The bindings decide the grab button and the joystick; re-centring is an action (view.reset) like any other.
        wn.grab_button = -1;
        for (const devices::ButtonInfo& b : su.bindings.wand.buttons)
            if (b.default_action == "nav.grab") wn.grab_button = b.bit;
        wn.reset_button = -1;
        wn.joystick_scales = su.bindings.wand.joystick_y == "nav.scale";
        wand_nav.emplace(wn);
    }
}

// 3. The sculpting threads. One Context for both threads: with a GPU sculpt path the sculpt thread contours into
// buffers this thread draws (unless --cpu-contour).
void RunPipeline::Parts::open_backend() {
    SculptOptions sculpt_options{su.cpu, su.validate, su.cpu_contour, su.gpu_contour, su.journal};
    sculpt_options.checkpoint_s = su.checkpoint_s;
    sculpt_options.tile_lod = su.lod && su.tiles;
    sculpt_options.coarse_groups_from_cells = su.coarse_groups_from_cells;
    sculpt_options.coarse_first = su.coarse_first;
    sculpt_options.stroke_coarse = su.stroke_coarse;
    // A coarse-first start-up and a stroke drawn coarse contour the tiles the frames ask for (they draw the coarse
    // levels everywhere else).
    if (su.coarse_first || su.stroke_coarse) sculpt_options.sculpt_setup.push_back([this](SculptThread& t) { t.refine_on_demand(detail); });
    if (su.stroke_coarse) sculpt_options.sculpt_setup.push_back([this](SculptThread& t) { t.follow_drawn_groups(drawn); });
    sculpt_options.gpu_clay = su.gpu_clay;
    sculpt_options.gpu = su.gpu;
    // Ctrl+S writes the --save file, or model.tdx in the output folder.
    sculpt_options.save_path = !su.save.empty() ? su.save : (fs::path(su.out) / "model.tdx").string();
    model_save_path = sculpt_options.save_path;
    // --record streams the ticks to disk while the session runs: a recording of any length.
    sculpt_options.stream_recording = su.record;
    for (SessionCompanion* c : companions) c->configure(sculpt_options);
    // A tracked tool reads the head's or the wand's receiver when it listens on the same port.
    std::shared_ptr<devices::DTrackReceiver> tool_dtrack;
    if (driver_caps(scene.spec.device_driver).input == devices::InputKind::kTracked) {
        if (dtrack && scene.dtrack_port == scene.tracked_port)
            tool_dtrack = dtrack->receiver();
        else if (wand && scene.wand_port == scene.tracked_port)
            tool_dtrack = wand->receiver();
    }
    backend.emplace(scene, 1.0 / 60.0, su.tiles ? MeshForm::kTiles : MeshForm::kWhole, sculpt_options, &*ctx,
                    tool_dtrack);
    SessionRuntime& rt = backend->runtime();
    for (SessionCompanion* c : companions) c->starting(rt);
    r.sculpt_path = rt.booleans().backend->path();
    r.sculpt_device = rt.booleans().backend->device();
    r.clay_path = rt.booleans().backend->clay_path();
    // Where clay would run only matters to a session that can use it: a clay op, or a device that switches ops
    // (the mouse's keys 4, 5, 6).
    const bool clay_possible =
        compute::is_clay_op(parse_tool_op(scene.spec.op)) || driver_caps(scene.spec.device_driver).switches_op;
    if (clay_possible && !rt.booleans().backend->clay_reason().empty())
        r.notes.push_back("clay path cpu: " + rt.booleans().backend->clay_reason());
    r.sculpt_path_reason = rt.booleans().cpu_reason();
    r.sculpt_backend_reason = rt.booleans().reason;
    if (!r.sculpt_path_reason.empty()) r.notes.push_back("sculpt path cpu: " + r.sculpt_path_reason);
    r.clay_path_reason = rt.booleans().backend->clay_reason();
    r.workpiece = workpiece_report_json(rt.workpiece(), rt.config().workpiece_pose);
    r.scan_s = rt.workpiece().scan_s;
    r.loaded_s = backend->loaded_s();
    r.coarse_first = rt.coarse_first();
    r.tiles_total = rt.workpiece().model.tiles.count();
    r.contour_path = rt.contour_path();
    r.contour_tiles_initial = rt.tiles_initial();
    r.contour_initial_s = rt.contour_s();
    r.contour_reason = rt.contour_reason();
    if (!r.contour_reason.empty()) r.notes.push_back("contour path cpu: " + r.contour_reason);
    gpu_contour = rt.gpu_contour();
    r.volume_before_m3 = rt.workpiece().volume_dexel_m3;
    // A clay session reports how far its surface moved: keep the model as it was (the threads have not started).
    if (compute::is_clay_op(parse_tool_op(scene.spec.op)) && scene.objects.empty()) clay_start = rt.workpiece().model;
    if (devices::MouseDevice* md = backend->mouse()) {
        mouse_stylus.emplace(*md, rt, scene.spec.tool, backend->start_tool_m());
        input->use_stylus(&mouse_stylus->stylus());
    }
    actions.emplace(&rt, mouse_stylus ? &mouse_stylus->stylus() : nullptr, nav, km, swap, ao, scene.spec.tool);
    controls.emplace(su.bindings, 0.05, scene.spec.palette);
    // Offscreen with a scripted cursor and no limits: the run ends half a second (device time) after the cursor
    // script and the scripted keys.
    script_end_s = scene.cursor.empty()
                       ? 0.0
                       : std::max(scene.cursor.end_s(), scene.keys.empty() ? 0.0 : scene.keys.back().t_s) + 0.5;
    const double path_s = static_cast<double>(backend->stroke_ticks()) * scene.spec.period_s;  // a study's path
    safety_s = scene.has_stroke     ? 3.0 * scene.stroke.end_s() + 10.0
               : script_end_s > 0.0 ? 3.0 * script_end_s + 10.0
               : path_s > 0.0       ? 3.0 * path_s + 10.0
                                    : 0.0;
    if (scene.study.enabled) study_view.emplace(scene.study);
    if (su.test_pattern) {
        pattern = wall_test_pattern(dc.screen);
        for (const PatternPiece& piece : pattern) pattern_objects.push_back({&piece.mesh, piece.colour, piece.eyes, piece.lit});
    }
    if (!scene.objects.empty())
        elastic_view.emplace(scene.objects, rt.config().tool_points, rt.config().tool.radius_m);
    std::vector<PlacedMesh> placed;
    for (std::size_t i = 0; i < rt.references().size(); ++i) {
        const ReferenceSpec& r = rt.spec().references[i];
        placed.push_back({&rt.references()[i].mesh_m, rt.references()[i].object.pose, rt.references()[i].mesh_m.bounds()});
        reference_objects.push_back(reference_scene_object(r, rt.references()[i].mesh_m));
    }
    reference_placed = placed;
    if (mouse_stylus) mouse_stylus->set_placed(std::move(placed));
    ghosts.emplace(rt.workpiece().model.lattice.bounds(), rt.tool_mesh());
}


// A desk window with a fixed head frames the workpiece as the demo's picture does (framing_screen: the part of the
// monitor it is seen through, with a margin, at the window's aspect): a zoom, chosen once, so that moving the head
// still moves the view. Tracked heads, fullscreen and offscreen keep the measured screen; so do scenes that draw
// more than the workpiece (a study, scene objects, the test pattern). Reference objects are framed with it.
void RunPipeline::Parts::frame_desk_window() {
    input->set_metres_per_pixel(dc.screen.width() / base_w);  // the window's own size, not the config's
    if (!window || su.display != DisplayKind::kWindow || scene.head != HeadMode::kFixed || scene.study.enabled ||
        su.test_pattern || !scene.objects.empty())
        return;
    base_screen = framing_screen(dc.screen, scene_bounds(backend->runtime()),
                                 scene.head_pose.position, static_cast<double>(base_w) / base_h);
    screen_now = base_screen;
    input->set_metres_per_pixel(base_screen.width() / base_w);
}

// After the frames: stop the threads and collect every counter the report needs.
void RunPipeline::Parts::collect() {
    SessionRuntime& rt = backend->runtime();
    r.render_s = seconds_since(t_render);
    r.window_resizes = window_resizes;
    r.render_scale_changes = render_scale_changes;
    r.eye_resolution_last = {rend->width(), rend->height()};
    r.eye_resolution_window = {window_eye_w, window_eye_h};
    r.stroke_completed = scene.has_stroke && backend->stroke_done() && rt.loop_stats().ticks >= backend->stroke_ticks();
    rt.stop();
    for (SessionCompanion* c : companions) {
        c->stopped(rt, shown);
        if (companion_failure.empty()) companion_failure = c->failure();
        r.companions[c->report_key()] = c->report();
    }
    if (!companion_failure.empty()) ended = companion_failure;
    r.loop = rt.loop_stats();
    if (r.loop.device_lost && !stop_requested()) {
        r.device_lost_at_s = std::max(0.0, (rt.records().empty() ? 0.0 : rt.records().back().t_s) - r.loop.device_down_s);
        ended = "the device was lost at " + format_number(*r.device_lost_at_s) + " s";
    }
    r.notes.insert(r.notes.begin(), "ended: " + ended);
    if (offscreen && dc.stereo == renderer::StereoOutput::kMono)
        r.notes.push_back("mono: left.png, right.png and output.png are the one view from between the eyes "
                          "(--stereo side-by-side or anaglyph draws both eyes)");
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
    r.controls = controls->report_json();
    r.requests_sent = actions->requests_sent();
    r.save_requests_sent = actions->saves_sent();
    if (actions->requests_dropped() > 0)
        r.notes.push_back(std::to_string(actions->requests_dropped()) +
                          " undo, redo or save requests were dropped: the sculpt thread's queue was full");
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
        // With levels of detail the GPU contour's tiles are read back as they change (published with their levels).
        r.mouse["pick_surface"] = !gpu_contour ? "cpu contour"
                                  : su.lod     ? "gpu contour tiles, read back as they change"
                                               : "gpu contour, read back";
        r.mouse["pick_reads"] = gpu_pick_reads;
    }
    if (study_view) r.study = study_view->report_json();
    if (!rt.references().empty()) r.references = references_report_json(rt.spec().references, rt.references());
    if (elastic_view) r.deformation = elastic_view->report_json();
    else if (clay_start) {
        const compute::TriDexel& after = rt.workpiece().model;
        r.deformation = {
            {"max_displacement_m", compute::clay_max_displacement_cells(*clay_start, after) * after.lattice.cell_m}};
    }
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
    add_pose_end(r.workpiece, rt.config().workpiece_pose, rt.latest_view().workpiece_pose);
    r.more_workpieces = more_workpieces_report_json(rt, rt.latest_view());
}

// 5. Outputs. Every output is tried, each failure noted; one that fails (a full disk) costs none of the others, and
// the report says which failed. The first failure is then the command's error.
void RunPipeline::Parts::write_outputs() {
    SessionRuntime& rt = backend->runtime();
    fs::create_directories(su.out);
    const fs::path out(su.out);
    OutputWrites writes;  // each on its own: one that fails is said at once and costs no other
    writes.attempt("the images", [&] {
        for (std::string& file : sink->finish(*rend, out.string())) r.files.push_back(std::move(file));
    });
    // The carved model as a closed mesh (the CPU contour of the final model, as demo and replay write it), and
    // the recording.
    const std::string ply = (out / "sculpted.ply").string();
    if (!su.test_pattern && writes.attempt(ply, [&] {
            const SessionRuntime::FinalMesh carved = rt.final_mesh();
            r.carved_mesh = carved_mesh_report_json(carved.mesh);
            compute::write_ply(ply, carved.mesh, carved.materials);
        }))
        r.files.push_back(ply);
    for (std::size_t k = 1; k < rt.workpiece_count() && !su.test_pattern; ++k) {  // each further workpiece's own
        const std::string more_ply = path_for_workpiece(ply, k);
        if (writes.attempt(more_ply, [&] {
                std::vector<std::uint8_t> materials;
                const TriMesh mesh = rt.more_workpiece(k).final_mesh(materials);
                compute::write_ply(more_ply, mesh, materials);
            }))
            r.files.push_back(more_ply);
    }
    if (!su.record.empty()) {
        if (const std::size_t dropped = rt.loop_stats().records_stream_dropped; dropped > 0)
            r.notes.push_back("record: " + std::to_string(dropped) + " of " + std::to_string(rt.loop_stats().ticks) +
                              " ticks were dropped (the disk fell behind); a replay carves less");
        if (writes.attempt(su.record, [&] {
                std::string notes;  // a protocol's test trial: tagged for `tridex study analyze`
                if (const RunStudy& st = scene.study; st.enabled && !st.participant.empty())
                    notes = study::tag_notes(spec_to_json(rt.spec()),
                                             study::StudyTag{st.participant, st.group, st.trial, st.model,
                                                             st.scene.tube.name, study::tube_id(st.scene.tube)});
                std::vector<std::vector<SculptMark>> more_marks;  // each further workpiece's own
                for (std::size_t k = 1; k < rt.workpiece_count(); ++k)
                    more_marks.push_back(rt.more_workpiece(k).sculpt_stats().marks);
                rt.tick_stream()->finish(notes, r.sculpt.marks, menu_track.to_json_text(), more_marks,
                                         rt.pose_changes());
            }))
            r.files.push_back(su.record);
    }
    if (!su.save.empty() && writes.attempt(su.save, [&] { save_session_model(su.save, rt.workpiece(), rt.spec()); })) {
        r.files.push_back(su.save);
        bool all_saved = true;  // each further workpiece's model beside it, with its own spec
        for (std::size_t k = 1; k < rt.workpiece_count(); ++k) {
            const std::string more_save = path_for_workpiece(su.save, k);
            MoreWorkpiece& m = rt.more_workpiece(k);
            if (writes.attempt(more_save, [&] { save_session_model(more_save, m.workpiece(), m.spec()); }))
                r.files.push_back(more_save);
            else
                all_saved = false;
        }
        // With objects beside the workpiece, several workpieces or a posed one, the scene that opens them as they were.
        const std::string saved_scene = saved_scene_path(su.save);
        const haptics::LoopView& lv = rt.latest_view();
        const Pose pose_now = lv.workpiece_pose;
        const std::vector<Pose> more_now(lv.workpiece_poses.begin() + 1, lv.workpiece_poses.begin() + rt.workpiece_count());
        if (all_saved && needs_saved_scene(rt.spec(), pose_now) && writes.attempt(saved_scene, [&] {
                write_saved_scene(scene.source, su.save, rt.spec(), pose_now, more_now);
            }))
            r.files.push_back(saved_scene);
    }
    for (const std::string& failure : writes.failures()) r.notes.push_back("not written: " + failure);
    // The render context's messages plus the sculpting device's (its own context on the GPU path).
    r.validation_messages = ctx->validation_messages() + rt.booleans().backend->validation_messages();
    r.wall_s = seconds_since(t_start);
    // The journal is written as the session runs: listed when it is whole (`tridex recover` rebuilds the model).
    if (const compute::JournalStats* j = rt.journal_stats(); j && j->error.empty() && !j->path.empty())
        r.files.push_back(j->path);
    for (std::size_t k = 1; k < rt.workpiece_count(); ++k)
        if (const compute::JournalStats* j = rt.more_workpiece(k).journal_stats(); j && j->error.empty() && !j->path.empty())
            r.files.push_back(j->path);
    const std::string report = (out / "report.json").string();
    r.files.push_back(report);
    writes.attempt(report, [&] { write_run_report(report, r); });
    writes.finish(su.out);
}

RunPipeline::RunPipeline(const RunOptions& options, std::vector<SessionCompanion*> companions)
    : p_(std::make_unique<Parts>(options, std::move(companions))) {}

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
    const RunSetup& su = p.r.setup;
    if (!p.companion_failure.empty())
        throw CompanionError(p.companion_failure + "; the session ended there and kept its work: " + kept_work(su));
    if (p.r.device_lost_at_s) {
        const std::string kept = kept_work(su);
        throw DeviceLostError("device '" + su.scene.spec.device_driver + "': the " +
                              p.backend->runtime().profile().name + " was lost " +
                              format_number(*p.r.device_lost_at_s) +
                              " s into the session; the session ended there and kept its work: " + kept);
    }
    return p.r;
}

RunResult run_stereo_session(const RunOptions& options) { return RunPipeline(options).run(); }

}  // namespace tridex::app
