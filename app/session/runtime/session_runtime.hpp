// app/session/runtime/session_runtime.hpp - one sculpting session's threads, built from one SessionSpec: the haptic loop on any
// HapticDevice, the sculpt thread with its Boolean backend and contouring, and the hand-offs to a renderer
// (DESIGN.md, "three threads, one direction of flow"). demo, replay and run all build their sessions here.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/scene/session_spec.hpp"
#include "app/scene/workpiece_source.hpp"
#include "app/session/record/tick_stream.hpp"
#include "app/session/runtime/more_workpiece.hpp"
#include "app/session/runtime/placement_history.hpp"
#include "app/session/runtime/undo_router.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/journal/journal_intake.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/journal/tool_stream.hpp"
#include "compute/model/tridexel.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/gpu_contour_share.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "compute/tools/mesh_tool.hpp"
#include "core/active_surface.hpp"
#include "core/change_signal.hpp"
#include "core/spsc_ring.hpp"
#include "core/tool_sample.hpp"
#include "core/tri_mesh.hpp"
#include "core/triple_buffer.hpp"
#include "devices/haptic_device.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::gpu {
class Context;
}

namespace tridex::app {


/// Where a session sculpts.
struct SculptOptions {
    /// --cpu: the CPU pool whatever the Vulkan device; with neither this nor `gpu`, the device's type decides
    /// (decide_backend: a CPU implementation such as lavapipe sculpts on the CPU pool, a GPU on the compute path).
    bool cpu = false;
    bool validate = false;  ///< Vulkan validation on the sculpting device
    /// --cpu-contour: contour dirty tiles on the CPU even when the Booleans run on the GPU.
    bool cpu_contour = false;
    /// --gpu-contour: contour on the GPU even on a CPU Vulkan implementation (lavapipe), where the CPU
    /// Contourer is faster and is the default (gpu_contour_default()).
    bool gpu_contour = false;
    /// The session journal file (compute/journal/journal_format.hpp): the tool samples the sculpt thread applies,
    /// with spec_to_json(spec) as the session identity; "" = no journal.
    std::string journal;
    /// With a journal: write a checkpoint model ("<journal file name>.checkpoint.tdx" next to it) after this much
    /// wall time (s) of a changing model, between strokes (SculptThread::use_checkpoints); 0 = none.
    double checkpoint_s = 120.0;
    /// Where a save request (SculptRequest::kSave, Ctrl+S in a window) writes the model (.tdx, atomically, on the
    /// sculpt thread); "" = such requests fail with "no save file".
    std::string save_path{};
    /// With per-tile meshes published (RuntimeOptions::mesh_form kTiles, CPU contour): the sculpt thread also
    /// builds each changed tile's levels of detail (SculptThread::use_tile_lod) for the renderer to choose from.
    bool tile_lod = false;
    /// With tile_lod: groups of tiles take their levels from the model read at coarser strides from this many cells
    /// along the model's longest side (compute::LodWorkerOptions::coarse_groups_from_cells; 0 = never).
    int coarse_groups_from_cells = compute::kCoarseGroupsFromCells;
    /// With tile_lod and coarse groups on the CPU contour: no tile is contoured before the session; the first mesh
    /// holds the coarsest group levels and the sculpt thread contours the tiles after it, region by region
    /// (compute::LodWorkerOptions::coarse_first; docs/design/lod.md, "Coarse first at start-up").
    bool coarse_first = true;
    /// With tile_lod and coarse groups on the CPU contour: a stroke's tiles wait while it is open and the coarse levels
    /// over them draw it (compute::LodWorkerOptions::stroke_coarse; docs/design/lod.md, "Strokes drawn coarse").
    bool stroke_coarse = true;
    /// A recording streamed to disk while the session runs (TickStream: no length limit, bounded memory), written to
    /// this path by tick_stream()->finish() after stop(); "" = none (a recording, if any, is written from records()).
    std::string stream_recording{};
    /// --gpu-clay: clay sweeps on the GPU clay kernel even on a CPU Vulkan implementation (lavapipe), where the CPU
    /// reference is faster and is the default (make_boolean_backend).
    bool gpu_clay = false;
    /// A replay: the recorded session's undos, redos and stroke closes at their places in the sample stream
    /// (SculptThread::follow_marks); nullopt (live sessions, recordings without marks) = taken as they come.
    std::optional<std::vector<SculptMark>> follow_marks{};
    /// --gpu: the GPU compute path whatever the Vulkan device's type (with --cpu: refused, backend_mode()).
    bool gpu = false;
    /// Also hands every batch and mark the sculpt thread applies to each of these sinks, in order
    /// (SculptThread::use_stream): a replica of the model elsewhere follows each (a cluster's render ranks, a shared
    /// session's joiners). Each must outlive the session's threads.
    std::vector<compute::ToolStreamSink*> streams{};
    /// Called with the sculpt thread after it is made and set up, before it starts, in order: a companion wires what it
    /// needs (a shared session's site intake and refusals, SculptThread::use_site_intake, follow_host). Each may throw
    /// tridex::Error, which fails the session's set-up.
    std::vector<std::function<void(SculptThread&)>> sculpt_setup{};
};

/// What `s` asks of the sculpting backend (its --cpu, --gpu, --gpu-contour and --gpu-clay), for decide_backend.
/// Throws tridex::Error when --cpu and --gpu are both set, or --cpu with --gpu-contour or --gpu-clay.
BackendRequest backend_request(const SculptOptions& s);

/// Whether GPU contouring is the default on `context`'s device: true for a real GPU; false for a CPU
/// implementation of Vulkan (VK_PHYSICAL_DEVICE_TYPE_CPU, e.g. Mesa lavapipe), where the GPU contour costs
/// more than the CPU Contourer and, sharing one queue with the renderer, limits a live session to one sculpt
/// step per frame. `reason` gets the why when false.
bool gpu_contour_default(const gpu::Context& context, std::string& reason);

/// What a replay adds to loop_config(spec) so that its samples carry what the recorded session's carried.
struct LoopOverrides {
    /// The op, material and tool changes of the recorded ticks (keys at the desk), by device time.
    std::vector<haptics::ToolChange> tool_schedule{};
    /// Button bits that engage the tool, ORed into the loop's engage_mask (a recorded mouse session's left
    /// button, mouse_buttons::kEngage, when the replay device stands in for the mouse).
    std::uint32_t engage_mask = 0;
    /// Run the loop free (HapticLoopConfig::free_run): a replay that draws no window, as fast as the sculpting goes,
    /// with the paced replay's samples and model. false: ticks paced at period_s, as the session ran.
    bool free_run = false;
    /// The recording's ticks (a replay), against which the session's progress is told; 0: not a replay.
    std::size_t recorded_ticks = 0;
    /// A replay of several workpieces: the recorded marks of each further workpiece (index k-1 for workpiece k;
    /// SculptThread::follow_marks); empty = taken as they come.
    std::vector<std::vector<SculptMark>> more_follow_marks{};
    /// The recorded pose sets (placements undone and redone), repeated at their ticks (HapticLoopConfig::pose_schedule).
    std::vector<haptics::PoseChange> pose_schedule{};
};

/// How a SessionRuntime places its GPU work and hands its surface over.
struct RuntimeOptions {
    SculptOptions sculpt;  ///< CPU or GPU Booleans and contouring, validation
    /// A live renderer's Context (tridex run). GPU contouring draws from buffers on it, so the Booleans run on
    /// it when the dirty tiles are contoured on the GPU; otherwise they keep a Context of their own and do not
    /// wait behind the frames. nullptr (demo, replay: the picture is drawn after the session): the runtime makes
    /// one Context for the Booleans, the GPU contour and the final render (context()).
    gpu::Context* render_context = nullptr;
    /// Hand the contoured surface to a live renderer (latest_mesh()) at most once per mesh_interval_s (s), in
    /// mesh_form; false: no mesh hand-off (the surface is read after stop(), final_mesh()).
    bool publish_meshes = false;
    MeshForm mesh_form = MeshForm::kTiles;
    double mesh_interval_s = 1.0 / 60.0;
    std::size_t max_ticks = 0;  ///< haptic tick records preallocated (recording stops when full)
    LoopOverrides loop{};       ///< replay additions to the loop's configuration
};

/// One session's threads: the HapticLoop on `device` configured by loop_config(spec), the SculptThread applying
/// the tool samples' swept volumes to the workpiece on the Boolean backend (GPU or CPU), publishing the active
/// surface for the loop first and then re-contouring the dirty tiles (GPU or CPU), and the latest-value
/// hand-offs a renderer reads. The model is a pure function of the device samples: the same samples give the
/// same model whatever the backend and timing. Not movable (the threads hold references into it); one render
/// thread may read latest_view() / latest_mesh().
class SessionRuntime {
public:
    /// Prepares everything (backend and Contexts, the initial contour, the loop configuration) without starting
    /// threads. Opens and homes `device` first (HapticDevice::open, home); the haptic loop enables its forces
    /// while it runs, and stop() closes it. `spec` must have device_origin_m set; start_m (world m) centres the
    /// first active-surface snapshot. Throws tridex::Error for a bad spec (loop_config), a device that cannot
    /// open or home (closed again), a model that does not fit the GPU, or a device whose profile the loop
    /// refuses. A mesh tool (spec.tool kMesh) is loaded from spec.tool_mesh_path (app/scene/tool_mesh.hpp) and handed to
    /// the sculpt thread (SculptThread::use_mesh_tools; the GPU backend takes its dexels with each batch).
    SessionRuntime(const SessionSpec& spec, Workpiece workpiece, std::unique_ptr<devices::HapticDevice> device,
                   const Vec3& start_m, const RuntimeOptions& options);
    /// A session of several workpieces: `more` holds the workpieces of spec.more_workpieces, in order
    /// (prepare_more_workpieces), each sculpted beside the first by the same loop (MoreWorkpiece: its own journal at
    /// path_for_workpiece(options.sculpt.journal, k), its save at path_for_workpiece(options.sculpt.save_path, k), its
    /// replay marks from options.more_follow_marks). Throws tridex::Error as the constructor above, and when `more`
    /// does not match spec.more_workpieces in number.
    SessionRuntime(const SessionSpec& spec, Workpiece workpiece, std::vector<Workpiece> more,
                   std::unique_ptr<devices::HapticDevice> device, const Vec3& start_m, const RuntimeOptions& options);
    /// Stops the threads if they run (errors of the sculpt thread are then dropped: call stop() to see them).
    ~SessionRuntime();
    SessionRuntime(const SessionRuntime&) = delete;
    SessionRuntime& operator=(const SessionRuntime&) = delete;

    /// Starts the sculpt thread, then the haptic loop. Once only; later calls do nothing.
    void start();
    /// Stops the haptic loop (zero force to the device, which is disabled and closed), then the sculpt thread,
    /// which drains every sample, publishes the last surface and syncs the journal, which is then closed.
    /// Rethrows a sculpt-thread failure. Idempotent.
    void stop();
    /// Asks the sculpt thread to undo, redo or close the open stroke (SculptThread::request); one thread (the
    /// window's) may call it. False when the request queue is full.
    /// An undo takes back the newest step of the session and a redo brings back the one undone last, whichever
    /// workpiece's stroke or placement it was (UndoRouter, PlacementHistory; a request may wait a few milliseconds
    /// for the one before it, sent by poll_device_frame() or stop()). With several workpieces, a stroke close or
    /// coarseness change goes to the workpiece the tool carves
    /// (the chosen one, else the target of the view latest_view() last returned: this call never takes a newer view,
    /// which would end the one its caller may still read), and a save to every workpiece.
    bool request(SculptRequest r);
    /// How many workpieces the session sculpts (1 + spec().more_workpieces.size()).
    std::size_t workpiece_count() const { return 1 + more_.size(); }
    /// The k-th further workpiece (k = 1..workpiece_count()-1); throws tridex::Error for another k.
    MoreWorkpiece& more_workpiece(std::size_t k);
    /// Chooses the workpiece the tool carves (HapticLoop::choose_workpiece: 0..workpiece_count()-1, -1 automatic);
    /// any thread. False for an index out of range.
    bool choose_workpiece(int index) { return loop_->choose_workpiece(index); }
    /// The chosen workpiece (-1: automatic, the touched or the nearest).
    int chosen_workpiece() const { return loop_->chosen_workpiece(); }
    /// Changes the Boolean the tool applies from now on (HapticLoop::set_tool_op, with the material chosen last); any
    /// thread. The sculpt thread closes the stroke at the change.
    void set_tool_op(ToolOp op) { loop_->set_tool_op(op, loop_->tool_material()); }
    /// Changes the material union adds and paint sets from now on (1..kMaxMaterialId; others ignored), keeping the
    /// Boolean; one thread (the window's). The sculpt thread closes the stroke at the change, and a recording keeps it.
    void set_material(std::uint8_t id) {
        if (id >= 1 && id <= kMaxMaterialId) loop_->set_tool_op(loop_->tool_op(), id);
    }
    /// The material union adds and paint sets now (HapticLoop::tool_material; any thread).
    std::uint8_t material() const { return loop_->tool_material(); }
    /// The open pie menu as the haptic loop feels it (HapticLoop::set_menu: no carving while open, a detent at
    /// each slice border); one thread (the window's).
    void set_menu(const haptics::MenuDetent& menu) { loop_->set_menu(menu); }
    /// The Boolean the tool applies now (HapticLoop::tool_op; any thread).
    ToolOp tool_op() const { return loop_->tool_op(); }
    /// Changes the symmetry the tool's samples carry from now on (HapticLoop::set_symmetry; the sculpt thread closes
    /// the stroke at the change and applies the copies). Throws tridex::Error for a symmetry that is not valid.
    void set_symmetry(const Symmetry& s) { loop_->set_symmetry(s); }
    /// The symmetry the samples carry now.
    Symmetry symmetry() const { return loop_->symmetry(); }
    /// Changes the tool's size from now on (HapticLoop::set_tool: the configured kind at another size; one
    /// thread, the window's). False when the loop refuses it (another kind, a mesh tool, a bad size).
    bool set_tool(const ToolShape& tool) { return loop_->set_tool(tool); }
    /// Saves so far and whether the journal and checkpoints still work (SculptThread::save_status; any thread).
    SaveStatus save_status() const { return sculpt_->save_status(); }
    /// False once the haptic loop ended by itself (device lost, replay over) or was stopped.
    bool loop_running() const { return loop_->running(); }
    /// True once start() was called.
    bool started() const { return started_; }
    /// The loop's counters (any time).
    haptics::LoopStats loop_stats() const { return loop_->stats(); }
    /// The loop's pose sets taken this session (HapticLoop::pose_changes: placements undone and redone); after stop().
    const std::vector<haptics::PoseChange>& pose_changes() const { return loop_->pose_changes(); }
    /// One record per tick (at most RuntimeOptions::max_ticks); valid after stop().
    const std::vector<haptics::TickRecord>& records() const { return loop_->records(); }
    /// The sculpt thread's live counters (SculptThread::live: steps, undo history bytes, step times; any thread).
    SculptLive sculpt_live() const { return sculpt_->live(); }
    /// The sculpt thread's counters; valid after stop().
    const SculptStats& sculpt_stats() const { return sculpt_->stats(); }
    /// The newest LoopView (one render thread).
    const haptics::LoopView& latest_view() {
        const haptics::LoopView& v = loop_->latest_view();
        viewed_target_ = v.target_workpiece;
        placements_->observe(v.placement, v.samples);  // a placement that ended becomes an undo step
        viewed_placing_ = v.placing;
        return v;
    }
    /// The frame loop's once-per-frame call on the window's thread: the device polls an input API that must run
    /// there (HapticDevice::poll_on_main_thread: GLFW's gamepads). Its buttons reach the loop's view
    /// (LoopView::buttons), which the session's bindings read (app/actions/bindings.hpp).
    /// It also sends the undos and redos waiting for their turn (UndoRouter::pump).
    void poll_device_frame() {
        device_->poll_on_main_thread();
        undo_router_->pump();
    }
    /// The newest contoured surface (publish_meshes; one render thread); valid until the next call.
    const MeshFrame& latest_mesh() { return meshes_.latest(); }
    /// Counts the published surfaces that carry a sculpted change (MeshFrame::oldest_sample_s set): a paced
    /// renderer waits on it to start a frame as soon as a change is in (publish_meshes; any thread).
    const ChangeSignal& sculpted_changes() const { return sculpted_changes_; }

    /// The carved model as one closed mesh (world m) with a material id per vertex.
    struct FinalMesh {
        TriMesh mesh;
        std::vector<std::uint8_t> materials;
    };
    /// After stop(): the CPU Contourer's mesh of the whole final model (on the GPU contour path every tile is
    /// contoured again on the CPU), so demo, replay and run export the same bytes for the same model. Throws
    /// tridex::Error while the threads run.
    FinalMesh final_mesh();
    /// After stop(), without a GPU contour: frees the GPU Booleans' model (large host memory on lavapipe) so a
    /// final render on context() has room. Nothing changes on the GPU contour path.
    void release_gpu_booleans();

    const SessionSpec& spec() const { return spec_; }                     ///< what decides the model
    const haptics::HapticLoopConfig& config() const { return cfg_; }      ///< loop_config(spec)
    /// A mesh tool's mesh in the tool frame (m; app/scene/tool_mesh.hpp), the one the Booleans sweep and the contact
    /// points lie on; nullptr for a ball or flat end.
    const TriMesh* tool_mesh() const { return mesh_tool_ ? &mesh_tool_->mesh() : nullptr; }
    /// The spec's reference objects as loaded (own-frame meshes, distance fields, poses), in the spec's order; the
    /// haptic loop feels them (HapticLoopConfig::reference_objects).
    const std::vector<PreparedReference>& references() const { return references_; }
    const devices::DeviceProfile& profile() const { return device_->profile(); }  ///< the device's
    /// The device's status channel (lifecycle state, faults, gated and clamped writes); any thread.
    devices::DeviceStatus device_status() const { return device_->status(); }
    /// The driver's transport measurements (read after stop()).
    devices::DeviceLinkStats device_link() const { return device_->link_stats(); }
    const Workpiece& workpiece() const { return wp_; }                    ///< the model (read after stop())
    const BackendChoice& booleans() const { return booleans_; }           ///< where the Booleans run and why
    /// The GPU contour a renderer draws (GpuContourShare::lock_frame), or nullptr when contouring on the CPU.
    GpuContourShare* gpu_contour() { return gpu_contour_.get(); }
    /// The Context the runtime made for the final render (render_context == nullptr and a Vulkan device);
    /// nullptr otherwise.
    gpu::Context* context() { return own_context_ ? &*own_context_ : nullptr; }
    /// "gpu" or "cpu": where dirty tiles are contoured.
    std::string contour_path() const { return gpu_contour_ ? "gpu" : "cpu"; }
    /// Why contouring runs on the CPU ("" on the GPU path), e.g. "--cpu-contour given".
    const std::string& contour_reason() const { return contour_reason_; }
    std::size_t tiles_initial() const { return tiles_initial_; }  ///< tiles contoured before the session
    double contour_s() const { return contour_s_; }               ///< initial contouring wall time, s
    /// True when no tile was contoured before the session: the sculpt thread publishes coarse group levels first
    /// and contours the tiles after them (SculptOptions::coarse_first).
    bool coarse_first() const { return coarse_first_; }
    double session_s() const { return session_s_; }               ///< start() .. stop() wall time, s
    /// The journal's counters and error (SculptOptions::journal); nullptr without a journal. Read after stop().
    const compute::JournalStats* journal_stats() const { return journal_ ? &journal_->stats() : nullptr; }
    /// The recording streamed while the session runs (SculptOptions::stream_recording), or nullptr. After stop(),
    /// finish() writes it.
    TickStream* tick_stream() { return tick_stream_.get(); }
    /// Vulkan validation messages of the Booleans on a Context of their own (0 when they share one).
    std::uint32_t sculpt_validation_messages() const;

private:
    void build(const Vec3& start_m, const RuntimeOptions& o);
    void build_more(const Vec3& start_m, const RuntimeOptions& o);
    // The one undo order: a lane per workpiece's sculpt thread and one for the placements (after loop_ is built).
    void build_undo_order();
    void choose_contour(const RuntimeOptions& o);

    SessionSpec spec_;
    Workpiece wp_;
    std::unique_ptr<devices::HapticDevice> device_;
    std::shared_ptr<const compute::MeshTool> mesh_tool_;  // kMesh: the session's one mesh tool (mesh_id 0); before cfg_
    haptics::HapticLoopConfig cfg_;
    std::vector<PreparedReference> references_;  // the spec's reference objects, loaded (their grids shared with cfg_)
    std::optional<gpu::Context> own_context_;  // before the Booleans and the contour: destroyed after them
    BackendChoice booleans_;
    std::unique_ptr<GpuContourShare> gpu_contour_;  // after booleans_ (its slabs), before sculpt_ (uses it)
    std::string contour_reason_;
    std::unique_ptr<compute::Contourer> contourer_;
    std::unique_ptr<SpscRing<ToolSample>> ring_;
    TripleBuffer<ActiveSurface> surface_;
    TripleBuffer<MeshFrame> meshes_;
    ChangeSignal sculpted_changes_;                    // before sculpt_, which notifies it
    std::unique_ptr<compute::JournalWriter> journal_;  // before sculpt_, which appends to it
    std::unique_ptr<compute::JournalIntake> intake_;   // after journal_, which it writes; before loop_, which feeds it
    std::unique_ptr<SculptThread> sculpt_;
    std::vector<Workpiece> more_wp_;                     // the further workpieces until build() moves them into more_
    std::vector<std::unique_ptr<MoreWorkpiece>> more_;  // before loop_, which feeds their rings
    std::unique_ptr<PlacementHistory> placements_;     // the placements as undo steps (render thread)
    std::unique_ptr<UndoRouter> undo_router_;          // where undo and redo go: the strokes' and placements' order
    std::unique_ptr<TickStream> tick_stream_;  // before loop_, which pushes into its ring
    std::unique_ptr<haptics::HapticLoop> loop_;
    std::size_t tiles_initial_ = 0;
    bool coarse_first_ = false;
    double contour_s_ = 0.0, session_s_ = 0.0;
    std::chrono::steady_clock::time_point t_start_{};
    bool started_ = false, stopped_ = false;
    bool viewed_placing_ = false;  // the view latest_view() last returned: the tool held a workpiece
    int viewed_target_ = 0;  // the target of the view latest_view() last returned (its one thread's, as request's)
};

}  // namespace tridex::app
