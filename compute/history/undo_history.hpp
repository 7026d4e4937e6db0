// compute/history/undo_history.hpp - per-stroke undo and redo of a tri-dexel model: the before-images of the rays a
// stroke changed, kept within a memory budget.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <span>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/sweep.hpp"
#include "core/aabb.hpp"

namespace tridex::compute {

/// What an UndoHistory holds and did (report.json `history`).
struct HistoryStats {
    std::size_t budget_bytes = 0;      ///< most bytes the history keeps (undo and redo steps and the open stroke)
    std::size_t bytes = 0;             ///< bytes held now
    std::size_t undo_steps = 0;        ///< strokes that can be undone now
    std::size_t redo_steps = 0;        ///< undone strokes that can be redone now
    std::uint64_t strokes = 0;         ///< strokes closed that changed the model (each became an undo step)
    std::uint64_t dropped_steps = 0;   ///< oldest steps dropped to stay within the budget (no longer undoable)
    std::uint64_t oversize_strokes = 0;///< strokes that alone outgrew the budget (applied, but not undoable)
    std::uint64_t undos = 0;           ///< undo() calls that restored a stroke
    std::uint64_t redos = 0;           ///< redo() calls that re-applied a stroke
};

/// Per-stroke undo and redo by before-images. A stroke opens at the first capture() after the previous one
/// closed (or at the start) and closes at end_stroke() (or at undo() / redo(), which close it first). Before each
/// batch of sweeps is applied, capture() copies every ray the batch's swept boxes may touch and the open stroke
/// has not copied yet; end_stroke() keeps, of those, the rays whose intervals differ now (exactly the rays the
/// stroke changed, materials included) as one undo step with the world box of its sweeps, and clears the redo
/// steps. undo() writes the newest step's before-images back and keeps the rays' current images for redo();
/// redo() does the reverse. Every step has a serial number (1, 2, ... per closed stroke, empty ones included), so a
/// journal can name the step an undo took. Memory: RayImage bytes plus the open stroke's copies are kept within
/// the budget by dropping the oldest undo steps first, then the oldest redo steps; a stroke that alone outgrows
/// the budget stops being captured (it stays applied and cannot be undone; stats().oversize_strokes), and since
/// older steps cannot be undone across it, every step before it is dropped too.
/// The model must be the one the captures were taken from and change only through the batches captured and the
/// writes undo() and redo() ask for. Not thread-safe.
class UndoHistory {
public:
    static constexpr std::size_t kDefaultBudgetBytes = std::size_t{256} << 20;  ///< 256 MiB

    /// A history for models on `lattice` keeping at most `budget_bytes` (> 0); the first stroke closed gets serial
    /// `last_serial` + 1 (a replay that starts from a checkpoint continues the session's numbering). Throws
    /// tridex::Error when the budget is 0. Allocates 4 bytes per ray of the three sets (which rays the open stroke
    /// copied).
    explicit UndoHistory(const Lattice& lattice, std::size_t budget_bytes = kDefaultBudgetBytes, std::uint64_t last_serial = 0);

    /// Copies, into the open stroke (opened if none is), the rays of `model` under each sweep's swept box
    /// (sweep_bounds, one cell of margin) not copied yet in this stroke. Call before the batch is applied.
    /// Sweeps with op kNone are skipped. Never throws for sweeps the Booleans accept (non-finite boxes are
    /// skipped; the Booleans refuse those sweeps).
    void capture(const TriDexel& model, std::span<const Sweep> batch);
    /// Copies, into the open stroke, the rays of `model` that `rays` names (only each image's axis and index are read)
    /// not copied yet in this stroke, and grows the stroke's world box by `box_m` (m): for rays a stroke changes
    /// beyond its sweeps' boxes (the specks SculptHistory removes at the stroke's end), so that undo restores them
    /// and marks their tiles dirty. Call before changing them. Returns false, copying nothing, when no stroke is open.
    /// Throws tridex::Error for an image outside the model.
    bool capture_rays(const TriDexel& model, std::span<const RayImage> rays, const Aabb& box_m);
    /// True while a stroke is open (something was captured since the last close).
    bool stroke_open() const { return open_; }
    /// Closes the open stroke: its changed rays become an undo step (when there are any, and the redo steps
    /// are cleared). Returns the stroke's serial, 0 when no stroke was open.
    std::uint64_t end_stroke(const TriDexel& model);

    /// Writes rays into the model (and whatever mirrors it); `box_m` (world m) bounds where they changed.
    using RayWriter = std::function<void(std::span<const RayImage> rays, const Aabb& box_m)>;
    /// What undo() or redo() did.
    struct Change {
        std::uint64_t serial = 0;  ///< the step's serial; 0 = nothing to undo / redo (nothing changed)
        std::size_t rays = 0;      ///< rays written
        Aabb box_m{};              ///< world box of the step's sweeps
        /// The step changed the model's lattice (app::SculptHistory::resample): the whole model was replaced, `rays`
        /// counts every ray of the model now and box_m is its lattice's box.
        bool lattice = false;
    };
    /// Closes the open stroke, then restores the newest undo step: `write` gets its before-images; the rays'
    /// current images are kept for redo(). Returns serial 0 when there is nothing to undo. An exception from
    /// `write` propagates (the step is then lost; the caller should stop sculpting).
    Change undo(const TriDexel& model, const RayWriter& write);
    /// Closes the open stroke (which, when it changed the model, clears the redo steps), then re-applies the
    /// newest undone step. Returns serial 0 when there is nothing to redo.
    Change redo(const TriDexel& model, const RayWriter& write);
    /// Serial of the step undo() would restore / redo() would re-apply (after closing the open stroke), 0 when none.
    std::uint64_t next_undo_serial() const { return undo_.empty() ? 0 : undo_.back().serial; }
    std::uint64_t next_redo_serial() const { return redo_.empty() ? 0 : redo_.back().serial; }
    /// Serial of the newest stroke closed (or of the history's start, `last_serial`), 0 when none.
    std::uint64_t last_serial() const { return serial_; }
    /// The next stroke closed gets a serial above `serial` (a step outside this history, such as a lattice change,
    /// took the serials up to it). Never lowers the numbering.
    void continue_serials_after(std::uint64_t serial) { serial_ = std::max(serial_, serial); }
    /// Drops every redo step (a change outside the history, such as a lattice change, made them stale). Closes
    /// nothing: call it with no stroke open.
    void drop_redo();
    /// Counters and sizes.
    HistoryStats stats() const;
    /// The undo and redo steps, their serials and the counters, as bytes (little-endian; undo_history_io.cpp): what a
    /// copy of the model elsewhere needs, besides the model itself, to undo and redo these strokes as this history
    /// would (a shared session's late joiner). Throws tridex::Error while a stroke is open.
    std::vector<unsigned char> save_steps() const;
    /// Replaces the steps, the serial numbering and the counters by those `bytes` hold (save_steps of a history on
    /// the same lattice). Each ray image keeps the capacity it had, so the bytes held, and so what the budget drops
    /// later, are the same. Then trims to this history's budget. Throws tridex::Error, changing nothing, while a stroke
    /// is open or when `bytes` are malformed (a truncated or unknown layout, a ray outside this lattice, intervals
    /// over their capacity).
    void load_steps(std::span<const unsigned char> bytes);
    /// Swaps the open stroke's before-images with the model's rays: called once, the model shows the state before
    /// the open stroke (every ray the stroke may have changed was captured before it changed); called again, it is
    /// back. Only the CPU `model` changes (no RayWriter: nothing to mirror, for a reader that swaps back at once:
    /// the clay push's haptic reference surface). Returns false, changing nothing, when no stroke is open or the
    /// open one outgrew the budget (its images are gone).
    bool swap_open_images(TriDexel& model);

private:
    struct Step {
        std::uint64_t serial = 0;
        Aabb box_m{};
        std::size_t bytes = 0;
        std::vector<RayImage> rays;
    };
    static std::size_t image_bytes(const RayImage& r);
    void copy_ray(const TriDexel& model, int axis, std::size_t index);  // into the open stroke, once per stroke
    void trim(std::size_t extra);  // drop oldest steps until bytes_ + extra fits the budget
    Change swap_in(Step& step, const TriDexel& model, const RayWriter& write);

    Lattice lattice_;
    std::size_t budget_ = 0;
    std::array<std::vector<std::uint32_t>, 3> copied_;  // per ray: the open stroke's stamp when copied
    std::uint32_t stamp_ = 1;
    bool open_ = false;
    bool oversize_ = false;  // the open stroke outgrew the budget: no more copies, no step
    Step open_step_;
    std::deque<Step> undo_, redo_;  // oldest first
    std::size_t bytes_ = 0;         // undo_ + redo_ + open_step_
    std::uint64_t serial_ = 0;
    HistoryStats counts_;
};

}  // namespace tridex::compute
