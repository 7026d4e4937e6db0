// compute/runtime/sculpt_stats.hpp - what the sculpt thread counts and times, read after it stops.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "compute/history/undo_history.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "compute/runtime/site_intake.hpp"
#include "compute/runtime/site_strokes.hpp"
#include "compute/tools/model_resample.hpp"
#include "core/duration_histogram.hpp"

namespace tridex::app {

/// A point of the sculpt thread's sample stream where it took a request that depends on when it came (an undo, a
/// redo, a stroke close asked for or made because the tool idled, a coarseness change made), as SculptStats::marks
/// lists them.
struct SculptMark {
    std::uint64_t after_samples = 0;                     ///< samples drained before it (SculptStats::samples then)
    SculptRequest request = SculptRequest::kEndStroke;   ///< kUndo, kRedo, kEndStroke, kFiner or kCoarser
};

/// One change of the model's coarseness the sculpt thread made (SculptRequest kFiner or kCoarser).
struct CoarsenessChange {
    std::uint64_t serial = 0;              ///< its undo step's serial
    compute::ResampleStats resample;       ///< the resolutions, cells and volumes before and after (no surface move)
    double seconds = 0.0;                  ///< wall time of the whole change (re-sampling, active surface, contour), s
    double resample_s = 0.0;               ///< of it, the re-sampling (compute::resample_model), s
};

/// Counters of the sculpt thread, read after stop().
struct SculptStats {
    std::uint64_t samples = 0;           ///< tool samples drained from the ring
    std::uint64_t booleans = 0;          ///< swept-volume Booleans applied (one per segment)
    std::uint64_t rays_changed = 0;      ///< rays whose intervals changed, summed over Booleans
    std::uint64_t steps = 0;             ///< sculpt steps that changed the model
    std::uint64_t tiles_recontoured = 0; ///< dirty tiles re-contoured, summed over steps
    std::uint64_t publishes = 0;         ///< active-surface snapshots published
    /// Per changing step: Booleans + active-surface publish, ms. The per-step histograms have 0.01 ms bins to 40 ms,
    /// then 0.25 ms bins to 240 ms (DurationHistogram::fine()): a session of any length keeps the same memory.
    DurationHistogram boolean_ms = DurationHistogram::fine();
    DurationHistogram contour_ms = DurationHistogram::fine();  ///< per changing step: dirty-tile re-contouring, ms
    std::uint64_t mesh_publishes = 0;    ///< contoured meshes handed to the renderer (publish_mesh_to)
    /// Per mesh publish: assembling + copying the mesh, ms.
    DurationHistogram mesh_publish_ms = DurationHistogram::fine();
    /// use_tile_lod: tiles and groups of tiles whose levels of detail were taken in (as of the last mesh
    /// publish) and the summed wall time of their builds on the level-of-detail worker, ms.
    std::uint64_t lod_tiles_built = 0;
    std::uint64_t lod_groups_built = 0;
    double lod_build_ms = 0.0;
    /// use_tile_lod: builds the worker finished for a tile or group that had changed again meanwhile (thrown away).
    std::uint64_t lod_discarded = 0;
    /// use_tile_lod: steady-clock time (s, the epoch of MeshFrame::published_s) of the first pass at which every
    /// tile and group of start-up had its levels (TileSurfaceCache::startup_lod_pending: those a stroke changed
    /// meanwhile count as the stroke's), or -1 when that never happened.
    double lod_all_built_s = -1.0;
    /// Steady-clock time (s, the epoch of MeshFrame::published_s) of the first mesh publish that held every tile at
    /// full resolution: the first publish, or with a coarse-first start-up (LodWorkerOptions::coarse_first) the one
    /// after the last region was contoured; -1 when that never happened.
    double startup_refined_s = -1.0;
    /// Coarse-first start-up: tiles contoured by the refinement (StartupRefiner) before the session ended.
    std::uint64_t startup_tiles_refined = 0;
    /// Strokes drawn coarse (LodWorkerOptions::stroke_coarse): tile deferrals (compute::DeferredContour::defer, a
    /// tile counted once per step that changed it), and deferred tiles contoured later.
    std::uint64_t tiles_deferred = 0;
    std::uint64_t deferred_tiles_contoured = 0;
    /// Times background work (a slice of start-up's refinement or of deferred tiles, a mesh publish of their results)
    /// stopped early or waited because a cutting sample or a request was waiting (SculptThread::cut_waiting).
    std::uint64_t background_yields = 0;
    /// use_tile_lod: tiles and groups still waiting for their levels at the last mesh publish.
    std::size_t lod_pending = 0;
    /// use_tile_lod: per tile or group re-contoured after start-up that got its levels, the wall time from its
    /// re-contoured mesh being taken in (a mesh publish) to its levels being taken in (TileSurfaceCache::
    /// lod_latency_ms; the next mesh publish carries them), ms (DurationHistogram::latency bins).
    DurationHistogram lod_latency_ms = DurationHistogram::latency();
    /// Wall time the thread spent working (steps that drained samples, journal syncs), ms.
    double busy_ms = 0.0;
    /// Per undo or redo that changed the model: from taking the request to the active surface published and the
    /// dirty tiles re-contoured (what a person waits for before the drawn model follows), ms.
    std::vector<double> undo_ms;
    /// Per entry of undo_ms: rays the undo or redo wrote back (UndoHistory::Change::rays).
    std::vector<std::size_t> undo_rays;
    /// Per entry of undo_ms: 0 for an undo, 1 for a redo.
    std::vector<std::uint8_t> undo_redo;
    /// Per entry of undo_ms: its rays written back and the active surface published (its boolean_ms share), ms.
    std::vector<double> undo_restore_ms;
    /// Per entry of undo_ms: its dirty tiles re-contoured (its contour_ms share), ms.
    std::vector<double> undo_contour_ms;
    std::uint64_t undo_requests = 0;   ///< undo requests taken (including those with nothing to undo)
    std::uint64_t redo_requests = 0;   ///< redo requests taken
    /// Undo and redo requests that waited for the local tool's release (SculptThread::strokes_end_on_release).
    std::uint64_t held_requests = 0;
    /// Undo and redo requests dropped because SculptThread::kMaxHeldRequests already waited.
    std::uint64_t held_requests_dropped = 0;
    compute::HistoryStats history;     ///< the undo history at stop()
    std::uint64_t checkpoints = 0;     ///< checkpoint models written
    double checkpoint_ms_total = 0.0;  ///< wall time spent writing them, ms
    std::string checkpoint_error;      ///< the first checkpoint failure ("" when none); sculpting went on
    /// The specks removed at stroke ends (remove_islands), summed over strokes.
    IslandRemoval islands;
    /// Per stroke searched for specks: the search and its writes, ms.
    std::vector<double> island_search_ms;
    /// Samples taken from other sites (use_site_intake), of `samples`.
    std::uint64_t site_samples = 0;
    /// A joiner (follow_host): its own tool's samples handed to the host, not applied here.
    std::uint64_t forwarded = 0;
    /// A joiner: the host's digest checks this replica passed (a failed one fails the thread).
    std::uint64_t digest_checks = 0;
    /// Undo and redo requests refused because they would take back another site's work, in order (SiteStrokes).
    std::vector<SculptRefusal> refusals;
    /// Where in the sample stream the thread took each undo, redo and stroke-close request and closed an idle stroke,
    /// in order (SculptMark): what a replay of the same samples needs to repeat the session's strokes
    /// (SculptThread::follow_marks).
    std::vector<SculptMark> marks;
    /// Each coarseness change taken (SculptRequest kFiner, kCoarser; not its undo or redo), in order.
    std::vector<CoarsenessChange> coarseness;
};

}  // namespace tridex::app
