// app/session/run/run_frame.cpp - `tridex run`: the frame loop of a run session: input, the end of the run, what a frame draws,
// and drawing it through the stereo sink.
#include "app/session/run/run_pipeline_parts.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "app/scene/saved_scene.hpp"
#include "renderer/scene/overlay_text.hpp"

namespace tridex::app {

namespace {

using run_detail::kForceMetresPerNewton;
using run_detail::ms_between;
using run_detail::seconds_since;

// The desk's pie menu: its radius on screen, pixels (at the tool's depth).
constexpr double kDeskRingPx = 110.0;
// How often the stylus's pick surface is read back from the GPU contour at most, s.
constexpr double kPickRefreshS = 0.1;
// The longest a frame waits for the haptic loop to take the mouse stylus's new target (RunMouse::await_hand): the
// device glides at a bounded speed, so a long move is drawn on its way; a stalled loop never holds the frame longer.
constexpr std::chrono::microseconds kHandWait{2000};
// A frame counts as sculpting (FrameBudget::set_sculpting) for this long after a frame drew a sculpted change, s: a
// stroke's changes arrive every few frames, and its re-contours and levels keep the cores busy a little longer.
constexpr double kSculptingHoldS = 0.3;

// The overlay's lines about saving: what the last Ctrl+S did, and loudly what is no longer being kept; and what the last
// coarseness change did.
std::string saving_lines(const SaveStatus& s) {
    std::string out;
    auto line = [&out](const std::string& l) { out += (out.empty() ? "" : "\n") + l; };
    if (!s.journal_error.empty()) line("NOT BEING SAVED: journal stopped: " + s.journal_error);
    if (!s.checkpoint_error.empty()) line("checkpoints stopped: " + s.checkpoint_error);
    if (!s.message.empty()) line(s.ok ? s.message : "save failed: " + s.message);
    if (!s.coarseness.empty()) line(s.coarseness);
    return out;
}

// The overlay's line naming the colour union adds and paint sets ("" for the other operations).
std::string colour_line(const ActionTarget& actions, const MaterialPalette& palette) {
    if (actions.op() != ToolOp::kUnion && actions.op() != ToolOp::kPaint) return "";
    return "\ncolour: " + palette[actions.material()].name + " (Shift+1..7)";
}

// The test pattern's overlay lines: what to check, and where the head and the tool are (world m: the display
// config's frame, which is the tracker's own when tracker_to_wall is the identity).
std::string test_pattern_lines(const Vec3& head_m, const Vec3& tool_m) {
    const auto xyz = [](const Vec3& p) {
        return format_number(std::round(p.x * 1e3) / 1e3) + " " + format_number(std::round(p.y * 1e3) / 1e3) + " " +
               format_number(std::round(p.z * 1e3) / 1e3) + " m";
    };
    return "test pattern: the border on the screen's edges; each eye reads its own name (Tab swaps); green nearer\n"
           "head " + xyz(head_m) + ", tool " + xyz(tool_m) + " (display config frame)";
}

}  // namespace

// Window events, the scene's scripted keys (at their device times, through the same handler as a window's), the
// requests they made of the sculpt thread, and the toggles of the eyes and ambient occlusion; false once Esc or the
// window's close button ended the session.
bool RunPipeline::Parts::take_input() {
    SessionRuntime& rt = backend->runtime();
    if (window) {
        window->poll_events();
        renderer::InputEvent e;
        while (window->input().pop(e)) input->handle(e);
    }
    // Devices whose input API runs on this thread poll it (their buttons reach the loop's view).
    rt.poll_device_frame();
    // Scripted keys, the scripted cursor (aim) and its end are on device time (the samples' clock, as a recording's),
    // read once per frame, not on the loop's, which runs ahead of it when the loop skips missed deadlines.
    script_t_s = rt.latest_view().device_t_s;
    for (; next_key < scene.keys.size() && scene.keys[next_key].t_s <= script_t_s; ++next_key)
        for (const renderer::InputEvent& e : chord_events(scene.keys[next_key].chord, script_t_s)) input->handle(e);
    // The hands: the keys' actions, the tool's and the wand's buttons through their bindings, and the pie menu.
    if (wand) wand_now = wand->sample();
    const haptics::LoopView& lv = rt.latest_view();
    HandsFrame h;
    h.t_s = lv.t_s;
    h.tool_fresh = lv.tick > 0;
    h.tool_buttons = lv.buttons;
    h.tool_m = lv.tool_world.position;
    h.tool_joystick_y = lv.joystick_y;
    h.desk_menu = input->menu_held();
    h.wand_fresh = wand && wand_now.fresh && is_finite(wand_now.pose.position);
    if (h.wand_fresh) {
        h.wand_buttons = wand_now.buttons;
        h.wand_m = nav.to_scene(wand_now.pose.position);
        h.wand_joystick_y = wand_now.joystick_y;
    }
    h.head_m = last_eye_scene_m;
    h.scene_scale = nav.scale();
    if (mouse_stylus && pointer_ray) {  // the desk: the cursor points at the slices; the ring a fixed size on screen
        h.pointer_ray = pointer_ray;
        h.ring_radius_m = kDeskRingPx * pointer_m_per_px * glm::length(h.tool_m - last_eye_scene_m);
    }
    controls->frame(h, input->take_actions(), *actions);
    try {  // a detent the device cannot render stably is not felt; the menu still works
        rt.set_menu(controls->detent());
    } catch (const Error& e) {
        if (!menu_detent_refused) r.notes.push_back(std::string("menu detent not felt: ") + e.what());
        menu_detent_refused = true;
    }
    sink->set_swap_eyes(swap);
    saving = rt.save_status();
    // Ctrl+S: the scene that opens it again.
    if (saving.saves > scene_saves && needs_saved_scene(rt.spec(), lv.workpiece_pose)) {
        scene_saves = saving.saves;
        try {
            write_saved_scene(scene.source, model_save_path, rt.spec(), lv.workpiece_pose);
        } catch (const Error& e) {
            r.notes.push_back(std::string("the saved scene was not written: ") + e.what());
        }
    }
    if (!saving.journal_error.empty() && !journal_warned) {
        journal_warned = true;
        std::fprintf(stderr, "tridex: this session is no longer being saved: journal: %s; the model stays in memory "
                             "(Ctrl+S or --save writes it elsewhere)\n", saving.journal_error.c_str());
    }
    if (actions->end_requested()) {
        ended = "the session was ended (session.end)";
        return false;
    }
    return !(window && window->should_close());
}

// True when this frame is the last one; `ended` then says why.
bool RunPipeline::Parts::last_frame(std::uint64_t frame) {
    const double t = seconds_since(t_render);
    const bool unlimited = su.frames == 0 && su.seconds == 0.0;
    std::string companion_ended;
    bool held_open = false;
    for (const SessionCompanion* c : companions) {
        if (companion_ended.empty()) companion_ended = c->ended();
        held_open |= c->holds_session_open();
    }
    if (su.frames > 0 && frame + 1 >= static_cast<std::uint64_t>(su.frames))
        ended = "--frames " + std::to_string(su.frames) + " rendered";
    else if (su.seconds > 0.0 && t >= su.seconds)
        ended = "--seconds " + format_number(su.seconds) + " passed";
    else if (!companion_ended.empty())
        ended = companion_ended;
    else if (offscreen && unlimited && !held_open && backend->stroke_done())
        ended = "the stroke ended";
    else if (offscreen && unlimited && !held_open && script_end_s > 0.0 &&
             backend->runtime().latest_view().device_t_s >= script_end_s)
        ended = "the scripted cursor ended";
    else if (study_view && scene.study.end_at_end_cap && study_view->trial_done())
        ended = "the wand reached the end cap";
    else if (stop_requested())
        ended = std::string(stop_signal_name()) + " received";
    else if (!companion_failure.empty())
        ended = companion_failure;
    else if (backend->runtime().loop_stats().device_lost)
        ended = "the device was lost";
    else if (safety_s > 0.0 && offscreen && unlimited && !held_open && t >= safety_s)
        ended = "the wall-time safety net (" + format_number(safety_s) + " s) stopped the run";
    else
        return false;
    final_frame = true;
    return true;
}

// What this frame draws: the newest mesh (or GPU contour), the tool, the workspace, the study's and the scene's
// objects, and the overlay.
renderer::SceneView RunPipeline::Parts::frame_view(const MeshFrame& mesh, const haptics::LoopView& lv,
                                                   const SaveStatus& saving) {
    SessionRuntime& rt = backend->runtime();
    // The GPU contour's tiles whose read-back levels are current are drawn from them, the others from its buffers.
    const bool gpu_levels = gpu_contour && su.lod && mesh.gpu && !mesh.tiles.empty();
    if (gpu_levels) {
        split_gpu_tiles(mesh.tiles, mesh.groups, indirect, gpu_split);
        tile_view_of(gpu_split.tiles, gpu_split.groups, true, tiles);
    } else {
        tile_view_of(mesh.tiles, mesh.groups, su.lod, tiles);
    }
    // The tool the loop uses now (its size changes with [ and ] at the desk).
    const ToolShape tool_now = lv.tool.radius_m > 0.0 ? lv.tool : scene.spec.tool;
    renderer::SceneView view = scene_view_from(lv, mesh.tiled ? nullptr : &mesh.mesh, tool_now.radius_m,
                                               backend->start_tool_m(), backend->start_box_m());
    view.tool_shape = tool_now;
    view.tool_mesh = rt.tool_mesh();
    view.tool_orientation = lv.tool_world.orientation;
    if (!mesh.tiled) view.workpiece_materials = &mesh.materials;
    view.palette = &scene.spec.palette;
    view.workpiece_pose = lv.workpiece_pose;  // where the loop holds it (the tool may place it)
    view.tiles = tiles.tiles;
    view.tile_groups = tiles.groups;
    view.lod = su.lod;
    if (gpu_contour) view.indirect_workpiece = &indirect;
    view.tiles_from_indirect = gpu_levels;
    view.cull_tiles = su.cull;
    // The picture a session ends on keeps the occlusion; sculpting frames drop it where r.ao_sculpting says so.
    const bool held = ao && sculpting && !r.ao_sculpting && !final_frame;
    if (held) ++r.frames_occlusion_held;
    view.occlusion_strength = ao && !held ? 1.0 : 0.0;
    if (budget) {
        view.occlusion_resolution = budget->quality().occlusion;
        view.lod_max_px = budget->quality().lod_px;
    }
    // Eyes rendered below the window's size: the overlay keeps its size in the window where it can.
    if (rend->height() < window_eye_h) view.overlay_scale = renderer::overlay_scale_for(rend->height(), window_eye_h);
    if (study_view) {
        view.workpiece = nullptr;
        view.tiles = {};
        view.tile_groups = {};
        view.tiles_from_indirect = false;
        view.indirect_workpiece = nullptr;
        view.objects = study_view->frame(lv);
    }
    if (su.test_pattern) {  // the pattern instead of the workpiece; the tool still follows its device
        view.workpiece = nullptr;
        view.tiles = {};
        view.tile_groups = {};
        view.tiles_from_indirect = false;
        view.indirect_workpiece = nullptr;
        view.show_workspace = false;
        view.objects = pattern_objects;
    }
    if (elastic_view) {
        const std::vector<renderer::SceneObject>& o = elastic_view->frame(lv);
        frame_objects.assign(view.objects.begin(), view.objects.end());
        frame_objects.insert(frame_objects.end(), o.begin(), o.end());
        view.objects = frame_objects;
    }
    if (!reference_objects.empty() && !su.test_pattern && !study_view) {  // drawn and felt, never sculpted
        if (view.objects.data() != frame_objects.data()) frame_objects.assign(view.objects.begin(), view.objects.end());
        frame_objects.insert(frame_objects.end(), reference_objects.begin(), reference_objects.end());
        view.objects = frame_objects;
    }
    if (rt.workpiece_count() > 1 && !su.test_pattern && !study_view) {  // the further workpieces
        if (view.objects.data() != frame_objects.data()) frame_objects.assign(view.objects.begin(), view.objects.end());
        more_view.append(rt, lv, scene.spec.palette, frame_objects);
        view.objects = frame_objects;
    }
    if (ghosts && lv.tick > 0 && !su.test_pattern && !study_view) {  // drawn, never felt
        const Symmetry sym = rt.symmetry();
        if (sym.on()) {
            if (view.objects.data() != frame_objects.data()) frame_objects.assign(view.objects.begin(), view.objects.end());
            ghosts->append(sym, lv.tool_world, tool_now, frame_objects, view.workpiece_pose);
            view.objects = frame_objects;
        }
    }
    others_now.clear();  // a shared session's other people: their tools and tracked heads, drawn, never felt
    for (const SessionCompanion* c : companions) c->add_presence(others_now);
    if (!others_now.empty()) {
        if (view.objects.data() != frame_objects.data()) frame_objects.assign(view.objects.begin(), view.objects.end());
        presence_view.append(others_now, frame_objects, last_eye_scene_m, view.workpiece_pose);
        view.objects = frame_objects;
    }
    add_menu(view, lv, saving);
    if (su.items) {
        if (lv.tick > 0) haptic_rate.add(lv.t_s, lv.tick);
        sculpt_rate.add(std::chrono::duration<double>(Clock::now().time_since_epoch()).count(), mesh.sculpt_steps);
        // The proxy of a mesh tool's tip: a marker a tenth of the tool's size, not its bounding sphere.
        const double proxy_r = scene.spec.tool.kind == ToolKind::kMesh ? 0.1 * scene.spec.tool_size_m : tool_now.radius_m;
        std::string status = saving_lines(saving);
        if (mouse_stylus)
            status = mouse_stylus->stylus().status() + colour_line(*actions, scene.spec.palette) +
                     (status.empty() ? "" : "\n" + status);
        if (study_view) status = study_view->status() + (status.empty() ? "" : "\n" + status);
        if (rt.workpiece_count() > 1) {  // which of several workpieces the tool carves, and why
            char line[96];
            const int chosen = rt.chosen_workpiece();
            std::snprintf(line, sizeof line, "workpiece %d of %zu (%s; P changes)", lv.target_workpiece + 1,
                          rt.workpiece_count(), chosen >= 0 ? "chosen" : "touched or nearest");
            status += (status.empty() ? "" : "\n") + std::string(line);
        }
        if (su.test_pattern) status = test_pattern_lines(last_head_m, lv.tool_world.position) + (status.empty() ? "" : "\n" + status);
        // Eyes drawn below the window's size say so, so that a softer picture is not taken for a fault.
        if (rend->width() < window_eye_w) {
            char line[96];
            std::snprintf(line, sizeof line, "eyes drawn at %d x %d, scaled up (--frame-target-ms %g)", rend->width(),
                          rend->height(), su.frame_target_ms);
            status += (status.empty() ? "" : "\n") + std::string(line);
        }
        add_run_items(view, lv, proxy_r, kForceMetresPerNewton,
                      RunOverlay{haptic_rate.rate_hz(), sculpt_rate.rate_hz(), prev_frame_ms, status, su.overlay_stats});
    }
    return view;
}

// The pie menu as this frame shows it (kept in the track for a recording, sent to a cluster's ranks) and, when shown,
// at the hand in the scene (both eyes, at the hand's depth), with the status lines below it.
void RunPipeline::Parts::add_menu(renderer::SceneView& view, const haptics::LoopView& lv, const SaveStatus& saving) {
    const PieMenu& menu = controls->menu();
    std::string status;
    if (menu.shown(lv.t_s)) {
        status = (mouse_stylus ? mouse_stylus->stylus().status()
                               : "operation: " + std::string(tool_op_name(actions->op()))) +
                 colour_line(*actions, scene.spec.palette);
        const std::string save_lines = saving_lines(saving);
        if (!save_lines.empty()) status += "\n" + save_lines;
    }
    menu_now = menu_frame_of(menu, lv.t_s, status);
    menu_track.add(lv.device_t_s, menu_now);  // the recording's clock: a replay's samples carry device time
    if (!menu_now.shown) return;
    if (view.objects.data() != frame_objects.data()) frame_objects.assign(view.objects.begin(), view.objects.end());
    menu_drawing.append(menu_now, controls->root(), frame_objects);
    view.objects = frame_objects;
}

// A desk window's framebuffer decides the eye images' size, so a larger window renders more pixels, not the same ones
// stretched; the screen is widened or heightened about its centre by the window's change of aspect, so the picture
// keeps its proportions and what was framed stays in view. The frame-time budget's render scale shrinks the eye
// images below that size (the present scales them up). Fullscreen and offscreen keep the display config's size and
// screen (a wall's projector shows the configured image on the measured screen).
renderer::Screen RunPipeline::Parts::follow_window() {
    if (!window || su.display != DisplayKind::kWindow) return dc.screen;
    const VkExtent2D fb = window->framebuffer_size();
    if (fb.width == 0 || fb.height == 0) return screen_now;  // minimised: nothing to draw into at any size
    const auto [w, h] = renderer::eye_size_for_output(dc.stereo, static_cast<int>(fb.width), static_cast<int>(fb.height));
    const double scale = budget ? budget->quality().scale : 1.0;
    const int rw = std::max(1, static_cast<int>(std::lround(w * scale)));
    const int rh = std::max(1, static_cast<int>(std::lround(h * scale)));
    if (rw == rend->width() && rh == rend->height()) return screen_now;
    rend->resize(rw, rh);
    if (w != window_eye_w || h != window_eye_h)
        ++window_resizes;
    else
        ++render_scale_changes;
    window_eye_w = w;
    window_eye_h = h;
    const renderer::Screen s =
        w == base_w && h == base_h
            ? base_screen
            : base_screen.fitted_to_aspect(base_screen.width() / base_screen.height() * (static_cast<double>(w) / h) /
                                           (static_cast<double>(base_w) / base_h));
    input->set_metres_per_pixel(s.width() / w);  // a drag pans the scene with the cursor at the new size
    return s;
}

// Moves the wand's navigation, the head and the window's screen to this frame and hands the mouse stylus's target
// to the loop (waiting, briefly, for the loop to take it); returns the frame's camera and start.
RunPipeline::Parts::FrameAim RunPipeline::Parts::aim(const MeshFrame& mesh) {
    const double t = seconds_since(t_render);
    if (wand) {
        wand_nav->update(wand_now, t - wand_prev_t, nav);
        wand_prev_t = t;
    }
    // A head the eyes cannot be drawn from (a tracker glitch: at or behind the screen, or not finite) holds the last
    // good head pose for this frame, counted, instead of ending the session.
    const Pose head_pose = head->head_at(t);
    last_head_m = head_pose.position;
    screen_now = follow_window();
    RunCamera cam = navigated_camera(screen_now, head_pose, dc.eye_separation_m, nav);
    if (eyes_see_screen(cam)) {
        last_good_head = head_pose;
    } else {
        ++head_frames_held;
        cam = navigated_camera(screen_now, last_good_head.value_or(scene.head_pose), dc.eye_separation_m, nav);
    }
    last_eye_scene_m = cam.head.position;
    const auto t0 = Clock::now();
    if (mouse_stylus) {
        const haptics::LoopView& lv = backend->runtime().latest_view();  // not used after await_hand()
        // Offscreen, or a window whose scene scripts the cursor (bench --stalls): the script moves the stylus, at the
        // device time the frame's scripted keys took (a cursor on loop time, which runs ahead, would press before a
        // key scripted earlier).
        if (!window || !scene.cursor.empty()) mouse_stylus->apply_script(scene.cursor, script_t_s);
        // The cursor is in one eye's image (side by side: either half; top-bottom: either half).
        double w_px = rend->width(), h_px = rend->height();
        if (window) {
            const VkExtent2D fb = window->framebuffer_size();
            const auto [ow, oh] = renderer::output_size(dc.stereo, rend->width(), rend->height());
            w_px = static_cast<double>(fb.width) * rend->width() / ow;
            h_px = static_cast<double>(fb.height) * rend->height() / oh;
        }
        SessionRuntime& rt = backend->runtime();
        if (rt.workpiece_count() > 1) {  // the further workpieces' newest meshes, where the loop holds them
            std::vector<PlacedMesh> placed = reference_placed;
            for (std::size_t k = 1; k < rt.workpiece_count(); ++k) {
                MoreWorkpiece& m = rt.more_workpiece(k);
                placed.push_back({&m.latest_mesh().mesh, k < lv.workpiece_count ? lv.workpiece_poses[k] : m.pose(),
                                  m.start_bounds_m()});
            }
            mouse_stylus->set_placed(std::move(placed));
        }
        // The GPU contour with levels of detail publishes its tiles read back: the stylus picks on those.
        if (gpu_contour && mesh.tiles.empty())
            mouse_stylus->frame(cam.screen, cam.head.position, w_px, h_px, gpu_pick, lv, t0);
        else mouse_stylus->frame(cam.screen, cam.head.position, w_px, h_px, mesh, lv, t0);
        mouse_stylus->await_hand(kHandWait);
        // The cursor's ray and the size of a pixel one metre from the eye, for the menu next frame.
        const MouseStylus& st = mouse_stylus->stylus();
        pointer_ray = st.has_cursor() ? cursor_ray(cam.screen, cam.head.position, st.cursor_x(), st.cursor_y(), w_px, h_px)
                                      : std::nullopt;
        const Vec3 n = glm::normalize(glm::cross(cam.screen.lower_right - cam.screen.lower_left,
                                                 cam.screen.upper_left - cam.screen.lower_left));
        const double eye_to_screen = std::abs(glm::dot(cam.head.position - cam.screen.lower_left, n));
        pointer_m_per_px = eye_to_screen > 1e-9 ? cam.screen.width() / w_px / eye_to_screen : 0.0;
    }
    return FrameAim{cam, t0};
}

// Draws the frame through the sink and presents it.
void RunPipeline::Parts::present(std::uint64_t frame, const FrameAim& aim, const haptics::LoopView& lv,
                                 renderer::SceneView& view, std::unique_lock<std::mutex>& contour_lock) {
    const RunCamera& cam = aim.camera;
    const auto t0 = aim.t0;
    if (frame > 0) r.interval_ms.add(ms_between(prev_start, t0));
    prev_start = t0;
    sink->draw(*rend, view, renderer::StereoCamera{cam.screen, cam.head, cam.eye_separation_m, cam.near_m, cam.far_m});
    if (contour_lock) contour_lock.unlock();
    shown = FrameShown{frame, last_good_head.value_or(scene.head_pose), &nav, dc.eye_separation_m,
                       lv.tool_world.position, lv.tool_world.orientation, view.tool_shape, true, view.occlusion_strength,
                       &menu_now};
    shown.proxy_m = lv.proxy_m;
    shown.workpiece_pose = view.workpiece_pose;
    shown.head_tracked = scene.head != HeadMode::kFixed;
    shown.others = others_now;
    for (SessionCompanion* c : companions) {
        c->before_present(shown);
        if (companion_failure.empty()) companion_failure = c->failure();
    }
    ++shown.frame;  // what stopped() is told: one past the last frame presented
    r.presents += sink->present(*rend);
    r.last_eye = sink->last_eye();
    if (mouse_stylus) mouse_stylus->shown(lv, Clock::now());
    prev_frame_ms = ms_between(t0, Clock::now());
    r.frame_ms.add(prev_frame_ms);
    if (budget) budget->add(prev_frame_ms, view.occlusion_strength > 0.0);
    r.gpu_ms.add(rend->last_gpu_ms());
    take_finished_frames();
    r.frames = frame + 1;
    if (su.frame_probe) su.frame_probe(RunFrameProbe{frame, prev_frame_ms, r.triangles, &backend->runtime()});
}

void RunPipeline::Parts::take_finished_frames() {
    for (const renderer::FrameStats& fs : rend->take_finished_frames()) {
        r.render.add(fs);
        detail.offer(fs.groups_wanting_detail);
        drawn.offer(fs.groups_at_level);
        if (fs.frame == 1) {  // the first frame: when it was done and what it drew (report.json startup)
            r.first_frame_done_s = std::isfinite(fs.gpu_end_s)
                                       ? fs.gpu_end_s
                                       : std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
            r.first_frame_triangles = fs.tile_triangles[0] + fs.tile_triangles[1];
            r.first_frame_groups = fs.groups_drawn[0] + fs.groups_drawn[1];
        }
        while (!changes_in_flight.empty() && changes_in_flight.front().frame <= fs.frame) {
            const ChangeDrawn c = changes_in_flight.front();
            changes_in_flight.pop_front();
            if (c.frame != fs.frame) continue;  // its statistics never came back: not counted
            // Drawn when both the device has finished the frame and its present has returned (a window's present
            // may return after the device finished: a software present hands the finished image to the display).
            const bool gpu_clock = std::isfinite(fs.gpu_end_s);
            const double drawn_s = gpu_clock ? std::max(fs.gpu_end_s, c.submitted_s) : c.submitted_s;
            r.sample_to_drawn_ms.add(1e3 * (drawn_s - c.sample_s));
            r.sample_to_submitted_ms.add(1e3 * (c.submitted_s - c.sample_s));
            ++(gpu_clock ? r.drawn_on_gpu_clock : r.drawn_on_submit_clock);
        }
    }
}

// One frame: the newest mesh (or the GPU contour, locked until the frame is drawn), the mouse stylus's pick surface,
// the frame's view, and the frame drawn and presented through the sink.
void RunPipeline::Parts::draw(std::uint64_t frame) {
    SessionRuntime& rt = backend->runtime();
    sculpted_seen = rt.sculpted_changes().count();  // before the mesh: a change published between is drawn again
    const MeshFrame& mesh = rt.latest_mesh();
    double sample_s = std::numeric_limits<double>::quiet_NaN();  // a sculpted change drawn for the first time
    if (mesh.version != r.last_mesh_version) {
        ++r.mesh_versions_drawn;
        r.last_mesh_version = mesh.version;
        // Counted from the first frame (a change made earlier could not have been drawn sooner) and from a scripted
        // stroke's start (a scene that delays its stroke measures the stroke, not the hand waiting at its start).
        const double from_t_s = scene.has_stroke ? scene.stroke.start_s : 0.0;
        if (mesh.oldest_sample_s >= r.first_frame_s && mesh.oldest_sample_t_s >= from_t_s)
            sample_s = mesh.oldest_sample_s;
        if (std::isfinite(sample_s)) r.sample_to_published_ms.add(1e3 * (mesh.published_s - sample_s));
    }
    // The mouse stylus picks on the CPU: with the GPU contour and no tiles published (levels of detail off) it is read back
    // when it changed, at most every kPickRefreshS, and not while the left button holds the surface anyway.
    if (mouse_stylus && gpu_contour && mesh.tiles.empty() && !mouse_stylus->stylus().left()) {
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
    {  // frames within kSculptingHoldS of a sculpted change drawn are sculpting frames (the budget's own step)
        const auto now = Clock::now();
        if (mesh.sculpt_steps != sculpt_steps_drawn) {
            sculpt_steps_drawn = mesh.sculpt_steps;
            sculpted_drawn_at = now;
        }
        sculpting = frame > 0 && ms_between(sculpted_drawn_at, now) < 1e3 * kSculptingHoldS;
        if (budget) budget->set_sculpting(sculpting);
    }
    const FrameAim frame_aim = aim(mesh);
    const haptics::LoopView& lv = rt.latest_view();  // after aim(): the loop has taken the stylus's target
    renderer::SceneView view = frame_view(mesh, lv, saving);
    present(frame, frame_aim, lv, view, contour_lock);
    if (std::isfinite(sample_s))
        changes_in_flight.push_back(ChangeDrawn{
            rend->frames_rendered(), sample_s, std::chrono::duration<double>(Clock::now().time_since_epoch()).count()});
}

// Between paced frames: wakes when the sculpt thread published a sculpted change the last frame did not take.
bool RunPipeline::Parts::wait_for_news(Clock::time_point deadline) {
    const bool news = backend->runtime().sculpted_changes().wait_past(sculpted_seen, deadline);
    if (news) ++r.frames_early;
    return news;
}

// 4. The session's frames, on this thread, through the one frame loop (run_frames) at the display's rate (offscreen:
// paced unless --no-pace, and early for a sculpted change unless --fixed-pace; a window's present waits for the
// display).
void RunPipeline::Parts::frame_loop() {
    swap = su.swap_eyes;
    ao = su.ao;
    const bool cpu_device = ctx->properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    r.ao_sculpting = su.ao_sculpting == "on" || (su.ao_sculpting == "auto" && !cpu_device);
    r.ao_sculpting_reason =
        su.ao_sculpting != "auto" ? "--ao-while-sculpting " + su.ao_sculpting
        : cpu_device              ? "auto: off on a CPU implementation of Vulkan (" + ctx->device_name() +
                           "), where the occlusion's passes lengthen every frame between the tool and the drawn surface"
                     : "auto: on (" + ctx->device_name() + " is not a CPU implementation of Vulkan)";
    FrameBudgetOptions bo;
    bo.target_ms = su.frame_target_ms;
    // The desk window alone trades pixels and levels: a wall's ranks must all draw the same picture, and an
    // offscreen run's images should not depend on how busy the machine is.
    const bool desk_window = window && su.display == DisplayKind::kWindow;
    bo.min_scale = desk_window ? su.min_render_scale : 1.0;
    bo.coarse_lod_px = desk_window && su.lod ? su.max_lod_px : 1.0;
    budget.emplace(bo);
    r.force_m_per_newton = su.items ? kForceMetresPerNewton : 0.0;
    t_render = Clock::now();
    r.first_frame_s = std::chrono::duration<double>(t_render.time_since_epoch()).count();
    if (dtrack) dtrack->set_session_origin(t_render);
    FramePacing pacing{sink->presents_per_frame() / dc.refresh_hz, offscreen && su.pace};
    if (pacing.sleep && su.early_frames) pacing.early_gap_s = pacing.period_s / 2.0;
    r.pacing = !offscreen ? "display" : !su.pace ? "none" : su.early_frames ? "early" : "fixed";
    run_frames(*this, pacing);
    rend->finish();  // the frames still in flight
    take_finished_frames();
    r.frame_budget = budget->to_json();
}


}  // namespace tridex::app
