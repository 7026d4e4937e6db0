// app/demo.cpp - `tridex demo`: wires the three threads of DESIGN.md around one scripted stroke.
#include "app/demo.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "app/memory.hpp"
#include "app/report.hpp"
#include "app/sculpt_thread.hpp"
#include "app/stroke.hpp"
#include "compute/contour_dual.hpp"
#include "compute/mesh_export.hpp"
#include "compute/mesh_io.hpp"
#include "compute/scan_convert.hpp"
#include "compute/volume.hpp"
#include "compute/workpiece.hpp"
#include "core/error.hpp"
#include "devices/simulated_device.hpp"
#include "gpu/context.hpp"
#include "haptics/haptic_loop.hpp"
#include "renderer/image.hpp"
#include "renderer/off_axis.hpp"
#include "renderer/stereo_renderer.hpp"

#ifndef TRIDEX_SOURCE_ASSETS
#define TRIDEX_SOURCE_ASSETS "assets"
#endif

namespace tridex::app {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// World frame (DESIGN.md): metres, y up, the PowerWall screen in the z = 0 plane facing +z.
// The designer's eyes are 0.65 m from the wall and 0.15 m above the workpiece's centre, which floats
// 0.3 m in front of the wall within arm's reach: the stroke carves the side facing the designer and
// the whole workpiece stays inside the wall's frame.
const Vec3 kWorkpieceCentre{0.0, 0.0, 0.3};
const Vec3 kHeadPosition{0.0, 0.15, 0.65};
constexpr double kEyeSeparation = 0.064;  // m
constexpr double kStiffness = 700.0;      // N/m: 0.7 N/mm, stable on Omni-class devices at 1 kHz
constexpr double kDamping = 0.5;          // N*s/m along the contact normal
constexpr std::size_t kRingCapacity = 1 << 16;  // tool samples: 65 s of ticks

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

std::string default_mesh_path() {
    std::vector<fs::path> candidates;
    if (const char* env = std::getenv("TRIDEX_ASSETS")) candidates.emplace_back(fs::path(env) / "bunny.off");
    candidates.emplace_back(fs::path("assets") / "bunny.off");
    candidates.emplace_back(fs::path(TRIDEX_SOURCE_ASSETS) / "bunny.off");
    for (const fs::path& p : candidates)
        if (fs::is_regular_file(p)) return p.string();
    throw Error("assets/bunny.off: the bundled workpiece is missing; pass --mesh FILE");
}

void run_demo(const DemoOptions& o) {
    const auto t_start = Clock::now();
    if (o.resolution < 8 || o.resolution > 4096)
        throw Error("--resolution: must be between 8 and 4096 cells, got " + std::to_string(o.resolution));
    if (!(o.seconds >= 0.5 && o.seconds <= 600.0))
        throw Error("--seconds: must be between 0.5 and 600, got " + std::to_string(o.seconds));
    if (!(o.tool_radius_m >= 0.0005 && o.tool_radius_m <= 0.25 * o.stock_m))
        throw Error("--tool-radius-mm: must be between 0.5 mm and a quarter of the stock (" +
                    std::to_string(250.0 * o.stock_m) + " mm), got " + std::to_string(o.tool_radius_m * 1e3));
    if (o.width < 16 || o.height < 16 || o.width > 8192 || o.height > 8192)
        throw Error("--width/--height: must be between 16 and 8192 px");
    const std::string mesh_path = o.mesh.empty() ? default_mesh_path() : o.mesh;

    // 1. Workpiece: load, place in the world, scan-convert into the tri-dexel model.
    const TriMesh input = compute::load_closed_mesh(mesh_path);
    const Mat4 to_world = compute::fit_to_stock(input.bounds(), kWorkpieceCentre, o.stock_m);
    const TriMesh world_mesh = compute::transformed(input, to_world);
    const double volume_mesh = signed_volume(world_mesh);
    const compute::Lattice lattice = compute::Lattice::around(world_mesh.bounds(), o.resolution);
    compute::TriDexel model = compute::TriDexel::empty(lattice, model_memory_budget_bytes());
    const auto t_scan = Clock::now();
    compute::scan_convert(world_mesh, model);
    const double scan_s = seconds_since(t_scan);
    const double volume_dexel = compute::dexel_volume_m3(model);
    compute::Contourer contourer(model);
    const auto t_contour = Clock::now();
    const std::size_t tiles_initial = contourer.update(model);
    const double contour_s = seconds_since(t_contour);

    // 2. The stroke and the simulated device that follows it.
    StrokeParams sp;
    sp.duration_s = o.seconds;
    sp.tool_radius_m = o.tool_radius_m;
    const StrokePlan plan = plan_stroke(model, sp);
    const devices::DeviceProfile profile = devices::DeviceProfile::phantom_omni();
    Pose device_to_world;
    device_to_world.position = plan.centre_m;  // the device workspace is centred on the pass
    std::vector<Vec3> device_path;
    for (const Vec3& w : plan.world_m) device_path.push_back(w - plan.centre_m);
    devices::SimulatedDevice device(profile, devices::ScriptedPath(plan.t_s, device_path), devices::SimulatedHandParams{},
                                    1e-3);

    // 3. The three threads' hand-offs, then the haptic loop and the sculpt thread.
    SpscRing<ToolSample> ring(kRingCapacity);
    TripleBuffer<ActiveSurface> surface;
    haptics::HapticLoopConfig cfg;
    cfg.period_s = 1e-3;
    cfg.contact = haptics::ContactParams{kStiffness, kDamping, o.tool_radius_m};
    cfg.device_to_world = device_to_world;
    cfg.op = ToolOp::kSubtract;
    cfg.max_ticks = static_cast<std::size_t>(o.seconds * 1000.0 * 1.5) + 1000;
    SculptThread sculpt(model, contourer, ring, surface, plan.world_m.front());
    haptics::HapticLoop loop(device, surface, ring, cfg);

    // The session lasts the stroke's length in device time (one simulated step per tick), so an
    // overloaded machine that skips deadlines still plays the whole stroke; wall time is only a
    // safety net.
    const std::size_t session_ticks = static_cast<std::size_t>(std::llround(o.seconds / cfg.period_s));
    const auto t_session = Clock::now();
    sculpt.start();
    loop.start();
    while (loop.running() && loop.stats().ticks < session_ticks && seconds_since(t_session) < 3.0 * o.seconds + 10.0)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    loop.stop();
    sculpt.stop();
    const double session_s = seconds_since(t_session);
    contourer.update(model);  // anything still dirty (normally nothing)

    // 4. Results: the carved mesh and its checks.
    const TriMesh carved = contourer.mesh();
    const EdgeStats edges = edge_stats(carved);
    const double volume_after = compute::dexel_volume_m3(model);

    // 5. Both eyes through the off-axis PowerWall frusta, offscreen.
    gpu::ContextOptions gopt;
    gopt.validation = o.validate;
    gpu::Context gpu_ctx = gpu::Context::create(gopt);
    auto renderer = renderer::OffscreenStereoRenderer::create(gpu_ctx, o.width, o.height);
    renderer::SceneView view;
    view.workpiece = &carved;
    const auto& recs = loop.records();
    view.tool_centre_m = recs.empty() ? plan.world_m.back() : recs.back().hip_m;
    view.tool_radius_m = o.tool_radius_m;
    view.show_workspace = true;
    view.workspace_m = Aabb{profile.workspace_m.lo + plan.centre_m, profile.workspace_m.hi + plan.centre_m};
    Pose head;
    head.position = kHeadPosition;
    const auto t_render = Clock::now();
    const renderer::StereoImages eyes =
        renderer.render(view, renderer::Screen::powerwall(), head, kEyeSeparation);
    const double render_s = seconds_since(t_render);

    // 6. Outputs.
    fs::create_directories(o.out);
    const fs::path out(o.out);
    renderer::write_png((out / "left.png").string(), eyes.left);
    renderer::write_png((out / "right.png").string(), eyes.right);
    renderer::write_png((out / "sbs.png").string(), renderer::side_by_side(eyes.left, eyes.right));
    compute::write_ply((out / "sculpted.ply").string(), carved);
    write_haptics_csv((out / "haptics.csv").string(), recs);

    DemoReport r;
    r.mesh_path = mesh_path;
    r.resolution = o.resolution;
    r.lattice = lattice;
    r.transform = to_world;
    r.volume_mesh_m3 = volume_mesh;
    r.volume_dexel_m3 = volume_dexel;
    r.volume_after_m3 = volume_after;
    r.edges = edges;
    r.vertices = carved.positions.size();
    r.triangles = carved.triangles.size();
    r.records = &recs;
    r.loop = loop.stats();
    r.sculpt = &sculpt.stats();
    r.tiles_initial = tiles_initial;
    r.tiles_total = model.tiles.count();
    r.scan_s = scan_s;
    r.contour_s = contour_s;
    r.session_s = session_s;
    r.render_s = render_s;
    r.tool_radius_m = o.tool_radius_m;
    r.stiffness_n_per_m = kStiffness;
    r.max_force_n = profile.max_force_n;
    r.device = gpu_ctx.device_name();
    r.eye_strategy = renderer.strategy_note();
    r.validation_messages = gpu_ctx.validation_messages();
    r.wall_s = seconds_since(t_start);
    write_report_json((out / "report.json").string(), r);
    print_summary(r, o.out);
}

}  // namespace tridex::app
