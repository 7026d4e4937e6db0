// compute/runtime/sculpt_history.cpp - Booleans with per-stroke undo and redo.
#include "compute/runtime/sculpt_history.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "compute/model/islands.hpp"
#include "compute/tools/clay_sweep.hpp"

namespace tridex::app {

SculptHistory::SculptHistory(compute::TriDexel& model, BooleanBackend& backend, std::size_t budget_bytes,
                             std::uint64_t last_serial)
    : model_(model), backend_(backend), history_(model.lattice, budget_bytes, last_serial), budget_(budget_bytes) {}

compute::BooleanStats SculptHistory::apply(std::span<const compute::Sweep> batch) {
    if (batch.empty()) return {};
    if (held_.empty() && !compute::is_grouped_clay_op(batch.back().op)) {  // nothing to hold
        history_.capture(model_, batch);
        const compute::BooleanStats st = backend_.apply(batch);
        note_cuts(batch);
        return st;
    }
    // The held sweeps, then the batch; all of it valid before anything changes.
    std::vector<compute::Sweep> all;
    all.reserve(held_.size() + batch.size());
    all.insert(all.end(), held_.begin(), held_.end());
    all.insert(all.end(), batch.begin(), batch.end());
    const std::size_t open =
        compute::clay_open_group(model_.lattice, all, backend_.clay_group_sweeps());  // validates the trailing run
    history_.capture(model_, batch);
    compute::BooleanStats st;
    if (open > 0) st = backend_.apply(std::span<const compute::Sweep>(all).first(open));
    held_.assign(all.begin() + static_cast<std::ptrdiff_t>(open), all.end());
    note_cuts(batch);
    return st;
}

void SculptHistory::note_cuts(std::span<const compute::Sweep> batch) {
    for (const compute::Sweep& s : batch) {
        if (s.op != ToolOp::kSubtract) continue;
        const Aabb b = compute::sweep_bounds(s);
        if (b.empty() || !is_finite(b.lo) || !is_finite(b.hi)) continue;
        cut_box_.add(b.lo);
        cut_box_.add(b.hi);
        const double r = s.tool.kind == ToolKind::kMesh && s.tool.mesh ? s.tool.mesh->bounding_radius_m() : s.tool.radius_m;
        if (std::isfinite(r)) cut_radius_m_ = std::max(cut_radius_m_, r);
    }
}

IslandRemoval SculptHistory::remove_specks() {
    const auto t0 = std::chrono::steady_clock::now();
    const double cell = model_.lattice.cell_m;
    compute::IslandOptions opt;
    opt.max_volume_m3 = compute::speck_volume_m3(cut_radius_m_);
    const compute::IslandSearch found = compute::find_islands(model_, cut_box_.inflated(cut_radius_m_ + 2.0 * cell), opt);
    IslandRemoval r;
    r.searches = 1;
    if (!found.rays.empty()) {
        const Aabb box = found.speck_box_m.inflated(cell);
        history_.capture_rays(model_, found.rays, box);  // undo restores the specks
        backend_.write_rays(found.rays, box);
        r.specks = found.specks.size();
        r.volume_m3 = found.speck_volume_m3;
        r.rays = found.rays.size();
    }
    r.search_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

compute::BooleanStats SculptHistory::flush() {
    if (held_.empty()) return {};
    std::vector<compute::Sweep> run;
    run.swap(held_);
    return backend_.apply(run);
}

std::uint64_t SculptHistory::end_stroke(compute::BooleanStats* flushed, IslandRemoval* islands) {
    const compute::BooleanStats f = flush();
    if (flushed) *flushed = f;
    IslandRemoval removed;
    if (remove_islands_ && history_.stroke_open() && !cut_box_.empty()) removed = remove_specks();
    cut_box_ = Aabb{};
    cut_radius_m_ = 0.0;
    island_totals_ += removed;
    if (islands) *islands = removed;
    const std::uint64_t serial = history_.end_stroke(model_);
    if (serial != 0 && history_.next_undo_serial() == serial) clear_redo_eras();  // a new step: lattice redos are stale
    return serial;
}

}  // namespace tridex::app
