// app/session.cpp - the session pipeline shared by demo and replay.
#include "app/session.hpp"
#include "haptics/tool_points.hpp"

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "app/memory.hpp"
#include "app/report.hpp"
#include "compute/contour_dual.hpp"
#include "compute/mesh_export.hpp"
#include "compute/mesh_io.hpp"
#include "compute/scan_convert.hpp"
#include "compute/volume.hpp"
#include "compute/workpiece.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/image.hpp"
#include "renderer/off_axis.hpp"
#include "renderer/stereo_renderer.hpp"

namespace tridex::app {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The designer's eyes are 0.65 m from the wall and 0.15 m above the workpiece's centre, which floats
// 0.3 m in front of the wall within arm's reach: the stroke carves the side facing the designer and
// the whole workpiece stays inside the wall's frame.
const Vec3 kHeadPosition{0.0, 0.15, 0.65};
constexpr double kEyeSeparation = 0.064;        // m
constexpr std::size_t kRingCapacity = 1 << 16;  // tool samples: 65 s of ticks

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

void check_image_size(int width, int height) {
    if (width < 16 || height < 16 || width > 8192 || height > 8192)
        throw Error("--width/--height: must be between 16 and 8192 px, got " + std::to_string(width) + "x" +
                    std::to_string(height));
}

Workpiece prepare_workpiece(const std::string& mesh_path, int resolution, double stock_m, const Vec3& centre_m) {
    if (resolution < 8 || resolution > 4096)
        throw Error("--resolution: must be between 8 and 4096 cells, got " + std::to_string(resolution));
    const TriMesh input = compute::load_closed_mesh(mesh_path);
    const Mat4 to_world = compute::fit_to_stock(input.bounds(), centre_m, stock_m);
    const TriMesh world_mesh = compute::transformed(input, to_world);
    const compute::Lattice lattice = compute::Lattice::around(world_mesh.bounds(), resolution);
    Workpiece wp{mesh_path, resolution, to_world, signed_volume(world_mesh), 0.0, 0.0,
                 compute::TriDexel::empty(lattice, model_memory_budget_bytes())};
    const auto t_scan = Clock::now();
    compute::scan_convert(world_mesh, wp.model);
    wp.scan_s = seconds_since(t_scan);
    wp.volume_dexel_m3 = compute::dexel_volume_m3(wp.model);
    return wp;
}

bool gpu_contour_default(const gpu::Context& context, std::string& reason) {
    if (context.properties().deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU) return true;
    reason = "the Vulkan device (" + context.device_name() +
             ") is a CPU implementation, where the CPU contour is faster; --gpu-contour forces GPU contouring";
    return false;
}

SessionRun run_session(Workpiece& wp, devices::HapticDevice& device, const haptics::HapticLoopConfig& cfg,
                       std::size_t ticks, double timeout_s, const Vec3& start_m, const SculptOptions& sculpt_opt) {
    SessionRun run;
    // GPU contouring needs the Booleans, the contour and the final render on one Context: the session owns it.
    // On a device where the CPU contour is the default (or with --cpu-contour) the Context still serves
    // the Booleans and the final render: one Context per session, not one per use.
    std::shared_ptr<SessionGpu> g;
    std::string device_reason;
    bool want_gpu_contour = false;
    if (!sculpt_opt.cpu) {
        gpu::ContextOptions gopt;
        gopt.validation = sculpt_opt.validate;
        try {
            g = std::make_shared<SessionGpu>();
            g->context.emplace(gpu::Context::create(gopt));
            want_gpu_contour = !sculpt_opt.cpu_contour &&
                               (sculpt_opt.gpu_contour || gpu_contour_default(*g->context, device_reason));
        } catch (const Error&) {
            g.reset();  // make_boolean_backend below says why on the CPU path
        }
    }
    BackendChoice own_booleans;
    if (g)
        g->booleans = make_boolean_backend_on(wp.model, false, *g->context);
    else
        own_booleans = make_boolean_backend(wp.model, sculpt_opt.cpu, sculpt_opt.validate);
    BackendChoice& booleans = g ? g->booleans : own_booleans;
    run.sculpt_path = booleans.backend->path();
    run.sculpt_device = booleans.backend->device();
    run.sculpt_path_reason = booleans.reason;
    if (g && want_gpu_contour && booleans.backend->gpu_slabs() != nullptr) {
        try {
            g->contour = std::make_unique<GpuContourShare>(*g->context, *booleans.backend->gpu_slabs(), wp.model);
        } catch (const Error& e) {
            run.contour_reason = std::string("the device cannot contour: ") + e.what();
        }
    } else {
        run.contour_reason = sculpt_opt.cpu_contour     ? "--cpu-contour given"
                             : !device_reason.empty() ? device_reason
                                                      : "the Booleans run on the CPU";
    }
    GpuContourShare* const gpu_contour = g ? g->contour.get() : nullptr;
    run.contour_path = gpu_contour ? "gpu" : "cpu";
    compute::Contourer contourer(wp.model);
    const auto t_contour = Clock::now();
    if (gpu_contour) {
        run.tiles_initial = gpu_contour->update_all();
        wp.model.clear_dirty();
    } else {
        run.tiles_initial = contourer.update(wp.model);
    }
    run.contour_s = seconds_since(t_contour);

    SpscRing<ToolSample> ring(kRingCapacity);
    TripleBuffer<ActiveSurface> surface;
    SculptThread sculpt(wp.model, contourer, ring, surface, start_m, cfg.contact.tool_radius_m,
                        haptics::max_point_distance_m(cfg.tool_points));
    sculpt.use_backend(*booleans.backend);
    if (gpu_contour) sculpt.use_gpu_contour(*gpu_contour);
    haptics::HapticLoop loop(device, surface, ring, cfg);
    const auto t_session = Clock::now();
    sculpt.start();
    loop.start();
    while (loop.running() && (ticks == 0 || loop.stats().ticks < ticks) && seconds_since(t_session) < timeout_s)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    run.last_view = loop.latest_view();  // this thread is the view's only reader
    loop.stop();
    sculpt.stop();  // drains every sample the loop pushed; rethrows a sculpt failure
    run.session_s = seconds_since(t_session);
    // The exported mesh: the CPU Contourer's, of the whole final model on the GPU contour path (it did not
    // follow the session), else of anything still dirty (normally nothing).
    if (gpu_contour) {
        std::fill(wp.model.tiles.dirty.begin(), wp.model.tiles.dirty.end(), std::uint8_t{1});
        run.gpu_contour = gpu_contour->stats();
    }
    contourer.update(wp.model);
    run.records = loop.records();
    run.loop = loop.stats();
    run.sculpt = sculpt.stats();
    run.volume_after_m3 = compute::dexel_volume_m3(wp.model);
    run.carved = contourer.mesh();
    run.carved_materials = contourer.mesh_materials();
    run.spilled_intervals = booleans.backend->spilled_intervals();
    run.model_bytes = booleans.backend->model_bytes();
    run.sculpt_validation_messages = booleans.backend->validation_messages();
    // The final render needs only the Context (and the contour buffers on the GPU contour path): free the
    // GPU Booleans' slabs (host memory on lavapipe, large at N = 512 and 1024) before it.
    if (g && !g->contour) g->booleans = {};
    run.gpu = g;
    return run;
}

void write_session_outputs(const OutputOptions& opt, const SessionSettings& settings, const Workpiece& wp,
                           const SessionRun& run,
                           const haptics::HapticLoopConfig& cfg, const devices::DeviceProfile& profile,
                           Clock::time_point t_start) {
    // Both eyes through the off-axis PowerWall frusta, offscreen.
    // On the GPU contour path the workpiece is drawn from the contour buffers, on the session's Context.
    GpuContourShare* const gpu_contour = run.gpu ? run.gpu->contour.get() : nullptr;
    std::optional<gpu::Context> own_ctx;
    if (!run.gpu) {
        gpu::ContextOptions gopt;
        gopt.validation = opt.validate;
        own_ctx.emplace(gpu::Context::create(gopt));
    }
    gpu::Context& gpu_ctx = run.gpu ? *run.gpu->context : *own_ctx;
    // Render-only validation count: on the session's Context the Booleans' messages came first (they are
    // sculpt_validation_messages), so count from here, renderer creation included, on either Context.
    const std::uint32_t validation_before_render = gpu_ctx.validation_messages();
    auto renderer = renderer::OffscreenStereoRenderer::create(gpu_ctx, opt.width, opt.height);
    renderer::SceneView view;
    renderer::IndirectWorkpiece indirect;
    std::unique_lock<std::mutex> contour_lock;
    if (gpu_contour) {
        contour_lock = gpu_contour->lock_frame(indirect);
        view.indirect_workpiece = &indirect;
    } else {
        view.workpiece = &run.carved;
        view.workpiece_materials = &run.carved_materials;
    }
    view.tool_centre_m = run.records.empty() ? cfg.device_to_world.position : run.records.back().hip_m;
    view.tool_radius_m = cfg.contact.tool_radius_m;
    view.show_workspace = true;
    const haptics::LoopView& lv = run.last_view;
    if (lv.tick > 0) {  // the workspace where the loop left it (workspace moving shifts it)
        view.workspace_m = Aabb{lv.box.position - lv.box_half_extents_m, lv.box.position + lv.box_half_extents_m};
        view.bubble_centre_m = lv.bubble_centre_m;
        view.bubble_radius_m = lv.bubble_radius_m;
    } else {
        const Vec3 c = cfg.device_to_world.position;
        view.workspace_m = Aabb{profile.workspace_m.lo * cfg.workspace_scale + c, profile.workspace_m.hi * cfg.workspace_scale + c};
    }
    Pose head;
    head.position = kHeadPosition;
    const auto t_render = Clock::now();
    const renderer::StereoImages eyes = renderer.render(view, renderer::Screen::powerwall(), head, kEyeSeparation);
    const double render_s = seconds_since(t_render);
    if (contour_lock) contour_lock.unlock();

    fs::create_directories(opt.out);
    const fs::path out(opt.out);
    renderer::write_png((out / "left.png").string(), eyes.left);
    renderer::write_png((out / "right.png").string(), eyes.right);
    renderer::write_png((out / "sbs.png").string(), renderer::side_by_side(eyes.left, eyes.right));
    compute::write_ply((out / "sculpted.ply").string(), run.carved, run.carved_materials);
    write_haptics_csv((out / "haptics.csv").string(), run.records);

    DemoReport r;
    r.mesh_path = wp.mesh_path;
    r.resolution = wp.resolution;
    r.lattice = wp.model.lattice;
    r.transform = wp.to_world;
    r.volume_mesh_m3 = wp.volume_mesh_m3;
    r.volume_dexel_m3 = wp.volume_dexel_m3;
    r.volume_after_m3 = run.volume_after_m3;
    r.edges = edge_stats(run.carved);
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
    r.tool_radius_m = cfg.contact.tool_radius_m;
    r.stiffness_n_per_m = cfg.contact.stiffness_n_per_m;
    r.max_force_n = profile.max_force_n;
    r.settings = &settings;
    r.device_profile = profile.name;
    r.sculpt_path = run.sculpt_path;
    r.sculpt_device = run.sculpt_device;
    r.sculpt_path_reason = run.sculpt_path_reason;
    r.spilled_intervals = run.spilled_intervals;
    r.model_bytes = run.model_bytes;
    r.sculpt_validation_messages = run.sculpt_validation_messages;
    r.contour_path = run.contour_path;
    r.contour_reason = run.contour_reason;
    r.gpu_contour = run.gpu_contour;
    r.device = gpu_ctx.device_name();
    r.eye_strategy = renderer.strategy_note();
    r.validation_messages = gpu_ctx.validation_messages() - validation_before_render;
    r.wall_s = seconds_since(t_start);
    write_report_json((out / "report.json").string(), r);
    print_summary(r, opt.out);
}

}  // namespace tridex::app
