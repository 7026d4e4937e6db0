// app/demo.cpp - `tridex demo`: wires the three threads of DESIGN.md around one scripted stroke.
#include "app/demo.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "app/session.hpp"
#include "app/stroke.hpp"
#include "core/error.hpp"
#include "devices/simulated_device.hpp"
#include "haptics/haptic_loop.hpp"

#ifndef TRIDEX_SOURCE_ASSETS
#define TRIDEX_SOURCE_ASSETS "assets"
#endif

namespace tridex::app {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// World frame (DESIGN.md): metres, y up, the PowerWall screen in the z = 0 plane facing +z. The
// workpiece floats 0.3 m in front of the wall, within the designer's reach (head pose: session.cpp).
const Vec3 kWorkpieceCentre{0.0, 0.0, 0.3};
constexpr double kStiffness = 700.0;      // N/m: 0.7 N/mm, stable on Omni-class devices at 1 kHz
constexpr double kDamping = 0.5;          // N*s/m along the contact normal

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
    if (!(o.seconds >= 0.5 && o.seconds <= 600.0))
        throw Error("--seconds: must be between 0.5 and 600, got " + std::to_string(o.seconds));
    if (!(o.tool_radius_m >= 0.0005 && o.tool_radius_m <= 0.25 * o.stock_m))
        throw Error("--tool-radius-mm: must be between 0.5 mm and a quarter of the stock (" +
                    std::to_string(250.0 * o.stock_m) + " mm), got " + std::to_string(o.tool_radius_m * 1e3));
    check_image_size(o.width, o.height);

    // 1. Workpiece: load, place in the world, scan-convert into the tri-dexel model.
    Workpiece wp = prepare_workpiece(o.mesh.empty() ? default_mesh_path() : o.mesh, o.resolution, o.stock_m,
                                     kWorkpieceCentre);

    // 2. The stroke and the simulated device that follows it.
    StrokeParams sp;
    sp.duration_s = o.seconds;
    sp.tool_radius_m = o.tool_radius_m;
    const StrokePlan plan = plan_stroke(wp.model, sp);
    const devices::DeviceProfile profile = devices::DeviceProfile::phantom_omni();
    std::vector<Vec3> device_path;
    for (const Vec3& w : plan.world_m) device_path.push_back(w - plan.centre_m);
    devices::SimulatedDevice device(profile, devices::ScriptedPath(plan.t_s, device_path), devices::SimulatedHandParams{},
                                    1e-3);

    // 3. The haptic loop (device workspace centred on the pass) and the sculpt thread. The session lasts
    // the stroke's length in device time (one simulated step per tick), so an overloaded machine that
    // skips deadlines still plays the whole stroke; wall time is only a safety net.
    haptics::HapticLoopConfig cfg;
    cfg.period_s = 1e-3;
    cfg.contact = haptics::ContactParams{kStiffness, kDamping, o.tool_radius_m};
    cfg.device_to_world.position = plan.centre_m;
    cfg.op = ToolOp::kSubtract;
    cfg.max_ticks = static_cast<std::size_t>(o.seconds * 1000.0 * 1.5) + 1000;
    const std::size_t ticks = static_cast<std::size_t>(std::llround(o.seconds / cfg.period_s));
    const SessionRun run = run_session(wp, device, cfg, ticks, 3.0 * o.seconds + 10.0, plan.world_m.front());

    // 4. Images, mesh, per-tick haptics and the report.
    write_session_outputs(OutputOptions{o.out, o.width, o.height, o.validate}, wp, run, cfg, profile, t_start);
}

}  // namespace tridex::app
