// app/run_sculpt.cpp - haptic loop + sculpt thread of a run.
#include "app/run_sculpt.hpp"

#include "core/error.hpp"
#include "haptics/tool_points.hpp"

#include <algorithm>
#include <cmath>

namespace tridex::app {

namespace {
using Clock = std::chrono::steady_clock;
constexpr std::size_t kRingCapacity = 1 << 16;         // tool samples: 65 s of ticks
constexpr std::size_t kMaxRecords = 120000;            // per-tick records kept: 2 minutes at 1 kHz
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace

SculptBackend::SculptBackend(const RunScene& scene, double mesh_interval_s, MeshForm form, const SculptOptions& booleans,
                             gpu::Context* render_context)
    : wp_(prepare_workpiece(scene.mesh_path, scene.resolution, scene.stock_m, scene.centre_m)),
      profile_(devices::DeviceProfile::phantom_omni()) {
    cfg_.period_s = 1e-3;
    cfg_.contact = haptics::ContactParams{scene.stiffness_n_per_m, scene.damping_n_s_per_m, scene.tool_radius_m};
    cfg_.op = ToolOp::kSubtract;
    cfg_.workspace_scale = scene.workspace_scale;
    cfg_.workspace.mode = scene.workspace_mode;

    // The hand's path in device coordinates (the device workspace is centred on the stroke's middle), or,
    // without a stroke, a hand at rest a tool diameter plus a clearance in front of the workpiece (+z).
    std::vector<double> t_s;
    std::vector<Vec3> path;
    Vec3 centre;
    if (scene.has_stroke) {
        const StrokePlan plan = plan_stroke(wp_.model, scene.stroke);
        centre = plan.centre_m;
        t_s = plan.t_s;
        for (const Vec3& w : plan.world_m) path.push_back((w - centre) / scene.workspace_scale);
        start_m_ = plan.world_m.front();
        stroke_ticks_ = static_cast<std::size_t>(std::llround(scene.stroke.duration_s / cfg_.period_s));
    } else {
        const Aabb box = wp_.model.lattice.bounds();
        centre = Vec3(box.centre().x, box.centre().y, box.hi.z + 2.0 * scene.tool_radius_m + 0.01);
        t_s = {0.0};
        path = {Vec3(0.0)};
        start_m_ = centre;
    }
    cfg_.device_to_world.position = centre;
    cfg_.max_ticks = std::min(kMaxRecords, stroke_ticks_ + stroke_ticks_ / 2 + 1000);
    device_ = std::make_unique<devices::SimulatedDevice>(profile_, devices::ScriptedPath(t_s, path),
                                                         devices::SimulatedHandParams{}, cfg_.period_s);

    // The render Context is shared only for GPU contouring: on lavapipe one Context is one queue, so GPU
    // Booleans on it wait behind the frame in flight; with CPU contouring they keep a Context of their own.
    if (booleans.cpu_contour)
        contour_reason_ = "--cpu-contour given";
    else if (form == MeshForm::kWhole)
        contour_reason_ = "the whole-mesh form (--no-tiles) needs the CPU mesh";
    else if (!render_context)
        contour_reason_ = "no render context shared with the sculpt thread";
    else if (!booleans.cpu && !booleans.gpu_contour) {
        std::string why;  // a CPU implementation of Vulkan: the CPU contour is faster there
        if (!gpu_contour_default(*render_context, why)) contour_reason_ = why;
    }
    const bool share = contour_reason_.empty();
    booleans_ = share ? make_boolean_backend_on(wp_.model, booleans.cpu, *render_context)
                      : make_boolean_backend(wp_.model, booleans.cpu, booleans.validate);
    if (share && !booleans_.backend->gpu_slabs()) {
        contour_reason_ = "the Booleans run on the CPU";
    } else if (share) {
        try {
            gpu_contour_ = std::make_unique<GpuContourShare>(*render_context, *booleans_.backend->gpu_slabs(), wp_.model);
        } catch (const Error& e) {
            contour_reason_ = std::string("the device cannot contour: ") + e.what();
            // CPU contouring after all: the Booleans get a Context of their own again, so they do not wait
            // behind the frames (nothing has been sculpted yet).
            booleans_ = make_boolean_backend(wp_.model, booleans.cpu, booleans.validate);
        }
    }
    contourer_ = std::make_unique<compute::Contourer>(wp_.model);
    const auto t0 = Clock::now();
    if (gpu_contour_) {
        tiles_initial_ = gpu_contour_->update_all();
        wp_.model.clear_dirty();
    } else {
        tiles_initial_ = contourer_->update(wp_.model);
    }
    contour_s_ = seconds_since(t0);
    ring_ = std::make_unique<SpscRing<ToolSample>>(kRingCapacity);
    sculpt_ = std::make_unique<SculptThread>(wp_.model, *contourer_, *ring_, surface_, start_m_, cfg_.contact.tool_radius_m,
                                             haptics::max_point_distance_m(cfg_.tool_points));
    sculpt_->use_backend(*booleans_.backend);
    if (gpu_contour_) sculpt_->use_gpu_contour(*gpu_contour_);
    sculpt_->publish_mesh_to(meshes_, mesh_interval_s, form);
    loop_ = std::make_unique<haptics::HapticLoop>(*device_, surface_, *ring_, cfg_);
}

SculptBackend::~SculptBackend() {
    try {
        stop();
    } catch (...) {  // a sculpt failure nobody asked about: the owner is going away
    }
}

void SculptBackend::start() {
    if (started_) return;
    started_ = true;
    t_start_ = Clock::now();
    sculpt_->start();
    loop_->start();
}

void SculptBackend::stop() {
    if (!started_ || stopped_) return;
    stopped_ = true;
    loop_->stop();
    session_s_ = seconds_since(t_start_);
    sculpt_->stop();  // drains the ring, publishes the last mesh; rethrows a failure
}

bool SculptBackend::stroke_done() const {
    if (started_ && !loop_->running()) return true;
    return stroke_ticks_ > 0 && loop_->stats().ticks >= stroke_ticks_;
}

Aabb SculptBackend::start_box_m() const {
    const Vec3 c = cfg_.device_to_world.position;
    return Aabb{profile_.workspace_m.lo * cfg_.workspace_scale + c, profile_.workspace_m.hi * cfg_.workspace_scale + c};
}

}  // namespace tridex::app
