// compute/runtime/sculpt_history_lattice.cpp - undo and redo across a change of the model's lattice (coarseness): the
// model on the other side is kept whole, with the strokes made on it.
#include <algorithm>
#include <numeric>
#include <utility>

#include "compute/runtime/sculpt_history.hpp"

namespace tridex::app {

namespace {

std::size_t ray_count(const compute::TriDexel& model) {
    std::size_t n = 0;
    for (const compute::RaySet& s : model.sets) n += s.rays.size();
    return n;
}

void mark_all_dirty(compute::TriDexel& model) {
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), compute::TileGrid::kWhole);
}

}  // namespace

std::size_t SculptHistory::era_bytes(const compute::TriDexel& model, const compute::UndoHistory& history) {
    const std::array<std::size_t, 3> m = cpu_model_bytes(model);
    return std::accumulate(m.begin(), m.end(), std::size_t{0}) + history.stats().bytes;
}

bool SculptHistory::lattice_undo_next() const {
    // The lattice change is next only when every stroke made on its model since is undone and none was dropped.
    const compute::HistoryStats h = history_.stats();
    return history_.next_undo_serial() == 0 && !below_.empty() && h.dropped_steps == 0 && h.oversize_strokes == 0;
}

std::uint64_t SculptHistory::next_undo_serial() const {
    return lattice_undo_next() ? below_.back().serial : history_.next_undo_serial();
}

bool SculptHistory::lattice_redo_next() const { return history_.next_redo_serial() == 0 && !above_.empty(); }

std::uint64_t SculptHistory::next_redo_serial() const {
    return lattice_redo_next() ? above_.back().serial : history_.next_redo_serial();
}

compute::UndoHistory::Change SculptHistory::undo() {
    end_stroke();
    if (lattice_undo_next()) {
        ++lattice_undos_;
        return cross(below_, above_);
    }
    return history_.undo(model_, [this](std::span<const compute::RayImage> rays, const Aabb& box) { backend_.write_rays(rays, box); });
}

compute::UndoHistory::Change SculptHistory::redo() {
    end_stroke();
    if (lattice_redo_next()) {
        ++lattice_redos_;
        return cross(above_, below_);
    }
    return history_.redo(model_, [this](std::span<const compute::RayImage> rays, const Aabb& box) { backend_.write_rays(rays, box); });
}

compute::UndoHistory::Change SculptHistory::cross(std::vector<LatticeEra>& from, std::vector<LatticeEra>& to) {
    LatticeEra era = std::move(from.back());
    from.pop_back();
    const std::uint64_t newest = std::max(history_.last_serial(), era.history.last_serial());
    std::swap(model_, era.model);
    std::swap(history_, era.history);
    history_.continue_serials_after(newest);  // serials stay unique across the change
    backend_.relattice();
    mark_all_dirty(model_);
    era.bytes = era_bytes(era.model, era.history);
    compute::UndoHistory::Change c{era.serial, ray_count(model_), model_.lattice.bounds(), true};
    to.push_back(std::move(era));
    return c;
}

compute::UndoHistory::Change SculptHistory::resample(int resolution, std::size_t max_bytes, compute::ResampleStats* stats) {
    if (history_.stroke_open() || !held_.empty())
        throw Error("sculpt history: a stroke is open; close it before changing the coarseness");
    compute::TriDexel next = compute::resample_model(model_, resolution, max_bytes, stats);
    const std::uint64_t serial = history_.last_serial() + 1;
    history_.drop_redo();
    clear_redo_eras();
    LatticeEra era{std::move(model_), compute::UndoHistory(next.lattice, budget_, serial), serial, 0};
    std::swap(history_, era.history);  // era.history: the strokes on the old model
    model_ = std::move(next);
    try {
        backend_.relattice();
    } catch (...) {  // the new lattice does not fit the device: the old one comes back, as it was
        model_ = std::move(era.model);
        std::swap(history_, era.history);
        backend_.relattice();
        throw;
    }
    mark_all_dirty(model_);
    era.bytes = era_bytes(era.model, era.history);
    below_.push_back(std::move(era));
    trim_eras();
    return compute::UndoHistory::Change{serial, ray_count(model_), model_.lattice.bounds(), true};
}

void SculptHistory::clear_redo_eras() {
    for (const LatticeEra& e : above_) dropped_strokes_ += e.history.stats().strokes;
    above_.clear();
}

void SculptHistory::trim_eras() {
    std::size_t held = 0;
    for (const LatticeEra& e : below_) held += e.bytes;
    for (const LatticeEra& e : above_) held += e.bytes;
    const auto drop = [&held, this](std::vector<LatticeEra>& eras) {
        const compute::HistoryStats h = eras.front().history.stats();
        dropped_strokes_ += h.strokes;  // still counted as strokes made
        held -= eras.front().bytes;
        eras.erase(eras.begin());
    };
    while (held > budget_ && !below_.empty()) drop(below_);  // oldest first: a dropped change cannot be undone
    while (held > budget_ && !above_.empty()) drop(above_);
}

compute::HistoryStats SculptHistory::stats() const {
    compute::HistoryStats s = history_.stats();
    // An era below holds undo steps (its change's and its strokes'), one above redo steps.
    const auto add = [&s](const LatticeEra& e, bool below) {
        const compute::HistoryStats h = e.history.stats();
        s.bytes += e.bytes;
        s.strokes += h.strokes;
        s.dropped_steps += h.dropped_steps;
        s.oversize_strokes += h.oversize_strokes;
        s.undos += h.undos;
        s.redos += h.redos;
        (below ? s.undo_steps : s.redo_steps) += 1 + (below ? h.undo_steps : h.redo_steps);
    };
    for (const LatticeEra& e : below_) add(e, true);
    for (const LatticeEra& e : above_) add(e, false);
    s.strokes += dropped_strokes_;
    s.undos += lattice_undos_;
    s.redos += lattice_redos_;
    return s;
}

std::vector<unsigned char> SculptHistory::save_steps() const {
    if (!held_.empty()) throw Error("sculpt history: sweeps are held; close the stroke before saving the steps");
    if (!below_.empty() || !above_.empty())
        throw Error("sculpt history: it holds a coarseness change, which saved steps cannot carry");
    return history_.save_steps();
}

}  // namespace tridex::app
