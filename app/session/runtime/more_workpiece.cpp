// app/session/runtime/more_workpiece.cpp - a further workpiece of a session.
#include "app/session/runtime/more_workpiece.hpp"

#include "app/session/runtime/sculpt_setup.hpp"
#include "app/support/progress.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {

constexpr std::size_t kRingCapacity = 1 << 16;  // tool samples: 65 s of ticks, as the first workpiece's

}  // namespace

MoreWorkpiece::MoreWorkpiece(SessionSpec spec, Workpiece workpiece, const Vec3& start_m, double tool_radius_m,
                             double tool_span_m, const MoreWorkpieceOptions& o)
    : spec_(std::move(spec)), wp_(std::move(workpiece)), start_bounds_m_(wp_.model.lattice.bounds()) {
    booleans_ = make_cpu_backend(wp_.model);
    booleans_->set_clay_group_sweeps(spec_.clay_group_sweeps);  // the grouping decides the model
    contourer_ = std::make_unique<compute::Contourer>(wp_.model);
    {
        ProgressReporter::Step step = progress().step("contouring " + wp_.mesh_path);
        contourer_->update(wp_.model, step.fn());
    }
    ring_ = std::make_unique<SpscRing<ToolSample>>(kRingCapacity);
    sculpt_ = std::make_unique<SculptThread>(wp_.model, *contourer_, *ring_, surface_, start_m, tool_radius_m, tool_span_m);
    sculpt_->use_backend(*booleans_);
    if (!o.journal.empty()) {
        journal_ = std::make_unique<compute::JournalWriter>(o.journal, spec_to_json(spec_));
        sculpt_->use_journal(*journal_);
        intake_ = std::make_unique<compute::JournalIntake>(*journal_);
        use_session_checkpoints(*sculpt_, o.journal, o.checkpoint_s, wp_.to_world, spec_);
    }
    set_session_sculpting(*sculpt_, spec_, o.kind);
    if (o.follow_marks) sculpt_->follow_marks(*o.follow_marks);
    use_session_saver(*sculpt_, o.save_path, wp_.to_world, spec_);
    if (o.mesh_tool) sculpt_->use_mesh_tools({o.mesh_tool});  // ToolShape::mesh_id 0
    if (o.publish_meshes) sculpt_->publish_mesh_to(meshes_, o.mesh_interval_s, MeshForm::kWhole, o.sculpted_changes);
}

MoreWorkpiece::~MoreWorkpiece() {
    try {
        stop();
    } catch (...) {  // a sculpt failure nobody asked about: the owner is going away
    }
}

haptics::LoopWorkpiece MoreWorkpiece::loop_workpiece() {
    haptics::LoopWorkpiece w;
    w.surface = &surface_;
    w.samples = ring_.get();
    w.sample_tap = intake_ ? &intake_->ring() : nullptr;
    w.pose = pose();
    w.bounds_m = start_bounds_m_;
    return w;
}

void MoreWorkpiece::start() {
    if (started_) return;
    started_ = true;
    sculpt_->start();
    if (intake_) intake_->start();
}

void MoreWorkpiece::stop() {
    if (!started_ || stopped_) return;
    stopped_ = true;
    stop_sculpting(*sculpt_, intake_.get(), journal_.get());
}

TriMesh MoreWorkpiece::final_mesh(std::vector<std::uint8_t>& materials) {
    if (started_ && !stopped_) throw Error("MoreWorkpiece::final_mesh: call stop() first");
    contourer_->update(wp_.model);
    materials = contourer_->mesh_materials();
    return contourer_->mesh();
}

}  // namespace tridex::app
