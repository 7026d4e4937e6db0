// app/session/runtime/session_runtime.cpp - a session's threads from its spec.
#include "app/session/runtime/session_runtime.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app/scene/session_memory.hpp"
#include "app/scene/workpiece_list.hpp"
#include "app/session/runtime/sculpt_setup.hpp"
#include "compute/tools/model_resample.hpp"
#include "app/scene/tool_mesh.hpp"
#include "app/support/crash_report.hpp"
#include "app/support/memory.hpp"
#include "app/support/progress.hpp"
#include "app/support/stop_signal.hpp"
#include "compute/mesh/mesh_io.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/volume.hpp"
#include "compute/model/workpiece.hpp"
#include "core/error.hpp"
#include "devices/net/net_device.hpp"
#include "gpu/context.hpp"
#include "haptics/tool_points.hpp"

namespace tridex::app {

namespace {

// The workpiece the tool carves: the chosen one, else `viewed_target` (the target of the view the render thread
// last took; a newer view would end the one it may still read).
int carving_workpiece(const haptics::HapticLoop& loop, int viewed_target) {
    const int k = loop.chosen_workpiece();
    return k < 0 ? viewed_target : k;
}

// The chaos tests' fault (docs/benchmarks/chaos.md): TRIDEX_FAULT_KILL_AT_SAMPLE=K kills the session with SIGKILL
// right after its K-th tool sample (HapticLoopConfig::fault_kill_at_sample); 0 or unset: never.
std::uint64_t fault_kill_at_sample() {
    const char* v = std::getenv("TRIDEX_FAULT_KILL_AT_SAMPLE");
    if (!v || !*v) return 0;
    char* end = nullptr;
    errno = 0;
    const unsigned long long k = std::strtoull(v, &end, 10);
    if (*end != '\0' || errno != 0 || v[0] == '-')
        throw Error(std::string("TRIDEX_FAULT_KILL_AT_SAMPLE: must be a whole number of samples, got '") + v + "'");
    return k;
}

using Clock = std::chrono::steady_clock;
constexpr std::size_t kRingCapacity = 1 << 16;  // tool samples: 65 s of ticks

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

bool gpu_contour_default(const gpu::Context& context, std::string& reason) {
    if (context.properties().deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU) return true;
    reason = "the Vulkan device (" + context.device_name() +
             ") is a CPU implementation, where the CPU contour is faster; --gpu-contour forces GPU contouring";
    return false;
}

BackendRequest backend_request(const SculptOptions& s) {
    BackendRequest r;
    r.mode = backend_mode(s.cpu, s.gpu);
    r.gpu_contour = s.gpu_contour;
    r.gpu_clay = s.gpu_clay;
    check_backend_request(r);
    return r;
}

SessionRuntime::SessionRuntime(const SessionSpec& spec, Workpiece workpiece, std::unique_ptr<devices::HapticDevice> device,
                               const Vec3& start_m, const RuntimeOptions& o)
    : SessionRuntime(spec, std::move(workpiece), {}, std::move(device), start_m, o) {}

SessionRuntime::SessionRuntime(const SessionSpec& spec, Workpiece workpiece, std::vector<Workpiece> more,
                               std::unique_ptr<devices::HapticDevice> device, const Vec3& start_m, const RuntimeOptions& o)
    : spec_(spec), wp_(std::move(workpiece)), device_(std::move(device)),
      mesh_tool_(spec.tool.kind == ToolKind::kMesh ? make_session_mesh_tool(spec.tool_mesh_path, spec.tool_size_m) : nullptr),
      cfg_(loop_config(spec, o.max_ticks, tool_mesh())) {
    if (!device_) throw Error("SessionRuntime: no haptic device");
    if (more.size() != spec_.more_workpieces.size())
        throw Error("SessionRuntime: " + std::to_string(more.size()) + " further workpieces for a spec of " +
                    std::to_string(spec_.more_workpieces.size()));
    more_wp_ = std::move(more);
    cfg_.tool_schedule = o.loop.tool_schedule;
    cfg_.pose_schedule = o.loop.pose_schedule;
    cfg_.engage_mask |= o.loop.engage_mask;
    cfg_.free_run = o.loop.free_run;
    configure_net_device(*device_, cfg_);  // local rendering: the server's loop gets the contact parameters
    // Connect and calibrate before the slow set-up, so a device that cannot tells the user at once; forces are
    // enabled by the haptic loop when it starts and disabled when it stops.
    device_->open();
    try {
        device_->home();
        build(start_m, o);
    } catch (...) {
        device_->close();
        throw;
    }
}

void SessionRuntime::build(const Vec3& start_m, const RuntimeOptions& o) {
    if (!spec_.references.empty()) {
        ProgressReporter::Step step = progress().step("building the reference objects' distance fields");
        references_ = prepare_references(spec_.references);
        for (const PreparedReference& r : references_) cfg_.reference_objects.push_back(r.object);
    }
    choose_contour(o);
    contourer_ = std::make_unique<compute::Contourer>(wp_.model);
    const auto t0 = Clock::now();
    // Coarse first: the sculpt thread contours the tiles after a first mesh of coarse group levels (use_tile_lod).
    coarse_first_ = o.sculpt.coarse_first && o.publish_meshes && o.mesh_form == MeshForm::kTiles &&
                              o.sculpt.tile_lod && !gpu_contour_ &&
                              compute::coarse_groups_apply(wp_.model.lattice.cells, o.sculpt.coarse_groups_from_cells);
    if (!coarse_first_) {
        const StopEndsSetUp set_up("contouring the workpiece");  // no force sent, no work to keep yet
        ProgressReporter::Step step = progress().step("contouring the workpiece");
        if (gpu_contour_) {
            tiles_initial_ = gpu_contour_->update_all();
            wp_.model.clear_dirty();
        } else {
            tiles_initial_ = contourer_->update(wp_.model, step.fn());
        }
    }
    contour_s_ = seconds_since(t0);
    ring_ = std::make_unique<SpscRing<ToolSample>>(kRingCapacity);
    sculpt_ = std::make_unique<SculptThread>(wp_.model, *contourer_, *ring_, surface_, start_m, cfg_.contact.tool_radius_m,
                                             haptics::max_point_distance_m(cfg_.tool_points));
    booleans_.backend->set_clay_group_sweeps(spec_.clay_group_sweeps);  // the grouping decides the model
    sculpt_->use_backend(*booleans_.backend);
    if (!o.sculpt.journal.empty()) {
        journal_ = std::make_unique<compute::JournalWriter>(o.sculpt.journal, spec_to_json(spec_));
        set_crash_note("the session's journal is " + o.sculpt.journal + ": `tridex recover " + o.sculpt.journal +
                       "` rebuilds the model up to its last complete record");
        sculpt_->use_journal(*journal_);
        // Samples the sculpt thread has not applied yet are journalled as they leave the haptic loop.
        intake_ = std::make_unique<compute::JournalIntake>(*journal_);
        cfg_.sample_tap = &intake_->ring();
        use_session_checkpoints(*sculpt_, o.sculpt.journal, o.sculpt.checkpoint_s, wp_.to_world, spec_);
    }
    set_session_sculpting(*sculpt_, spec_, o.publish_meshes ? SessionKind::kLive : SessionKind::kBatch);
    if (o.sculpt.follow_marks) sculpt_->follow_marks(*o.sculpt.follow_marks);
    for (compute::ToolStreamSink* s : o.sculpt.streams) sculpt_->use_stream(*s);
    for (const auto& setup : o.sculpt.sculpt_setup) setup(*sculpt_);
    use_session_saver(*sculpt_, o.sculpt.save_path, wp_.to_world, spec_);
    if (mesh_tool_) sculpt_->use_mesh_tools({mesh_tool_});  // ToolShape::mesh_id 0
    if (gpu_contour_) sculpt_->use_gpu_contour(*gpu_contour_);
    if (o.publish_meshes && (o.mesh_form == MeshForm::kTiles || gpu_contour_) && o.sculpt.tile_lod) {
        compute::LodWorkerOptions lod;
        lod.lod.cell_m = wp_.model.lattice.cell_m;
        lod.coarse_groups_from_cells = o.sculpt.coarse_groups_from_cells;
        lod.coarse_first = coarse_first_;
        lod.stroke_coarse = o.sculpt.stroke_coarse;
        sculpt_->use_tile_lod(lod);
        sculpt_->coarse_first_on_lattice_change(o.sculpt.coarse_first);
    }
    if (o.publish_meshes) sculpt_->publish_mesh_to(meshes_, o.mesh_interval_s, o.mesh_form, &sculpted_changes_);
    // A device that renders contact next to itself (net, local rendering) gets each snapshot from the sculpt thread.
    if (const auto* net = dynamic_cast<const devices::net::NetDevice*>(device_.get());
        net && net->mode() == devices::net::RenderingMode::kLocal)
        sculpt_->observe_surface([dev = device_.get()](const ActiveSurface& s) { dev->observe_surface(s); });
    if (!o.sculpt.stream_recording.empty()) {
        tick_stream_ = std::make_unique<TickStream>(spec_, o.sculpt.stream_recording);
        cfg_.record_stream = &tick_stream_->ring();
    }
    cfg_.fault_kill_at_sample = fault_kill_at_sample();
    if (more_wp_.empty()) {
        loop_ = std::make_unique<haptics::HapticLoop>(*device_, surface_, *ring_, cfg_);
    } else {
        build_more(start_m, o);
        std::vector<haptics::LoopWorkpiece> pieces{
            {&surface_, ring_.get(), cfg_.sample_tap, cfg_.workpiece_pose, wp_.model.lattice.bounds()}};
        for (const auto& m : more_) pieces.push_back(m->loop_workpiece());
        loop_ = std::make_unique<haptics::HapticLoop>(*device_, pieces, cfg_);
    }
    build_undo_order();
    if (loop_->stiffness_capped()) {  // the report and the views show what the device renders
        std::fprintf(stderr,
                     "tridex: contact stiffness cut to %.0f N/m (world): the %s renders at most %.0f N/m at a workspace "
                     "gain of %g\n",
                     loop_->config().contact.stiffness_n_per_m, device_->profile().name.c_str(),
                     device_->profile().max_stiffness_n_per_m, cfg_.workspace_scale);
        cfg_.contact.stiffness_n_per_m = loop_->config().contact.stiffness_n_per_m;
        cfg_.contact.materials = loop_->config().contact.materials;
    }
}

void SessionRuntime::build_more(const Vec3& start_m, const RuntimeOptions& o) {
    for (std::size_t k = 1; k <= more_wp_.size(); ++k) {
        SessionSpec one = spec_for_workpiece(spec_, k);
        MoreWorkpieceOptions mo;
        mo.journal = path_for_workpiece(o.sculpt.journal, k);
        mo.checkpoint_s = o.sculpt.checkpoint_s;
        mo.save_path = path_for_workpiece(o.sculpt.save_path, k);
        mo.kind = o.publish_meshes ? SessionKind::kLive : SessionKind::kBatch;
        mo.publish_meshes = o.publish_meshes;
        mo.mesh_interval_s = o.mesh_interval_s;
        mo.sculpted_changes = &sculpted_changes_;
        if (k - 1 < o.loop.more_follow_marks.size()) mo.follow_marks = o.loop.more_follow_marks[k - 1];
        else if (o.sculpt.follow_marks) mo.follow_marks = std::vector<SculptMark>{};  // a replay: no idle closes
        mo.mesh_tool = mesh_tool_;
        const Vec3 start_model = workpiece_pose(one).inverse().apply(start_m);
        more_.push_back(std::make_unique<MoreWorkpiece>(std::move(one), std::move(more_wp_[k - 1]), start_model,
                                                        cfg_.contact.tool_radius_m,
                                                        haptics::max_point_distance_m(cfg_.tool_points), mo));
    }
    more_wp_.clear();
}

void SessionRuntime::build_undo_order() {
    placements_ = std::make_unique<PlacementHistory>(
        [this](int k, const Pose& pose) { return loop_->set_workpiece_pose(k, pose); });
    std::vector<UndoLane> lanes{{[this] { return sculpt_->live().undo_times; }, [this] { return sculpt_->passes(); },
                                 [this](SculptRequest r) { return sculpt_->request(r); }, 2,
                                 [this] { return sculpt_->requests_held(); }}};
    for (const auto& m : more_) {
        MoreWorkpiece* p = m.get();
        lanes.push_back({[p] { return p->sculpt_live().undo_times; }, [p] { return p->sculpt_passes(); },
                         [p](SculptRequest r) { return p->request(r); }, 2, [p] { return p->sculpt_requests_held(); }});
    }
    lanes.push_back({[this] { return placements_->times(); }, [this] { return loop_->pose_changes_taken(); },
                     // While the hand holds a workpiece its pose is the hand's: a placement's undo is refused then.
                     [this](SculptRequest r) { return !viewed_placing_ && placements_->request(r); }, 1});
    undo_router_ =
        std::make_unique<UndoRouter>(std::move(lanes), [this] { return carving_workpiece(*loop_, viewed_target_); });
}

MoreWorkpiece& SessionRuntime::more_workpiece(std::size_t k) {
    if (k < 1 || k > more_.size())
        throw Error("workpiece " + std::to_string(k) + ": the session's further workpieces are 1.." +
                    std::to_string(more_.size()));
    return *more_[k - 1];
}

bool SessionRuntime::request(SculptRequest r) {
    if (r == SculptRequest::kUndo || r == SculptRequest::kRedo) return undo_router_->ask(r);
    if (more_.empty()) return sculpt_->request(r);
    if (r == SculptRequest::kSave) {
        bool all = sculpt_->request(r);
        for (const auto& m : more_) all = m->request(r) && all;
        return all;
    }
    const int k = carving_workpiece(*loop_, viewed_target_);
    return k <= 0 || static_cast<std::size_t>(k) > more_.size() ? sculpt_->request(r) : more_[k - 1]->request(r);
}

void SessionRuntime::choose_contour(const RuntimeOptions& o) {
    const SculptOptions& s = o.sculpt;
    const BackendRequest request = backend_request(s);  // refuses flags that disagree before any Vulkan work
    const bool cpu_forced = request.mode == BackendMode::kCpu;
    gpu::Context* shared = o.render_context;
    if (!shared && !cpu_forced) {
        // Demo and replay: one Context for the Booleans, the GPU contour and the final render.
        gpu::ContextOptions gopt;
        gopt.validation = s.validate;
        try {
            own_context_.emplace(gpu::Context::create(gopt));
            shared = &*own_context_;
        } catch (const Error&) {
            // make_boolean_backend below says why the CPU runs
        }
    }
    // A live renderer's Context is shared only for GPU contouring: on lavapipe one Context is one queue, so GPU
    // Booleans on it would wait behind the frame in flight.
    if (s.cpu_contour)
        contour_reason_ = "--cpu-contour given";
    else if (o.publish_meshes && o.mesh_form == MeshForm::kWhole)
        contour_reason_ = "the whole-mesh form (--no-tiles) needs the CPU mesh";
    else if (!shared)
        contour_reason_ = cpu_forced ? "the Booleans run on the CPU" : "no Vulkan Context for the contour";
    else if (!cpu_forced && !s.gpu_contour) {
        std::string why;  // a CPU implementation of Vulkan: the CPU contour is faster there
        if (!gpu_contour_default(*shared, why)) contour_reason_ = why;
    }
    const bool share = shared && (own_context_ || contour_reason_.empty());
    booleans_ = share ? make_boolean_backend_on(wp_.model, request, *shared)
                      : make_boolean_backend(wp_.model, request, s.validate);
    if (!contour_reason_.empty()) return;
    if (!booleans_.backend->gpu_slabs()) {
        contour_reason_ = "the Booleans run on the CPU";
        return;
    }
    try {
        gpu_contour_ = std::make_unique<GpuContourShare>(*shared, *booleans_.backend->gpu_slabs(), wp_.model);
    } catch (const Error& e) {
        contour_reason_ = std::string("the device cannot contour: ") + e.what();
        // CPU contouring after all: with a live renderer the Booleans get a Context of their own again, so they
        // do not wait behind the frames (nothing has been sculpted yet).
        if (!own_context_) booleans_ = make_boolean_backend(wp_.model, request, s.validate);
    }
}

SessionRuntime::~SessionRuntime() {
    try {
        stop();
    } catch (...) {  // a sculpt failure nobody asked about: the owner is going away
    }
    if (device_) device_->close();  // never started: it was opened and homed by the constructor
    if (journal_) set_crash_note("");
}

void SessionRuntime::start() {
    if (started_) return;
    started_ = true;
    t_start_ = Clock::now();
    sculpt_->start();
    for (const auto& m : more_) m->start();
    if (intake_) intake_->start();
    if (tick_stream_) tick_stream_->start();
    loop_->start();
}

void SessionRuntime::stop() {
    if (!started_ || stopped_) return;
    stopped_ = true;
    // Undos and redos still waiting for their turn are sent while the sculpt threads still run.
    if (!undo_router_->drain(std::chrono::milliseconds(3000)))
        std::fprintf(stderr, "tridex: undo or redo requests dropped at the end: a sculpt thread did not take them\n");
    loop_->stop();  // zero force, device disabled
    if (tick_stream_) tick_stream_->stop();  // every tick the loop pushed is in the temporary file
    session_s_ = seconds_since(t_start_);
    device_->close();
    // Each sculpt thread drains its ring, publishes its last surface and syncs its journal; a failure is rethrown.
    stop_sculpting(*sculpt_, intake_.get(), journal_.get());
    for (const auto& m : more_) m->stop();
}

SessionRuntime::FinalMesh SessionRuntime::final_mesh() {
    if (started_ && !stopped_) throw Error("SessionRuntime::final_mesh: call stop() first");
    if (gpu_contour_) std::fill(wp_.model.tiles.dirty.begin(), wp_.model.tiles.dirty.end(), std::uint8_t{1});
    contourer_->update(wp_.model);
    return FinalMesh{contourer_->mesh(), contourer_->mesh_materials()};
}

void SessionRuntime::release_gpu_booleans() {
    if (started_ && !stopped_) throw Error("SessionRuntime::release_gpu_booleans: call stop() first");
    if (!gpu_contour_ && booleans_.backend && booleans_.backend->gpu_slabs()) booleans_.backend.reset();
}

std::uint32_t SessionRuntime::sculpt_validation_messages() const {
    return booleans_.backend ? booleans_.backend->validation_messages() : 0u;
}

}  // namespace tridex::app
