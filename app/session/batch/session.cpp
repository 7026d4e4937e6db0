// app/session/batch/session.cpp - the session pipeline shared by demo and replay: the one frame loop with the end-only sink (the
// picture is rendered once, from the final model), then the outputs.
#include "app/session/batch/session.hpp"

#include "app/session/runtime/frame_loop.hpp"
#include "app/session/view/framing.hpp"
#include "app/session/view/symmetry_view.hpp"
#include "app/session/view/more_view.hpp"
#include "app/scene/workpiece_list.hpp"
#include "app/session/run/run_actions.hpp"
#include "app/support/progress.hpp"
#include "app/support/stop_signal.hpp"
#include "haptics/tool_points.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "app/support/memory.hpp"
#include "app/session/report/report.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/mesh_export.hpp"
#include "compute/mesh/mesh_io.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/volume.hpp"
#include "core/format.hpp"
#include "compute/model/workpiece.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/camera/display_config.hpp"
#include "renderer/image/image.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The designer's eyes are 0.65 m from the wall and 0.15 m above the workpiece's centre, which floats
// 0.3 m in front of the wall within arm's reach: the stroke carves the side facing the designer and
// the whole workpiece stays inside the wall's frame.
const Vec3 kHeadPosition{0.0, 0.15, 0.65};
constexpr double kEyeSeparation = renderer::kDefaultEyeSeparationM;  // m

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// How often a session drawn by the end-only sink looks at its end conditions, s.
constexpr double kEndOnlyPollS = 0.002;

// The frames of a session whose picture is rendered once from the final model (demo, replay): each frame polls the
// device's main-thread input, runs the commands its buttons are bound to (the driver's defaults: a game controller's
// Y switches the operation, a stylus's buttons undo and redo; no menu is drawn here) and checks the end of the
// session; the end-only sink draws nothing until then.
class EndOnlyFrames final : public FrameSteps {
public:
    // `expected`: the ticks the session should run, for `step`'s progress (0: unknown).
    EndOnlyFrames(SessionRuntime& rt, std::size_t ticks, double timeout_s, std::size_t expected,
                  ProgressReporter::Step& step)
        : rt_(rt),
          ticks_(ticks),
          timeout_s_(timeout_s),
          expected_(expected),
          step_(step),
          t0_(Clock::now()),
          actions_(&rt, nullptr, nav_, nullptr, swap_, ao_, rt.spec().tool),
          buttons_(default_bindings(rt.spec().device_driver, driver_caps(rt.spec().device_driver)).tool) {}
    bool take_input() override {
        rt_.poll_device_frame();
        const haptics::LoopView& v = rt_.latest_view();
        if (expected_ > 0) step_.update(static_cast<double>(v.tick) / static_cast<double>(expected_));
        if (v.tick > 0) {
            pressed_.clear();
            buttons_.update(v.buttons, pressed_);
            for (const std::string& a : pressed_) (void)builtin_actions().run(a, actions_);
        }
        return !actions_.end_requested();
    }
    // The last frame: the loop ended by itself (the device vanished, a replay's end), the ticks are done, the
    // wall-time safety net ran out, or a stop signal came.
    bool last_frame(std::uint64_t) override {
        return !rt_.loop_running() || (ticks_ > 0 && rt_.loop_stats().ticks >= ticks_) ||
               seconds_since(t0_) >= timeout_s_ || stop_requested();
    }
    void draw(std::uint64_t) override {}

private:
    SessionRuntime& rt_;
    std::size_t ticks_;
    double timeout_s_;
    std::size_t expected_;
    ProgressReporter::Step& step_;
    Clock::time_point t0_;
    renderer::SceneNavigation nav_;  // nothing is navigated here: view actions change nothing that is drawn
    bool swap_ = false, ao_ = true;
    RunActions actions_;
    BindingReader buttons_;
    std::vector<std::string> pressed_;
};

// The name of a session's progress step: a replay's length of samples and pace, or the session's length.
std::string session_step_name(const SessionSpec& spec, const LoopOverrides& loop, std::size_t ticks) {
    char buf[96];
    if (loop.recorded_ticks > 0)
        std::snprintf(buf, sizeof buf, "replaying %.1f s of samples%s",
                      static_cast<double>(loop.recorded_ticks) * spec.period_s, loop.free_run ? "" : " in real time");
    else if (ticks > 0)
        std::snprintf(buf, sizeof buf, "sculpting the %.1f s session", static_cast<double>(ticks) * spec.period_s);
    else
        std::snprintf(buf, sizeof buf, "sculpting the session");
    return buf;
}

}  // namespace

void check_image_size(int width, int height) {
    if (width < 16 || height < 16 || width > 8192 || height > 8192)
        throw Error("--width/--height: must be between 16 and 8192 px, got " + std::to_string(width) + "x" +
                    std::to_string(height));
}

std::pair<int, int> parse_image_size(const std::string& text, const std::string& option) {
    int w = 0, h = 0;
    char x = 0;
    std::size_t used = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%zn", &w, &x, &h, &used) != 3 || x != 'x' || used != text.size())
        throw Error(option + ": '" + text + "' is not WIDTHxHEIGHT in pixels, e.g. 1280x720");
    try {
        check_image_size(w, h);
    } catch (const Error&) {
        throw Error(option + ": must be between 16 and 8192 px per side, got " + text);
    }
    return {w, h};
}

SessionRun run_session(const SessionSpec& spec, Workpiece wp, std::unique_ptr<devices::HapticDevice> device,
                       std::size_t ticks, std::size_t max_records, double timeout_s, const Vec3& start_m,
                       const SculptOptions& sculpt_opt, const LoopOverrides& loop, std::vector<Workpiece> more) {
    SessionRun run;
    RuntimeOptions ro;
    ro.sculpt = sculpt_opt;
    ro.loop = loop;
    ro.max_ticks = max_records;
    run.runtime = std::make_unique<SessionRuntime>(spec, std::move(wp), std::move(more), std::move(device), start_m, ro);
    SessionRuntime& rt = *run.runtime;
    const BackendChoice& booleans = rt.booleans();
    run.sculpt_path = booleans.backend->path();
    run.sculpt_device = booleans.backend->device();
    run.sculpt_path_reason = booleans.cpu_reason();
    run.sculpt_backend_reason = booleans.reason;
    run.clay_path = booleans.backend->clay_path();
    run.clay_path_reason = booleans.backend->clay_reason();
    run.contour_path = rt.contour_path();
    run.contour_reason = rt.contour_reason();
    run.tiles_initial = rt.tiles_initial();
    run.contour_s = rt.contour_s();

    const std::size_t expected = loop.recorded_ticks > 0 ? loop.recorded_ticks : ticks;
    ProgressReporter::Step step = progress().step(session_step_name(spec, loop, ticks));
    rt.start();
    EndOnlyFrames frames(rt, ticks, timeout_s, expected, step);
    run_frames(frames, FramePacing{kEndOnlyPollS, true});
    step.finish();
    run.stopped_by = stop_signal_name();
    run.last_view = rt.latest_view();  // this thread is the view's only reader
    rt.stop();  // drains every sample the loop pushed; rethrows a sculpt failure
    run.session_s = rt.session_s();
    if (GpuContourShare* g = rt.gpu_contour()) run.gpu_contour = g->stats();
    run.records = rt.records();
    run.loop = rt.loop_stats();
    if (run.loop.device_lost && ticks > 0 && (run.loop.ticks < ticks || run.loop.device_down_s > 0.0) &&
        run.stopped_by.empty())
        run.device_lost_at_s = std::max(0.0, (run.records.empty() ? 0.0 : run.records.back().t_s) - run.loop.device_down_s);
    run.sculpt = rt.sculpt_stats();
    if (const compute::JournalStats* j = rt.journal_stats()) run.journal = *j;
    run.volume_after_m3 = compute::dexel_volume_m3(rt.workpiece().model);
    ProgressReporter::Step contour_step = progress().step("contouring the carved model");
    SessionRuntime::FinalMesh carved = rt.final_mesh();
    contour_step.finish();
    run.carved = std::move(carved.mesh);
    run.carved_materials = std::move(carved.materials);
    run.spilled_intervals = booleans.backend->spilled_intervals();
    run.model_bytes = booleans.backend->model_bytes();
    run.sculpt_validation_messages = rt.sculpt_validation_messages() +
                                     (rt.context() ? rt.context()->validation_messages() : 0u);
    // The final render needs only the Context (and the contour buffers on the GPU contour path).
    rt.release_gpu_booleans();
    return run;
}

namespace {

// The smallest box holding both (an empty one adds nothing).
Aabb united(Aabb a, const Aabb& b) {
    if (!b.empty()) {
        a.add(b.lo);
        a.add(b.hi);
    }
    return a;
}

// Each further workpiece's final model beside the first's `first_ply` (path_for_workpiece), in its model frame.
void write_more_meshes(SessionRuntime& rt, const std::string& first_ply, OutputWrites& writes) {
    for (std::size_t k = 1; k < rt.workpiece_count(); ++k) {
        const std::string ply = path_for_workpiece(first_ply, k);
        writes.attempt(ply, [&] {
            std::vector<std::uint8_t> materials;
            const TriMesh mesh = rt.more_workpiece(k).final_mesh(materials);
            compute::write_ply(ply, mesh, materials);
        });
    }
}

// The symmetric copies of the tool where the session ended, as ghosts, and the mirror planes, as the window draws them.
std::vector<renderer::SceneObject> symmetry_objects(const SymmetryGhosts& ghosts,
                                                    const std::vector<haptics::TickRecord>& records, const ToolShape& tool,
                                                    const Pose& pose) {
    std::vector<renderer::SceneObject> out;
    if (!records.empty()) ghosts.append(records.back().symmetry, records.back().tool_world, tool, out, pose);
    return out;
}

// The tool where the session ended (the start of the device's workspace when it never ticked).
void show_final_tool(renderer::SceneView& view, const SessionRun& run, const haptics::HapticLoopConfig& cfg) {
    view.tool_centre_m = run.records.empty() ? cfg.device_to_world.position : run.records.back().hip_m;
    view.tool_radius_m = cfg.contact.tool_radius_m;
    view.tool_shape = cfg.tool;
    view.tool_mesh = run.runtime ? run.runtime->tool_mesh() : nullptr;
    if (!run.records.empty()) view.tool_orientation = run.records.back().tool_world.orientation;
}

// The workspace where the loop left it (workspace moving shifts it); as in Peng et al. (4.1), the box drawn only while
// its button is held at the end.
void show_final_workspace(renderer::SceneView& view, const SessionRun& run, const haptics::HapticLoopConfig& cfg,
                          const devices::DeviceProfile& profile) {
    const haptics::LoopView& lv = run.last_view;
    view.show_workspace = lv.tick > 0 && lv.modelling_paused;
    if (lv.tick > 0) {
        view.workspace_m = Aabb{lv.box.position - lv.box_half_extents_m, lv.box.position + lv.box_half_extents_m};
        view.bubble_centre_m = lv.bubble_centre_m;
        view.bubble_radius_m = lv.bubble_radius_m;
    } else {
        const Vec3 c = cfg.device_to_world.position;
        view.workspace_m = Aabb{profile.workspace_m.lo * cfg.workspace_scale + c, profile.workspace_m.hi * cfg.workspace_scale + c};
    }
}

}  // namespace

void write_session_outputs(const OutputOptions& opt, SessionRun& run, Clock::time_point t_start, OutputWrites& writes) {
    SessionRuntime& rt = *run.runtime;
    const SessionSpec& settings = rt.spec();
    const Workpiece& wp = rt.workpiece();
    const haptics::HapticLoopConfig& cfg = rt.config();
    const devices::DeviceProfile& profile = rt.profile();
    // Both eyes through the PowerWall frusta, offscreen (GPU contour: from its buffers, on the session's Context).
    GpuContourShare* const gpu_contour = rt.gpu_contour();
    std::optional<gpu::Context> own_ctx;
    if (!rt.context()) {
        gpu::ContextOptions gopt;
        gopt.validation = opt.validate;
        own_ctx.emplace(gpu::Context::create(gopt));
    }
    gpu::Context& gpu_ctx = rt.context() ? *rt.context() : *own_ctx;
    // Render-only validation count: on the session's Context the Booleans' messages came first (they are
    // sculpt_validation_messages), so count from here, renderer creation included, on either Context.
    const std::uint32_t validation_before_render = gpu_ctx.validation_messages();
    auto renderer = renderer::OffscreenStereoRenderer::create(gpu_ctx, opt.width, opt.height);
    renderer::SceneView view;
    view.palette = &settings.palette;  // the session's names and colours
    renderer::IndirectWorkpiece indirect;
    std::unique_lock<std::mutex> contour_lock;
    if (gpu_contour) {
        contour_lock = gpu_contour->lock_frame(indirect);
        view.indirect_workpiece = &indirect;
    } else {
        view.workpiece = &run.carved;
        view.workpiece_materials = &run.carved_materials;
    }
    show_final_tool(view, run, cfg);
    // Where the loop left the workpiece (the tool may have placed it).
    view.workpiece_pose = run.last_view.tick > 0 ? run.last_view.workpiece_pose : cfg.workpiece_pose;
    const SymmetryGhosts ghosts(wp.model.lattice.bounds(), view.tool_mesh);
    std::vector<renderer::SceneObject> ghost_objects = symmetry_objects(ghosts, run.records, cfg.tool, view.workpiece_pose);
    std::vector<TriMesh> more_meshes;  // the further workpieces' final models, by material (drawn from here)
    const Aabb more_box = append_final_more(rt, run.last_view, settings.palette, more_meshes, ghost_objects);
    view.objects = ghost_objects;
    show_final_workspace(view, run, cfg, profile);
    Pose head;
    head.position = kHeadPosition;
    ProgressReporter::Step step = progress().step("drawing and writing the outputs");
    const auto t_render = Clock::now();
    // The part of the wall the workpiece is seen through from the head (same eyes, same geometry), so that the
    // workpiece fills the images instead of a tenth of a 3 m wall.
    const renderer::Screen screen =
        framing_screen(renderer::Screen::powerwall(), united(placed(wp.model.lattice.bounds(), view.workpiece_pose), more_box),
                       head.position, static_cast<double>(opt.width) / opt.height);
    view.occlusion_strength = opt.ao ? 1.0 : 0.0;
    const renderer::StereoImages eyes = renderer.render(view, screen, head, kEyeSeparation);
    const double render_s = seconds_since(t_render);
    if (contour_lock) contour_lock.unlock();

    fs::create_directories(opt.out);
    const fs::path out(opt.out);
    const auto file = [&](const char* name) { return (out / name).string(); };
    writes.attempt(file("left.png"), [&] { renderer::write_png(file("left.png"), eyes.left); });
    writes.attempt(file("right.png"), [&] { renderer::write_png(file("right.png"), eyes.right); });
    writes.attempt(file("sbs.png"), [&] { renderer::write_png(file("sbs.png"), renderer::side_by_side(eyes.left, eyes.right)); });
    step.update(0.5);
    writes.attempt(file("sculpted.ply"), [&] { compute::write_ply(file("sculpted.ply"), run.carved, run.carved_materials); });
    write_more_meshes(rt, file("sculpted.ply"), writes);
    writes.attempt(file("haptics.csv"), [&] { write_haptics_csv(file("haptics.csv"), run.records); });
    step.finish();

    DemoReport r;
    r.mesh_path = wp.mesh_path;
    r.resolution = wp.resolution;
    r.lattice = wp.model.lattice;
    r.transform = wp.to_world;
    r.volume_mesh_m3 = wp.volume_mesh_m3;
    r.volume_dexel_m3 = wp.volume_dexel_m3;
    r.volume_after_m3 = run.volume_after_m3;
    r.edges = edge_stats(run.carved);
    r.components = mesh_components(run.carved);
    r.vertices = run.carved.positions.size();
    r.triangles = run.carved.triangles.size();
    r.records = &run.records;
    r.loop = run.loop;
    r.sculpt = &run.sculpt;
    r.tiles_initial = run.tiles_initial;
    r.tiles_total = wp.model.tiles.count();
    r.scan_s = wp.scan_s;
    r.contour_s = run.contour_s;
    r.session_s = run.session_s;
    r.render_s = render_s;
    r.stiffness_n_per_m = cfg.contact.stiffness_n_per_m;
    r.max_force_n = profile.max_force_n;
    r.settings = &settings;
    r.device_profile = profile.name;
    r.device_status = run.runtime->device_status();
    r.device_link = run.runtime->device_link();
    r.stopped_by = run.stopped_by;
    r.deformation_max_displacement_m = run.deformation_max_displacement_m;
    r.more_workpieces = more_workpieces_report_json(rt, run.last_view);
    r.sculpt_path = run.sculpt_path;
    r.sculpt_device = run.sculpt_device;
    r.sculpt_path_reason = run.sculpt_path_reason;
    r.sculpt_backend_reason = run.sculpt_backend_reason;
    r.clay_path = run.clay_path;
    r.clay_path_reason = run.clay_path_reason;
    r.spilled_intervals = run.spilled_intervals;
    r.model_bytes = run.model_bytes;
    r.sculpt_validation_messages = run.sculpt_validation_messages;
    r.contour_path = run.contour_path;
    r.contour_reason = run.contour_reason;
    r.gpu_contour = run.gpu_contour;
    r.journal = run.journal ? &*run.journal : nullptr;
    r.device = gpu_ctx.device_name();
    r.eye_strategy = renderer.strategy_note();
    r.validation_messages = gpu_ctx.validation_messages() - validation_before_render;
    r.workpiece = &wp;
    r.workpiece_pose_end = view.workpiece_pose;
    if (gpu_contour) {
        r.contour_lock_wait_ms_total = gpu_contour->lock_wait_ms_total();
        r.contour_lock_wait_ms_max = gpu_contour->lock_wait_ms_max();
    }
    r.command = opt.command;
    r.eye_width = opt.width;
    r.eye_height = opt.height;
    r.eye_separation_m = kEyeSeparation;
    r.ambient_occlusion = opt.ao;
    r.files = writes.written();
    // The journal is written as the session runs: listed when it is whole (`tridex recover` rebuilds the model).
    if (run.journal && run.journal->error.empty() && !run.journal->path.empty()) r.files.push_back(run.journal->path);
    r.files.push_back(file("report.json"));
    for (const std::string& failure : writes.failures()) r.notes.push_back("not written: " + failure);
    if (!run.sculpt_path_reason.empty()) r.notes.push_back("sculpt path cpu: " + run.sculpt_path_reason);
    if (!run.contour_reason.empty()) r.notes.push_back("contour path cpu: " + run.contour_reason);
    if (run.journal && !run.journal->error.empty()) r.notes.push_back("journal stopped: " + run.journal->error);
    if (!run.sculpt.checkpoint_error.empty()) r.notes.push_back("checkpoints stopped: " + run.sculpt.checkpoint_error);
    r.notes.insert(r.notes.begin(), "ended: " + (!run.stopped_by.empty() ? run.stopped_by + " received"
                                                 : run.device_lost_at_s ? "the device was lost at " +
                                                                              format_number(*run.device_lost_at_s) + " s"
                                                 : driver_caps(settings.device_driver).input == devices::InputKind::kRecorded
                                                     ? std::string("the recording ended")
                                                                           : std::string("the stroke ended")));
    r.wall_s = seconds_since(t_start);
    if (!writes.attempt(file("report.json"), [&] { write_report_json(file("report.json"), r); })) r.files.pop_back();
    print_summary(r, opt.out, opt.command);
    if (run.journal && !run.journal->error.empty())
        std::fprintf(stderr, "tridex: journal %s stopped: %s (the session went on; report.json journal.error)\n",
                     run.journal->path.c_str(), run.journal->error.c_str());
    if (!run.sculpt.checkpoint_error.empty())
        std::fprintf(stderr, "tridex: checkpoints stopped: %s (the session went on; report.json journal.checkpoint_error)\n",
                     run.sculpt.checkpoint_error.c_str());
}

}  // namespace tridex::app
