// compute/runtime/sculpt_history.hpp - Booleans applied stroke by stroke with undo and redo, for the sculpt thread
// and for replaying its journal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "compute/history/undo_history.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/tools/model_resample.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/model/tridexel.hpp"
#include "core/error.hpp"

namespace tridex::app {

/// What the speck search did at the end of one stroke (SculptHistory::end_stroke), or summed over strokes.
struct IslandRemoval {
    std::uint64_t searches = 0;  ///< strokes searched (strokes that cut, with removal on)
    std::uint64_t specks = 0;    ///< specks removed (compute::find_islands)
    double volume_m3 = 0.0;      ///< their volume, m^3
    std::uint64_t rays = 0;      ///< rays written to remove them
    double search_ms = 0.0;      ///< wall time of the search and the writes, ms

    /// Adds `o`'s counts to these.
    IslandRemoval& operator+=(const IslandRemoval& o) {
        searches += o.searches;
        specks += o.specks;
        volume_m3 += o.volume_m3;
        rays += o.rays;
        search_ms += o.search_ms;
        return *this;
    }
};

/// A BooleanBackend's model with per-stroke undo and redo (compute::UndoHistory): apply() captures the rays a batch
/// may change before applying it; undo() and redo() write rays back through the backend (its GPU slabs and the CPU
/// model alike) and mark the tiles around the stroke dirty, so contouring and the active surface follow. The sculpt
/// thread and journal replay both use it, so a replay closes, undoes and redoes the same strokes.
/// Specks (remove_islands): when a stroke that cut (subtract sweeps) closes, the pieces of material it left floating
/// that are smaller than the ball of its tool's radius (compute::find_islands, compute::speck_volume_m3) are removed
/// within its sweeps' box grown by that radius and two cells: their rays are captured into the stroke's undo step
/// first (undo restores them, redo removes them again) and written through the backend (GPU slabs and CPU model
/// alike, tiles marked dirty). The removal depends only on the model and the stroke's sweeps, so a replay of the
/// same strokes with the same setting removes the same specks. Not thread-safe.
class SculptHistory {
public:
    /// `model` and `backend` (built on that model) must outlive this. budget_bytes > 0 (UndoHistory); last_serial:
    /// the serial of the last stroke closed before `model`'s state (0 for a fresh session). Throws tridex::Error
    /// when the budget is 0.
    SculptHistory(compute::TriDexel& model, BooleanBackend& backend,
                  std::size_t budget_bytes = compute::UndoHistory::kDefaultBudgetBytes, std::uint64_t last_serial = 0);

    /// Captures the rays `batch` may change (opening a stroke if none is open), then applies it after the sweeps
    /// held back before it, except that a push, smooth or grab group at its end that later sweeps could still join
    /// (compute::clay_open_group) is held back until they cannot or the stroke ends: the backends group short clay
    /// sweeps (compute::apply_clay_batch), and this keeps the groups, and so the model, the same however the
    /// stroke's samples were split into batches (a live session and its replay split them differently). Throws what
    /// the backend throws (nothing changed for a bad sweep, held ones included).
    compute::BooleanStats apply(std::span<const compute::Sweep> batch);
    /// Applies the sweeps held back (apply); their stats (zero when none were held).
    compute::BooleanStats flush();
    /// Number of sweeps held back.
    std::size_t held() const { return held_.size(); }
    /// True while a stroke is open.
    bool stroke_open() const { return history_.stroke_open(); }
    /// Applies the held sweeps (their stats into `flushed` when not null), removes the specks the stroke left when
    /// remove_islands is on (what it did into `islands` when not null), then closes the open stroke; its serial, 0
    /// when none was open. Throws what the backend's write_rays throws.
    std::uint64_t end_stroke(compute::BooleanStats* flushed = nullptr, IslandRemoval* islands = nullptr);
    /// Undoes the newest stroke, or the newest lattice change when no stroke after it is left to undo (closing the
    /// open stroke first as end_stroke does); serial 0 when there was nothing to undo. A lattice change's undo puts
    /// the model from before it back, bit for bit (Change::lattice; every tile marked dirty).
    compute::UndoHistory::Change undo();
    /// Redoes the newest undone stroke, or the newest undone lattice change when no stroke before it is left to redo
    /// (closing the open stroke first as end_stroke does); serial 0 when there was nothing to redo.
    compute::UndoHistory::Change redo();
    /// Changes the model's coarseness: replaces it by compute::resample_model(model, resolution, max_bytes) (every
    /// tile dirty), as one undo step with the next serial (Change::lattice, `rays` the new model's ray count). The
    /// model before it is kept whole for undo; the steps before it stay undoable past it. Clears the redo steps, as
    /// a stroke does. Kept lattice changes (the models and the histories under them) are held within the history's
    /// budget: the oldest are dropped first, and a model alone over the budget makes the change final (not
    /// undoable). The backend follows each change, its undo and redo (BooleanBackend::relattice: the GPU slabs are made
    /// again). Throws tridex::Error, changing nothing, while a stroke is open or sweeps are held, as resample_model (a
    /// resolution out of range, over max_bytes), and when the new model does not fit the GPU path's device; `stats`
    /// (not null) gets resample_model's figures.
    compute::UndoHistory::Change resample(int resolution, std::size_t max_bytes, compute::ResampleStats* stats = nullptr);
    /// Lattice changes that undo() / redo() can still take back / re-apply.
    std::size_t lattice_undo_steps() const { return below_.size(); }
    std::size_t lattice_redo_steps() const { return above_.size(); }
    /// Whether strokes that cut remove the specks they leave (default false: the session spec decides,
    /// SessionSpec::keep_islands; a replay must use the live session's setting).
    void remove_islands(bool on) { remove_islands_ = on; }
    /// Whether strokes that cut remove their specks (the last remove_islands() setting).
    bool removes_islands() const { return remove_islands_; }
    /// The speck removals of every stroke closed so far, summed.
    const IslandRemoval& islands() const { return island_totals_; }
    /// Serials undo() / redo() would take next (after closing the open stroke), a lattice change's included; 0 when
    /// none.
    std::uint64_t next_undo_serial() const;
    std::uint64_t next_redo_serial() const;
    /// The history's counters and sizes, the kept lattice changes included (their models' and histories' bytes, and
    /// each change as one undo or redo step).
    compute::HistoryStats stats() const;
    /// The closed steps as bytes (UndoHistory::save_steps; throws while a stroke is open or sweeps are held, or when
    /// the history holds a lattice change, which the bytes cannot carry).
    std::vector<unsigned char> save_steps() const;
    /// Replaces the steps by `bytes` (UndoHistory::load_steps).
    void load_steps(std::span<const unsigned char> bytes) { history_.load_steps(bytes); }
    /// Calls `read` with the CPU model showing its state before the open stroke (UndoHistory::swap_open_images), then
    /// restores it; with the current state when no stroke is open or its images are gone. `read` must not throw
    /// past the restore: it is called inside a guard that swaps back.
    template <class F>
    void read_stroke_start(F&& read) {
        const bool swapped = history_.swap_open_images(model_);
        struct Back {
            SculptHistory* h;
            bool on;
            ~Back() {
                if (on) h->history_.swap_open_images(h->model_);
            }
        } back{this, swapped};
        read(static_cast<const compute::TriDexel&>(model_));
    }

private:
    // The model and history of one side of a lattice change: below_ holds, per change, the model before it with the
    // strokes made on it; above_ (redo) the model after it with its strokes.
    struct LatticeEra {
        compute::TriDexel model;
        compute::UndoHistory history;
        std::uint64_t serial = 0;  // the lattice change's serial
        std::size_t bytes = 0;     // the model's and the history's
    };
    bool lattice_undo_next() const;  // undo() would take back the newest lattice change
    bool lattice_redo_next() const;  // redo() would make the newest undone lattice change again
    compute::UndoHistory::Change cross(std::vector<LatticeEra>& from, std::vector<LatticeEra>& to);
    void trim_eras();
    void clear_redo_eras();  // a new step made the lattice changes undone so far stale
    static std::size_t era_bytes(const compute::TriDexel& model, const compute::UndoHistory& history);

    compute::TriDexel& model_;
    BooleanBackend& backend_;
    compute::UndoHistory history_;
    std::size_t budget_ = 0;
    std::vector<LatticeEra> below_, above_;  // oldest first
    std::uint64_t dropped_strokes_ = 0;      // strokes of the eras dropped, for stats().strokes
    std::uint64_t lattice_undos_ = 0, lattice_redos_ = 0;  // lattice changes undone and redone
    std::vector<compute::Sweep> held_;  // the open push group, not applied yet
    bool remove_islands_ = false;
    Aabb cut_box_{};             // world box of the open stroke's subtract sweeps (empty: it cut nothing)
    double cut_radius_m_ = 0.0;  // the largest radius of its subtract sweeps' tools, m
    IslandRemoval island_totals_;
    void note_cuts(std::span<const compute::Sweep> batch);  // grows cut_box_ and cut_radius_m_
    IslandRemoval remove_specks();                          // within cut_box_, into the open stroke
};

}  // namespace tridex::app
