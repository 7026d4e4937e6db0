// compute/runtime/sculpt_history.cpp - Booleans with per-stroke undo and redo.
#include "compute/runtime/sculpt_history.hpp"

namespace tridex::app {

SculptHistory::SculptHistory(compute::TriDexel& model, BooleanBackend& backend, std::size_t budget_bytes,
                             std::uint64_t last_serial)
    : model_(model), backend_(backend), history_(model.lattice, budget_bytes, last_serial) {}

compute::BooleanStats SculptHistory::apply(std::span<const compute::Sweep> batch) {
    history_.capture(model_, batch);
    return backend_.apply(batch);
}

compute::UndoHistory::Change SculptHistory::undo() {
    return history_.undo(model_, [this](std::span<const compute::RayImage> rays, const Aabb& box) { backend_.write_rays(rays, box); });
}

compute::UndoHistory::Change SculptHistory::redo() {
    return history_.redo(model_, [this](std::span<const compute::RayImage> rays, const Aabb& box) { backend_.write_rays(rays, box); });
}

}  // namespace tridex::app
