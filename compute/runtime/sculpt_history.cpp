// compute/runtime/sculpt_history.cpp - Booleans with per-stroke undo and redo.
#include "compute/runtime/sculpt_history.hpp"

#include "compute/tools/clay_sweep.hpp"

namespace tridex::app {

SculptHistory::SculptHistory(compute::TriDexel& model, BooleanBackend& backend, std::size_t budget_bytes,
                             std::uint64_t last_serial)
    : model_(model), backend_(backend), history_(model.lattice, budget_bytes, last_serial) {}

compute::BooleanStats SculptHistory::apply(std::span<const compute::Sweep> batch) {
    if (batch.empty()) return {};
    if (held_.empty() && batch.back().op != ToolOp::kPush && batch.back().op != ToolOp::kSmooth) {  // nothing to hold
        history_.capture(model_, batch);
        return backend_.apply(batch);
    }
    // The held sweeps, then the batch; all of it valid before anything changes.
    std::vector<compute::Sweep> all;
    all.reserve(held_.size() + batch.size());
    all.insert(all.end(), held_.begin(), held_.end());
    all.insert(all.end(), batch.begin(), batch.end());
    const std::size_t open = compute::clay_open_group(model_.lattice, all);  // validates the trailing clay run
    history_.capture(model_, batch);
    compute::BooleanStats st;
    if (open > 0) st = backend_.apply(std::span<const compute::Sweep>(all).first(open));
    held_.assign(all.begin() + static_cast<std::ptrdiff_t>(open), all.end());
    return st;
}

compute::BooleanStats SculptHistory::flush() {
    if (held_.empty()) return {};
    std::vector<compute::Sweep> run;
    run.swap(held_);
    return backend_.apply(run);
}

std::uint64_t SculptHistory::end_stroke(compute::BooleanStats* flushed) {
    const compute::BooleanStats f = flush();
    if (flushed) *flushed = f;
    return history_.end_stroke(model_);
}

compute::UndoHistory::Change SculptHistory::undo() {
    flush();
    return history_.undo(model_, [this](std::span<const compute::RayImage> rays, const Aabb& box) { backend_.write_rays(rays, box); });
}

compute::UndoHistory::Change SculptHistory::redo() {
    flush();
    return history_.redo(model_, [this](std::span<const compute::RayImage> rays, const Aabb& box) { backend_.write_rays(rays, box); });
}

}  // namespace tridex::app
