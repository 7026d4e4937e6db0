// app/session/runtime/more_workpiece.hpp - a session's workpiece after its first (SessionSpec::more_workpieces),
// sculpted beside it by the same haptic loop: its own model, Booleans, contour, sample ring, active surface, journal and
// mesh hand-off.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/scene/session_memory.hpp"
#include "app/scene/session_spec.hpp"
#include "app/scene/workpiece_source.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/journal/journal_intake.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "compute/tools/mesh_tool.hpp"
#include "core/active_surface.hpp"
#include "core/change_signal.hpp"
#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

/// What a further workpiece takes from its session.
struct MoreWorkpieceOptions {
    /// Its journal (app/scene/workpiece_list.hpp path_for_workpiece of the session's), with its own spec
    /// (spec_for_workpiece) as the identity, so `tridex recover` rebuilds it alone; "" = none.
    std::string journal{};
    double checkpoint_s = 0.0;   ///< with a journal: checkpoints this often (s; SculptOptions::checkpoint_s); 0 = none
    std::string save_path{};     ///< where a save request writes its model (.tdx); "" = nowhere
    SessionKind kind = SessionKind::kBatch;  ///< what memory a coarseness change may take (check_resample_memory)
    /// Hand its whole contoured mesh (MeshForm::kWhole) to a renderer at most once per mesh_interval_s; false: none.
    bool publish_meshes = false;
    double mesh_interval_s = 1.0 / 60.0;
    ChangeSignal* sculpted_changes = nullptr;  ///< notified with each mesh that carries a sculpted change; may be null
    /// A replay: this workpiece's recorded marks (SculptThread::follow_marks); nullopt = taken as they come.
    std::optional<std::vector<SculptMark>> follow_marks{};
    /// The session's mesh tool (ToolShape::mesh_id 0), when its tool is a mesh.
    std::shared_ptr<const compute::MeshTool> mesh_tool{};
};

/// A workpiece after a session's first. Its Booleans and contour run on the CPU pool, whatever the first's run on, and
/// it hands a renderer whole meshes (its first workpiece's levels of detail, GPU contour and shared-session streams are
/// not made for it). The haptic loop reads its active surface and feeds its ring through loop_workpiece(). Not movable
/// (its thread holds references into it).
class MoreWorkpiece {
public:
    /// Prepares the model's contour, the sculpt thread and (with options.journal) the journal, without starting
    /// threads. `spec` is this workpiece's own (spec_for_workpiece); `start_m` (its model frame, m) centres the first
    /// active-surface snapshot; tool_radius_m and tool_span_m as SculptThread's. Throws tridex::Error for a journal
    /// that cannot be created, or as the sculpt thread's set-up does.
    MoreWorkpiece(SessionSpec spec, Workpiece workpiece, const Vec3& start_m, double tool_radius_m, double tool_span_m,
                  const MoreWorkpieceOptions& options);
    ~MoreWorkpiece();
    MoreWorkpiece(const MoreWorkpiece&) = delete;
    MoreWorkpiece& operator=(const MoreWorkpiece&) = delete;

    /// What the haptic loop needs of it: its active surface, its sample ring and journal tap, its pose and box.
    haptics::LoopWorkpiece loop_workpiece();
    /// Starts the sculpt thread (and the journal's intake). Once; later calls do nothing.
    void start();
    /// After the haptic loop stopped: drains the ring, closes the stroke, joins, closes the journal; rethrows a
    /// sculpt-thread failure. Idempotent.
    void stop();
    /// Queues an undo, redo, stroke close or save (SculptThread::request); one thread. False when the queue is full.
    bool request(SculptRequest r) { return sculpt_->request(r); }
    /// Its sculpt thread's live counters and passes (SculptThread::live, passes; any thread).
    SculptLive sculpt_live() const { return sculpt_->live(); }
    std::uint64_t sculpt_passes() const { return sculpt_->passes(); }
    /// Its sculpt thread's requests waiting for the tool's release (SculptThread::requests_held). Any thread.
    std::size_t sculpt_requests_held() const { return sculpt_->requests_held(); }
    /// The newest whole mesh (options.publish_meshes; one render thread), in its model frame.
    const MeshFrame& latest_mesh() { return meshes_.latest(); }
    /// After stop(): its whole final model contoured on the CPU (model frame, m) with a material id per vertex.
    /// Throws tridex::Error while its thread runs.
    TriMesh final_mesh(std::vector<std::uint8_t>& materials);

    const SessionSpec& spec() const { return spec_; }           ///< its own spec (spec_for_workpiece)
    const Workpiece& workpiece() const { return wp_; }          ///< its model (read after stop())
    Pose pose() const { return workpiece_pose(spec_); }         ///< model frame -> world (as its spec placed it)
    /// Its lattice's box when the session started (model frame, m): a cull box for picks on its meshes (any thread).
    const Aabb& start_bounds_m() const { return start_bounds_m_; }
    const SculptStats& sculpt_stats() const { return sculpt_->stats(); }  ///< after stop()
    /// The journal's counters, file and error; nullptr without a journal. Read after stop().
    const compute::JournalStats* journal_stats() const { return journal_ ? &journal_->stats() : nullptr; }

private:
    SessionSpec spec_;
    Workpiece wp_;
    Aabb start_bounds_m_{};
    std::unique_ptr<BooleanBackend> booleans_;
    std::unique_ptr<compute::Contourer> contourer_;
    std::unique_ptr<SpscRing<ToolSample>> ring_;
    TripleBuffer<ActiveSurface> surface_;
    TripleBuffer<MeshFrame> meshes_;
    std::unique_ptr<compute::JournalWriter> journal_;  // before sculpt_, which appends to it
    std::unique_ptr<compute::JournalIntake> intake_;   // after journal_, which it writes
    std::unique_ptr<SculptThread> sculpt_;
    bool started_ = false, stopped_ = false;
};

}  // namespace tridex::app
