// app/session/report/strip_moments.hpp - where a film strip's pictures stop: spread over the stretch of the journal where the
// model changed (docs/commands/replay.md, "A carve in pictures").
#pragma once

#include <cstddef>
#include <vector>

#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/model/tridexel.hpp"
#include "core/progress.hpp"

namespace tridex::app {

/// Samples in one batch of the journal a film strip is drawn from (split_batches): a picture can stop between any two
/// such pieces, however the replay's sculpt thread batched the samples (a replay that runs free drains thousands at
/// once).
inline constexpr std::size_t kStripPieceSamples = 8;

/// The share of a session's change before a strip's first picture: the first picture shows the model just before the
/// change made so far passes this share of the whole (so a graze on the way to the first cut costs no picture).
inline constexpr double kStripLeadShare = 0.01;

/// `journal` with every batch record of more than max_samples samples (0 taken as 1) split into consecutive batches of
/// at most max_samples, the records numbered again 0, 1, ... (a damaged journal's gaps are not kept). The sweeps, and
/// so the model journal_apply builds, are those of `journal`: the Booleans sweep between consecutive samples across
/// record boundaries.
compute::Journal split_batches(const compute::Journal& journal, std::size_t max_samples);

/// `replay` (a session's replay_settings) for a journal applied from its start: record 0, no stroke closed yet, and an
/// undo budget so large that every undo finds its stroke.
compute::JournalApplyFrom strip_replay(compute::JournalApplyFrom replay);

/// Per record of `journal` applied to `start` in order (JournalApplier with `from`), how much it changed the model: the
/// rays it rewrote (of the three sets; a ray's interval ends or their materials differ after it). A cut, an added
/// ridge, a painted band, a clay push, an undo, a redo and a stroke end that removed specks each count the rays they
/// changed, so a deep carve counts many times more than a graze of the same length (its footprint is wider), and
/// painting counts as carving does. `progress` hears the fraction of records applied. O(journal_apply + the rays the
/// dirty tiles hold). Throws as journal_apply.
std::vector<double> record_changes(const compute::Journal& journal, const compute::TriDexel& start,
                                   const compute::JournalApplyFrom& from, const ProgressFn& progress = {});

/// Where a strip of `frames` pictures (>= 2) stops, as the number of records of `journal` applied before each picture,
/// from `change` (one amount per record, record_changes). The pictures are spread over the stretch where the model
/// changed: the first just before the change made so far passes kStripLeadShare of the whole, the last just after the
/// last record that changed anything (it shows the final model), the others evenly spaced in samples between. Neither
/// the approach before the first cut (grazes included) nor the moving about after the last costs a picture, and the
/// pictures between are a time-lapse: a pause between strokes (the menu open, the hand moved on) keeps its share of
/// pictures, as it had its share of the session. A journal that changed nothing: from the first sample with an
/// operation to the end, evenly.
std::vector<std::size_t> strip_picture_records(const compute::Journal& journal, const std::vector<double>& change,
                                               int frames);

}  // namespace tridex::app
