// compute/journal/journal_replay.hpp - applying a journal's records to a model, as the sculpt thread applied them.
// Defined in compute/runtime/journal_replay.cpp: the replay runs through the sculpt thread's history (runtime/).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "compute/history/undo_history.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/model/tridexel.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "core/progress.hpp"

namespace tridex::compute {

/// What journal_apply did.
struct JournalApplyStats {
    std::uint64_t records = 0;   ///< records applied (batches and marks)
    std::uint64_t samples = 0;   ///< samples read
    std::uint64_t tail_samples = 0;  ///< of those, the tail's (JournalRecord::tail: received, never applied live)
    std::uint64_t booleans = 0;  ///< swept Booleans applied (one per consecutive pair with an op)
    std::uint64_t strokes = 0;   ///< stroke-end marks replayed
    std::uint64_t undos = 0;     ///< undo marks replayed
    std::uint64_t redos = 0;     ///< redo marks replayed
    std::uint64_t lattices = 0;  ///< coarseness changes replayed (lattice records)
    std::uint64_t marks_skipped = 0;  ///< marks after a gap in record indices that no longer matched the replay
    std::uint64_t islands_removed = 0;  ///< specks removed at stroke ends (JournalApplyFrom::remove_islands)
    double island_volume_m3 = 0.0;      ///< their volume, m^3
    double last_t_s = 0.0;       ///< t_s of the last sample (device time, s); 0 without samples
    /// Bytes the replay's undo history held after the last record (its before-images: what a copy of the model must
    /// hold besides the model itself to follow undos and redos of the strokes before it).
    std::uint64_t history_bytes = 0;
};

/// Where journal_apply starts.
struct JournalApplyFrom {
    std::size_t record = 0;          ///< first record to apply (0: the start; after a checkpoint: the record after it)
    std::uint64_t last_serial = 0;   ///< serial of the last stroke closed before that record (0 at the start)
    /// The undo history's budget, bytes; at least the session's, so that every undo it journalled finds its stroke.
    std::size_t history_budget_bytes = UndoHistory::kDefaultBudgetBytes;
    /// Whether strokes that cut remove the specks they left (app::SculptHistory::remove_islands): the session's
    /// setting (the journal header's settings, keep_islands), so that the replay removes what the session removed.
    bool remove_islands = false;
    /// The most sweeps one push or smooth group held (app::BooleanBackend::set_clay_group_sweeps): the session's
    /// setting (the journal header's settings, clay_group_sweeps), so that the replay groups its clay sweeps, and so
    /// builds its model, as the session did (1..kClayGroupSweepsMax).
    std::size_t clay_group_sweeps = kClayGroupSweeps;
};

/// Applies `records` from `from.record` on, in order, to `model` through the CPU reference Booleans, as the sculpt
/// thread did: one batch per batch record (sample_sweep between consecutive samples of one site, across record boundaries: SiteSweeps; each
/// batch validated before any of it changes the model), the model re-sampled at lattice records (its coarseness;
/// `model` may end on another lattice), strokes closed, undone and redone at their marks (through
/// an UndoHistory; checkpoint records are skipped; with from.remove_islands each stroke that cut removes its specks
/// where it closes, as the sculpt thread did), marking dirty tiles. Intake records are skipped; the tail record
/// (JournalRecord::tail) is applied as the sculpt thread applies what it drains: one batch per stroke, the stroke
/// closed where the tool stops cutting or changes, or another site's tool cuts (SiteSweeps::closes_before). Sessions have no mesh tools: a kMesh
/// sample throws. Throws tridex::Error naming the record on a sweep the Booleans refuse, or on a mark that does not
/// match the replay (a stroke closed or undone under another serial, an undo with nothing to undo, another number
/// of rays written back: a journal replayed from a state it was not written from); the model then holds the
/// records before it. After a gap in the record indices (damaged records the reader skipped), marks are matched
/// leniently: a stroke end closes the open stroke and relearns the offset between the journal's serials and the
/// replay's (a lost stroke end merges two strokes), an undo or redo whose stroke is not the replay's next is skipped
/// and counted in marks_skipped, and another number of rays written back is accepted (lost samples change it).
/// `progress` (core/progress.hpp) hears the fraction of the records applied, on the calling thread, about a hundred
/// times (the records are applied in slices, which gives the same model as all at once).
JournalApplyStats journal_apply(TriDexel& model, std::span<const JournalRecord> records,
                                const JournalApplyFrom& from = {}, const ProgressFn& progress = {});

/// journal_apply's work, kept between calls: records applied a few at a time, as they arrive (a cluster's render
/// ranks follow the session's stream frame by frame), give the same model as journal_apply over all of them at
/// once, bit for bit. The records passed to successive apply() calls are one journal's records in order (record
/// indices continuing). `model` must outlive the applier. Not thread-safe.
class JournalApplier {
public:
    /// Starts on `model` as journal_apply does with `from` at the start of a journal (from.record is ignored: the
    /// first record given to apply() is the journal's first, index 0, unless resume_after() said otherwise).
    /// Throws tridex::Error when from.history_budget_bytes is 0 or from.clay_group_sweeps is out of range.
    explicit JournalApplier(TriDexel& model, const JournalApplyFrom& from = {});
    ~JournalApplier();
    JournalApplier(const JournalApplier&) = delete;
    JournalApplier& operator=(const JournalApplier&) = delete;
    /// Applies `records` in order (journal_apply's rules, errors and lenience after gaps); the counters add up in
    /// stats(). A push group left open at the end stays held (flush() applies it), as the sculpt thread holds it.
    void apply(std::span<const JournalRecord> records);
    /// Continues a journal after its record `last_index` (a checkpoint): the next record is expected at
    /// last_index + 1, and each site's first sweep starts at its sample in `prevs`, the site's last sample before it
    /// (journal_last_samples; a site without one starts with no previous sample); records_before: the records before
    /// it as read, so that errors name records by their place in the journal ("journal record K"). Call before the
    /// first apply(). Throws tridex::Error for a sample of a site >= kMaxSites.
    void resume_after(std::uint64_t last_index, std::span<const ToolSample> prevs, std::uint64_t records_before);
    /// Starts from a session's undo history as it stood (UndoHistory::save_steps bytes: a snapshot's, taken with no
    /// stroke open), so that undos and redos of strokes made before find them; with from.last_serial (the newest
    /// stroke closed then) and resume_after (the record the snapshot follows, each site's last sample), records
    /// streamed after a snapshot apply to its model as they did to the session's. Call before the first apply().
    /// Throws tridex::Error for malformed bytes (UndoHistory::load_steps).
    void load_history(std::span<const unsigned char> steps);
    /// Applies a held push group (the end of a journal that ended without closing its stroke).
    void flush();
    /// What was applied so far.
    const JournalApplyStats& stats() const;
    /// The replay's undo history as bytes (UndoHistory::save_steps): what a late joiner of a shared session gets with
    /// the model. Throws tridex::Error while a stroke is open or sweeps are held.
    std::vector<unsigned char> history_steps() const;
    /// True while the records applied so far leave a stroke open (its close not applied yet) or sweeps held (a push
    /// group): what a copy of the model draws as a stroke in progress.
    bool stroke_open() const;

private:
    struct State;
    std::unique_ptr<State> s_;
};

/// Each site's last sample in the batch records of records [0, end), by site (for JournalApplier::resume_after).
std::vector<ToolSample> journal_last_samples(std::span<const JournalRecord> records, std::size_t end);

/// The serial of the last stroke closed in records [0, end) (the largest stroke-end serial), for
/// JournalApplyFrom::last_serial.
std::uint64_t journal_last_serial(std::span<const JournalRecord> records, std::size_t end);

}  // namespace tridex::compute
