// compute/runtime/sculpt_thread.hpp - the sculpt thread: tool samples in, Booleans, dirty-tile contouring,
// active-surface snapshots out (DESIGN.md, "three threads").
#pragma once

#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <string>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <cstdint>
#include <thread>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/deferred_contour.hpp"
#include "compute/contour/startup_refine.hpp"
#include "compute/history/undo_history.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/journal/tool_stream.hpp"
#include "compute/model/tridexel.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/detail_requests.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "compute/runtime/site_intake.hpp"
#include "compute/runtime/sculpt_stats.hpp"
#include "compute/runtime/site_strokes.hpp"
#include "compute/runtime/undo_clock.hpp"
#include "compute/tools/mesh_tool.hpp"
#include "core/active_surface.hpp"
#include "core/change_signal.hpp"
#include "core/duration_histogram.hpp"
#include "core/spsc_ring.hpp"
#include "core/tool_sample.hpp"
#include "core/tri_mesh.hpp"
#include "core/triple_buffer.hpp"

namespace tridex::app {

/// What a monitor reads of the sculpt thread while it runs (SculptThread::live; any thread).
struct SculptLive {
    std::uint64_t steps = 0;           ///< sculpt steps that changed the model so far
    std::size_t history_bytes = 0;     ///< the undo history's bytes held as of the thread's last pass
    std::size_t history_budget_bytes = 0;  ///< its budget, bytes
    /// Per changing step: Booleans (or clay), active-surface publish and dirty-tile re-contouring, ms
    /// (DurationHistogram::fine bins: fixed memory however long the session).
    DurationHistogram step_ms = DurationHistogram::fine();
    /// Where the newest undo and redo steps stand in the sample stream, as of the last pass that worked.
    UndoTimes undo_times;
};

/// What the saver did so far (SculptThread::save_status; any thread).
struct SaveStatus {
    std::uint64_t saves = 0;     ///< saves that succeeded
    std::uint64_t failures = 0;  ///< saves that failed
    std::string message;         ///< the last save's line: what was written, or why it failed ("" before any)
    bool ok = true;              ///< false when the last save failed
    std::string journal_error;     ///< why the journal stopped ("" while it works or without one): work is not being kept
    std::string checkpoint_error;  ///< why checkpoints stopped ("" while they work or without them)
    /// The last coarseness request's line: what changed (resolution, cell, volume), or why it was refused ("" before
    /// any).
    std::string coarseness;
};

/// What a checkpoint writer (SculptThread::use_checkpoints) wrote: the file's name in the journal's folder, its
/// size and CRC-32.
struct CheckpointFile {
    std::string name;
    std::uint64_t bytes = 0;
    std::uint32_t crc = 0;
};

class GpuContourShare;

/// How the sculpt thread hands the contoured surface to the renderer.
enum class MeshForm {
    kWhole,  ///< MeshFrame::mesh: the whole mesh assembled and copied on every publish
    kTiles,  ///< MeshFrame::tiles: per-tile meshes (TileSurfaceCache), only changed tiles rebuilt and copied
};

/// A contoured mesh handed from the sculpt thread to the renderer (SculptThread::publish_mesh_to).
struct MeshFrame {
    std::uint64_t version = 0;  ///< 1 for the first publish, +1 per publish; 0 = nothing published yet
    TriMesh mesh;               ///< kWhole: the whole contoured model, world m, CCW from outside; kTiles: empty
    /// kWhole: material id per mesh vertex (Contourer::mesh_materials, same order as mesh.positions);
    /// kTiles: empty (each TileSurface carries its own materials).
    std::vector<std::uint8_t> materials;
    /// kTiles: every non-empty tile, ordered by id (world m). A tile whose version did not change since the
    /// previous publish is the same shared object (never modified after publishing), so publishing costs
    /// O(changed tiles' triangles) and the renderer re-uploads only tiles whose version changed.
    std::vector<std::shared_ptr<const compute::TileSurface>> tiles;
    /// kTiles with use_tile_lod: the groups of tiles with their levels of detail (TileSurfaceCache::groups),
    /// ordered by id, shared as `tiles` are (an unchanged group is the same object); else empty.
    std::vector<std::shared_ptr<const compute::TileGroupSurface>> groups;
    bool tiled = false;          ///< true when `tiles` holds the surface (MeshForm::kTiles)
    /// true: the surface lives in the GPU contour (SculptThread::use_gpu_contour); mesh is empty and the renderer
    /// draws GpuContourShare's buffers. Without use_tile_lod `tiles` is empty too and this frame only announces
    /// that they changed; with it, `tiles` and `groups` hold the contour's tiles read back
    /// (GpuContourShare::refresh_tiles) with their levels, for the renderer to draw a tile from them instead of
    /// its buffers while TileSurface::source_version equals the buffers' IndirectTile::version.
    bool gpu = false;
    std::size_t triangles = 0;   ///< triangles in mesh or summed over tiles
    std::uint64_t sculpt_steps = 0;  ///< SculptStats::steps when published (for a sculpt rate, steps/s)
    double published_s = 0.0;    ///< steady-clock time of the publish, s (same epoch as std::chrono::steady_clock)
    /// The oldest ToolSample::made_s among the cutting samples of the steps that changed the model since the previous
    /// publish (steady-clock s): a renderer that draws this frame shows that sample's effect, so draw time minus this
    /// is the frame's worst tool-sample-to-drawn latency. A version replaced before the renderer took it passes its
    /// oldest sample on to the next publish. NaN when no such step (or no sample time) came.
    double oldest_sample_s = std::numeric_limits<double>::quiet_NaN();
    /// The same sample's device time (ToolSample::t_s), s; NaN with oldest_sample_s.
    double oldest_sample_t_s = std::numeric_limits<double>::quiet_NaN();
};

/// Where a joiner's sculpt thread sends its own tool's samples and requests (SculptThread::follow_host).
struct FollowerOutlet {
    std::function<void(std::span<const ToolSample>)> samples;  ///< each pass's own samples, in order
    std::function<void(SculptRequest)> request;                ///< an undo, redo or stroke close asked here
    /// Optional: the host's digest check failed (what differs); the thread then fails (stop() rethrows).
    std::function<void(const std::string&)> mismatch;
};

/// The session as it stands, for a site joining a shared session late (SculptThread::use_snapshots): taken by the
/// host's sculpt thread between two records of its stream, with no stroke open (the open one is closed first, as
/// another site's cut closes it, and that close is in the stream), or asked for a replica of the session's own
/// (SculptThread::ask_snapshot: taken when no stroke is open).
struct SculptSnapshot {
    std::uint8_t site = 0;               ///< who joins (SiteIntake::push_snapshot); 0: asked (ask_snapshot)
    compute::TriDexel model;             ///< the model after every record streamed so far, every tile marked dirty
    std::vector<unsigned char> history;  ///< the undo history's steps (SculptHistory::save_steps)
    std::vector<ToolSample> prevs;       ///< each site's last sample (sweeps continue from it), by site, at most one each
    std::uint64_t last_closed_serial = 0;  ///< the newest stroke closed
    std::uint64_t asks = 0;  ///< asked (site 0): the ask_snapshot calls made before it was taken, all served by it
};

/// Where a follower starts when it joined late: the history and sweeps of a SculptSnapshot (its model is the one the
/// follower's thread was made with).
struct FollowStart {
    std::vector<unsigned char> history;  ///< SculptSnapshot::history
    std::vector<ToolSample> prevs;       ///< SculptSnapshot::prevs
    std::uint64_t last_closed_serial = 0;
};

/// Strokes and undo: the samples' sweeps are applied stroke by stroke through a SculptHistory. A stroke closes at a
/// sample with op kNone (the tool lifted, the workspace button held), at a change of op, material or tool, when
/// its sweeps have changed nothing for kStrokeIdleS of device time after it changed the model (the tool left the
/// material), and at a kEndStroke request; a drained batch is split where a stroke closes. Undo and redo requests
/// are taken at the start of a step, before that step's samples, except while a held-button stroke is open
/// (strokes_end_on_release): then they wait for its release. Every close, undo and redo is journalled as a
/// mark between the batch records, so a journal replays the same strokes. Coarseness requests (kFiner, kCoarser)
/// close the open stroke and re-sample the model onto a lattice of twice or half the resolution as one undo step
/// (SculptHistory::resample), journalled as a lattice record; the Contourer and the tile cache are made again for it.
/// Clay: while a push stroke (ToolOp::kPush) is open, the published active surface is the model as it was when the
/// stroke began (SculptHistory::read_stroke_start), so the haptic force comes from the undeformed reference surface
/// (Popescu, Burdea, Bouzit, section 3.3); the surface is published again, deformed, when the stroke closes (plastic).
/// Drains ToolSamples in order and applies the swept volume of each consecutive pair (a capsule for
/// the ball tool; the sample's op: subtract, or union / paint with the sample's material) to the
/// model, all samples drained in one step as one batch on the BooleanBackend (the GPU or the CPU),
/// re-contours only the dirty tiles, and publishes the active surface
/// around the newest tool position. The model is a pure function of the sample stream: batching
/// changes only when work happens, not the result.
class SculptThread {
public:
    /// All references must outlive the thread. The initial snapshot is published centred on start_m
    /// (world m; throws tridex::Error when it is not finite).
    /// tool_radius_m and tool_span_m (m, >= 0; the ball radius and the largest distance of a contact point
    /// from the tool centre, haptics::max_point_distance_m) size the active-surface window so that it covers
    /// the whole tool (compute::tool_extent_m); the radius of each sample replaces tool_radius_m once
    /// samples arrive.
    SculptThread(compute::TriDexel& model, compute::Contourer& contourer, SpscRing<ToolSample>& samples,
                 TripleBuffer<ActiveSurface>& surface, const Vec3& start_m, double tool_radius_m = 0.0,
                 double tool_span_m = 0.0);
    ~SculptThread();
    SculptThread(const SculptThread&) = delete;
    SculptThread& operator=(const SculptThread&) = delete;

    /// Runs the Booleans on `backend` (built on the same model) instead of the built-in CPU reference.
    /// `backend` must outlive the thread. Throws tridex::Error when the thread runs.
    void use_backend(BooleanBackend& backend);
    /// Re-contours dirty tiles into `share` (on the GPU, from the GPU backend's slabs) instead of the CPU
    /// Contourer, which is then left untouched (its mesh stays the one it held). Still after the active
    /// surface is published; mesh publishes then carry MeshFrame::gpu and no mesh. `share` must outlive the
    /// thread and have contoured every tile already. Throws tridex::Error when the thread runs.
    void use_gpu_contour(GpuContourShare& share);
    /// The session's mesh tools: a sample whose tool is ToolKind::kMesh sweeps tools[tool.mesh_id] (a sample
    /// naming an id outside the table fails the thread with tridex::Error), each mesh in the tool frame of
    /// core/tool_shape.hpp (+y the tool axis) turned by the sample's full orientation (Sweep::orientation).
    /// Throws tridex::Error when the thread runs.
    void use_mesh_tools(std::vector<std::shared_ptr<const compute::MeshTool>> tools);
    /// Appends every batch the thread applies to `journal` (one record per step, after the batch was applied;
    /// nothing after a failure), syncs it when due while idle, and syncs it once more when the thread ends. The
    /// journal's own errors never stop the thread (JournalWriter records them). `journal` must outlive the thread.
    /// Throws tridex::Error when the thread runs.
    void use_journal(compute::JournalWriter& journal);
    /// Hands every batch and mark the journal would get to `stream` too, in the same order, each followed by
    /// stream.after_record(model) (compute/journal/tool_stream.hpp), with or without a journal: a replica of the
    /// model elsewhere (a cluster's render ranks, a shared session's joiners) follows it. Called again, adds another
    /// stream: each gets every record, in the order they were added. `stream` must outlive the thread. Throws
    /// tridex::Error when the thread runs.
    void use_stream(compute::ToolStreamSink& stream);
    /// Calls `observer` (on the sculpt thread, or here once at once with a fresh snapshot around the newest centre)
    /// with every active-surface snapshot just before it is published: a device that renders contact next to
    /// itself (net, local rendering) gets the surface without the haptic thread's help. Throws tridex::Error when
    /// the thread runs.
    void observe_surface(std::function<void(const ActiveSurface&)> observer);
    /// A shared session: takes other sites' samples and requests from `intake` (after its own tool's samples, each
    /// pass), in the order they were queued. Each site's sweeps join its own samples, one stroke is open at a time
    /// (another site's cut closes it), and an undo or redo takes back only the asker's own newest stroke, refused
    /// (observe_refusals) when another site's stroke is newer or interrupted it, or another site's stroke is open
    /// (SiteStrokes). The journal and the stream get every site's samples in the order applied. `intake` must outlive
    /// the thread. Throws tridex::Error when the thread runs.
    void use_site_intake(SiteIntake& intake);
    /// A joiner of a shared session: the model follows the host's stream, which a network thread queues in `intake`
    /// (SiteIntake::push_host_samples, push_host_mark, push_host_check) in the host's order, applied by the host's rules
    /// (SiteSweeps; strokes closed, undone and redone at the host's marks, each checked against this replica's serials
    /// and rays, and the model's digest at the host's checks: a mismatch fails the thread, after outlet.mismatch). This site's own tool (the ring's samples) is not applied here: each pass hands
    /// its samples, tagged own_site, to outlet.samples, and the active surface follows them at once. Undo, redo and
    /// stroke-close requests go to outlet.request (the host decides; its marks come back); saves are taken here.
    /// Both functions are called on the sculpt thread, must be quick and must not throw. Throws tridex::Error when the
    /// thread runs, own_site is not 1..kMaxSites-1, or a function is missing.
    /// `from`: the follower joined late and starts from a snapshot's history and sweeps (its model is the snapshot's);
    /// without it, from the session's start. Throws tridex::Error as well for malformed history bytes (at start()).
    void follow_host(SiteIntake& intake, std::uint8_t own_site, FollowerOutlet outlet,
                     std::optional<FollowStart> from = std::nullopt);
    /// A host: takes each snapshot request of the intake (SiteIntake::push_snapshot) where it stands in the stream,
    /// closes the open stroke (journalled and streamed like any close) and calls `out` with the snapshot, on the
    /// sculpt thread, before the next record is streamed. Throws tridex::Error when the thread runs.
    void use_snapshots(std::function<void(SculptSnapshot&&)> out);
    /// Asks, from any thread, for a snapshot of the model as it stands for this session's own replicas (a cluster's
    /// render rank joining the wall, or replacing one that failed; SculptSnapshot::site is 0). The thread takes it at
    /// its first pass with no stroke open (it never closes one, so the person's stroke stays one undo step), between
    /// two records of its stream, and hands it to the function given to use_snapshot_asks; asks made before it is
    /// taken are served by it (SculptSnapshot::asks). On a session of its own, a shared session's host and a follower
    /// alike. Returns the number of asks so far, this one included.
    std::uint64_t ask_snapshot() { return snapshot_asks_.fetch_add(1, std::memory_order_acq_rel) + 1; }
    /// Where asked snapshots go (ask_snapshot), called on the sculpt thread before the next record is streamed.
    /// Throws tridex::Error when the thread runs.
    void use_snapshot_asks(std::function<void(SculptSnapshot&&)> out);
    /// Calls `observer` on the sculpt thread with every refused undo or redo (a shared session tells the asker who
    /// stands in the way). Throws tridex::Error when the thread runs.
    void observe_refusals(std::function<void(const SculptRefusal&)> observer);
    /// Sets the undo history's memory budget (bytes > 0; default compute::UndoHistory::kDefaultBudgetBytes).
    /// Throws tridex::Error when the thread runs or the budget is 0.
    void set_history_budget(std::size_t bytes);
    /// Whether a stroke that cut removes the specks it left floating when it closes (SculptHistory::remove_islands;
    /// default false: the session spec decides, and a journal's replay must use the same setting). The removal is
    /// part of the stroke: journalled with it, undone and redone with it, published and contoured at once. Throws
    /// tridex::Error when the thread runs.
    void remove_islands(bool on);
    /// Whether a stroke is a held button (default false: a force device's stroke ends when the tool leaves the
    /// material, closed after kStrokeIdleS of device time without a change). On for input whose stroke is a held
    /// button (the mouse stylus, a Flystick's trigger: samples carry op none while it is up, which closes the stroke):
    /// - no stroke closes for idling, so holding still mid-drag keeps one stroke one undo step;
    /// - an undo or redo request taken while the local tool cuts (its newest sample carries an op) waits until the
    ///   local tool stops cutting (the release, or a gap in its samples), and is then taken after that sample (its
    ///   mark counts it), so that an undo takes back the whole drag when the thread had drained part of it. Every
    ///   later request (a save, a coarseness change too) waits behind it, in order; at most kMaxHeldRequests wait,
    ///   further ones are dropped (counted in SculptStats::held_requests_dropped). Requests still waiting when the
    ///   thread stops are taken then. A joiner (follow_host) sends its undos and redos to the host after its own
    ///   samples up to the release, also at stop.
    /// Throws tridex::Error when the thread runs.
    void strokes_end_on_release(bool on);
    /// Replays a recorded session's marks (SculptStats::marks of the live session, in order): the thread takes each
    /// as a request once it has drained exactly mark.after_samples samples (splitting a step's batch there, so the
    /// sweeps before and after it fall as they did live), and closes no stroke for idling, even with no marks (the
    /// live idle closes are among them). With the live session's samples, the strokes, undos and redos, and so the
    /// model, are the live session's. Throws tridex::Error when the thread runs, when after_samples decreases from
    /// one mark to the next, or when a mark's request is kSave.
    void follow_marks(std::vector<SculptMark> marks);
    /// Writes a checkpoint model with `write` (on the sculpt thread, never the haptic thread) when at least
    /// `interval_s` (s, > 0) of wall time passed since the session started or the last checkpoint, the model changed
    /// since, and no stroke is open; then appends a checkpoint record to the journal (use_journal) naming the file.
    /// `write` gets the CPU model and returns the file it wrote (atomically: a failure leaves the previous one) or
    /// throws tridex::Error; a failure is kept in stats().checkpoint_error and no more checkpoints are tried.
    /// Throws tridex::Error when the thread runs or interval_s is not finite and > 0.
    void use_checkpoints(std::function<CheckpointFile(const compute::TriDexel&)> write, double interval_s);
    /// Saves the model on request (SculptRequest::kSave), on the sculpt thread between steps: `save` gets the CPU
    /// model and returns a line saying what it wrote, or throws tridex::Error (kept in save_status(); sculpting goes
    /// on). Without a saver a kSave request is counted as a failure ("no save file"). Throws tridex::Error when the
    /// thread runs.
    void use_saver(std::function<std::string(const compute::TriDexel&)> save);
    /// Checks, before a coarseness change (SculptRequest kFiner, kCoarser) re-samples `model` onto `resolution` cells
    /// along its longest side, that the session has the memory for it: `check` throws tridex::Error naming what it
    /// would take (the request is then refused with that line) or returns the bytes the new model may take
    /// (compute::resample_model's max_bytes). Without a check, only resample_model's own estimate is held to no limit.
    /// Throws tridex::Error when the thread runs.
    void use_lattice_check(std::function<std::size_t(const compute::TriDexel& model, int resolution)> check);
    /// With use_tile_lod: after a coarseness change to a lattice where coarse groups apply, the new lattice is first
    /// shown by its coarsest group levels and its tiles are contoured after them, nearest the tool first, as a
    /// coarse-first start-up (true, the default); false: every tile is contoured before the change is published.
    /// Throws tridex::Error when the thread runs.
    void coarse_first_on_lattice_change(bool on);
    /// The saves so far and whether the journal and checkpoints still work (any thread; takes a mutex the sculpt
    /// thread holds only to update it).
    SaveStatus save_status() const;
    /// A copy of the live counters (SculptLive): steps, the undo history's bytes and the step times so far (any thread;
    /// takes a mutex the sculpt thread holds only to update them, once per step and once per pass).
    SculptLive live() const;
    /// Queues an undo, redo, stroke-close or save request for the sculpt thread (taken at its next step, within about a
    /// millisecond when idle, or later when it waits for a release: strokes_end_on_release). One thread may call it
    /// (a single-producer queue); false when 64 requests are already waiting. Safe while the thread runs; requests
    /// queued before start() are taken at its first step.
    bool request(SculptRequest r);
    /// Device time (s) without a change after which an open stroke closes.
    static constexpr double kStrokeIdleS = 0.5;
    /// Undo and redo requests that may wait for a held stroke's release (strokes_end_on_release).
    static constexpr std::size_t kMaxHeldRequests = 64;
    /// Coarse-first start-up: wall time (s) a pass of the thread spends contouring regions of tiles (at least one),
    /// as long as no change is waiting (use_tile_lod); after a stroke drawn coarse, contouring its deferred tiles.
    static constexpr double kRefineSliceS = 0.1;
    /// A mesh publish of background work (start-up's refinement, deferred tiles, levels) waits for a waiting cut's
    /// pass, which publishes it too, for at most this long after the last publish (s).
    static constexpr double kBackgroundPublishWaitS = 0.25;

    /// Starts the thread. Throws tridex::Error when it is already running.
    void start();
    /// Processes every sample still in the ring, closes the open stroke (journalled), takes the requests still held
    /// for a release (a joiner sends them to the host, which its own model then does not follow), then joins; call
    /// it after the producer (the haptic loop) has stopped. Idempotent. Rethrows the first exception the thread hit
    /// (a bad sample, out of memory); after such a failure the thread kept draining the ring without applying
    /// anything, and the held requests are dropped (counted).
    void stop();
    /// Counters; call after stop().
    const SculptStats& stats() const { return stats_; }
    /// How many passes of the thread's loop have finished (any thread). A pass takes every queued request, drains
    /// the ring, applies and publishes; so once two more passes finish after a caller queued requests and the ring
    /// is empty, all of them have taken effect, unless requests_held() is above 0.
    std::uint64_t passes() const { return passes_.load(std::memory_order_acquire); }
    /// Requests waiting for the local tool's release (strokes_end_on_release), as of the thread's last change of
    /// them; while any wait, passes() moving does not mean a request was taken. Any thread.
    std::size_t requests_held() const { return held_count_.load(std::memory_order_acquire); }
    /// Tiles and groups whose levels of detail are still being built (use_tile_lod), as of the thread's last
    /// pass. Any thread.
    std::size_t lod_tiles_pending() const { return lod_pending_.load(std::memory_order_acquire); }

    /// Hands the contoured mesh to a renderer through `out` (lock-free latest-value hand-off; the
    /// renderer is its one reader and takes the newest MeshFrame without waiting). Publishes the current
    /// mesh at once (on the calling thread), then, on the sculpt thread, after re-contouring: a sculpted change
    /// at once when the renderer has taken the last publish (TripleBuffer::unread), else, and for levels of
    /// detail alone, at most once per min_interval_s of wall time (s, >= 0; a change inside the interval is
    /// published when it passes, even if no more samples come, and at the latest by stop()). The haptic path is untouched:
    /// the active surface is still published before contouring. `out` must outlive the thread. Call
    /// before start(). `form` chooses the whole mesh or per-tile meshes (MeshFrame). `sculpted`, when given,
    /// is notified after each publish that carries a sculpted change (MeshFrame::oldest_sample_s set), so a
    /// renderer may start a frame for it; it must outlive the thread. Throws tridex::Error when the thread runs
    /// or min_interval_s is not finite and >= 0.
    void publish_mesh_to(TripleBuffer<MeshFrame>& out, double min_interval_s = 1.0 / 60.0,
                         MeshForm form = MeshForm::kWhole, ChangeSignal* sculpted = nullptr);
    /// With MeshForm::kTiles: builds the levels of detail of the tile meshes it publishes (TileSurface::lods,
    /// compute::build_tile_lod) for tiles whose version changed, and of the groups of tiles over them
    /// (MeshFrame::groups, TileLodOptions::group_depth; made as options.lod says), on a level-of-detail worker
    /// (options.threads threads at Linux nice value options.nice; compute::TileSurfaceCache::
    /// build_lods_in_background), so that neither start-up
    /// nor a stroke waits for them: each mesh publish queues the tiles it re-contoured (a stroke's ahead of
    /// start-up's), and every pass of this thread takes in what the worker finished and publishes it with the
    /// next mesh. Until then a tile is published with its full mesh only, then again with its levels and a new
    /// version; a group whose tiles changed is published without levels until rebuilt. Call before
    /// publish_mesh_to() (whose first publish queues every tile). Throws tridex::Error when the thread runs,
    /// after publish_mesh_to(), or as compute::LodWorker (cell_m, threads, nice). With use_gpu_contour the tiles
    /// are read back from the GPU contour at each publish (MeshFrame::gpu). On the CPU contour of a model of at
    /// least options.coarse_groups_from_cells cells along its longest side, the groups of tiles take their levels
    /// from the model read at coarser strides (TileSurfaceCache::use_coarse_groups), the coarser ones in the first
    /// publish.
    /// With options.coarse_first (coarse groups only, else tridex::Error; the Contourer must not have contoured
    /// the model: its dirty tiles are the ones to contour): the first publish holds no tile, only the groups with the
    /// coarsest depth's levels, which the renderer draws where no tile stands in (TileGroupSurface::children_cover);
    /// each later pass of the thread reads a finer coarse depth or contours the next region of tiles (nearest the
    /// tool first; compute::StartupRefiner), published as start-up's tiles; a finer coarse depth is read only while no
    /// stroke is open. A change (stroke, undo) during it contours at once the tiles of the depth-1 groups it reaches
    /// (StartupRefiner::contour_with_change), so it is drawn at full resolution; the coarsest groups within reach are
    /// redrawn with it (TileSurfaceCache::use_coarse_groups). stop() contours what is left.
    void use_tile_lod(const compute::LodWorkerOptions& options);
    /// With a coarse-first start-up or lattice change: after the finer coarse depths are read, contours only the tile
    /// groups `requests` asks for (the frames' compute::DetailRequests), finest first, for up to kRefineSliceS per
    /// pass, instead of every region; tiles no frame needs stay coarse until stop(). With strokes drawn coarse
    /// (LodWorkerOptions::stroke_coarse), the deferred tiles of those groups too, also in a pass without samples while
    /// the stroke is open. Throws when the thread runs.
    void refine_on_demand(compute::DetailRequests& requests);
    /// With strokes drawn coarse (LodWorkerOptions::stroke_coarse): the groups the frames drew at a level within the
    /// pixel bound (compute::DrawnGroups), read at each mesh publish, so that a stroke rebuilds the coarse levels the
    /// frames draw and leaves those under them for later (TileSurfaceCache::frames_drew). Throws when the thread runs.
    void follow_drawn_groups(compute::DrawnGroups& drawn);

private:
    // A cutting sample's times (ToolSample::made_s, t_s; infinity: none), kept for the oldest of several.
    struct SampleTimes {
        double made_s = std::numeric_limits<double>::infinity();
        double t_s = std::numeric_limits<double>::infinity();
        void keep_older(const SampleTimes& o) {
            if (o.made_s < made_s) *this = o;
        }
    };
    // One step's progress through its samples: drained_[begin, n) not journalled yet; whether the model changed.
    struct StepWork {
        bool changed = false;
        std::size_t begin = 0, n = 0;
        SampleTimes oldest_cut;  // the oldest cutting sample's
    };
    void run();
    bool step();  // one drain + apply + contour + publish; false when there was nothing to do
    void take_sample(const ToolSample& s, StepWork& w);  // into batch_, closing the stroke where it ends
    bool take_sites(StepWork& w, bool& sampled);         // other sites' samples and requests; true when any
    bool take_requests();                            // undo / redo / close requests; true when one was taken
    bool holds_request(SculptRequest r) const;       // r waits for the local tool's release (strokes_end_on_release)
    void take_held_requests();                       // the requests that waited, in order
    void take(SculptRequest r, std::uint8_t site);   // one request of `site`, recorded in stats_.marks (own site)
    void save_now();                                 // a kSave request
    void refuse(SculptRequest r, std::uint8_t site, std::uint8_t by_site, std::uint64_t serial);
    bool take_marks(StepWork& w);                    // follow_marks due now; flushes first
    // An undo or redo on the history, journalled, published and contoured (t0: when it was taken); serial 0: none.
    compute::UndoHistory::Change restore(bool undo, const std::chrono::steady_clock::time_point& t0);
    void change_coarseness(SculptRequest r, std::uint8_t site);  // a kFiner or kCoarser request
    std::string coarseness_refusal() const;  // why this session cannot change its lattice ("" when it can)
    void relattice();  // the Contourer and the tile cache made again for the model's new lattice
    void relattice_after(bool undo);  // relattice() after an undo or redo of a coarseness change, and its line
    void coarseness_line(const std::string& line);  // into save_status_.coarseness
    std::function<std::size_t(const compute::TriDexel&, int)> lattice_check_;
    std::optional<compute::LodWorkerOptions> lod_options_;  // use_tile_lod's, for relattice()
    bool relattice_coarse_first_ = true;                    // coarse_first_on_lattice_change
    void arm_tile_lod(const compute::LodWorkerOptions& options);  // use_tile_lod's work on tile_cache_
    void forward_own(ToolSample s);         // follow_host: one own sample, to own_
    void follow_mark(const SiteEntry& e);   // follow_host: one of the host's marks
    void follow_check(std::uint64_t host_digest);  // follow_host: the model's digest against the host's
    void flush(std::size_t begin, std::size_t end, bool& changed);  // apply batch_, journal drained_[begin, end)
    // End the open stroke and journal it; by_site: another site's sample or request closed it (its gesture goes on).
    void close_stroke(std::optional<std::uint8_t> by_site = std::nullopt);
    double open_t_s() const;  // device time of the open stroke's site's newest sample
    // A stroke-end, undo or redo mark to the journal and the stream (then the stream's after_record).
    void record_mark(std::uint32_t type, std::uint64_t serial, std::uint64_t rays);
    // Re-contours the dirty tiles and records a changing step (Booleans from t0 to t1, then the contour); returns
    // the contour's time, ms. stroke_tail: the change ends a stroke just closed (close_stroke), so it is deferred as
    // the stroke's own steps were.
    double contour_changed(const std::chrono::steady_clock::time_point& t0,
                           const std::chrono::steady_clock::time_point& t1, bool stroke_tail = false);
    void checkpoint_if_due();
    void note_persistence();  // copies a new journal or checkpoint error into save_status_
    void publish(const Vec3& centre_m);
    void publish_mesh();                // assemble and hand over the mesh (mesh_out_ set)
    void publish_mesh_if_due(bool force);  // publish a pending mesh when the interval passed (or force)
    void collect_lods();                   // take in finished levels of detail (use_tile_lod)
    // True when a cutting sample (or a request) waits: background work yields to it. Moves the ring's samples into
    // carried_ to look at them; pop_sample() hands them on in order.
    bool cut_waiting();
    bool pop_sample(ToolSample& s);  // the next sample: carried_ first, then the ring
    void share_tile_cache(MeshFrame& slot);  // tile_cache_'s tiles and groups into slot, sharing unchanged ones
    // Coarse-first start-up and strokes drawn coarse: one step of the refinement (a finer coarse depth, a region of
    // tiles, the groups the frames asked for, deferred tiles), or all of it.
    void refine_startup(bool finish);
    std::size_t refine_requested(const std::function<bool()>& in_slice, int block_depth);  // DetailRequests' groups
    void refresh_tile_cache();  // tile_cache_ from the contour, through the refiner and the deferral while they run
    void count_deferred();      // the deferral's tiles contoured since the last count into stats_

    compute::TriDexel& model_;
    std::unique_ptr<BooleanBackend> own_backend_;  // the CPU reference unless use_backend() was called
    BooleanBackend* backend_ = nullptr;
    std::vector<compute::Sweep> batch_;           // reused between steps
    std::vector<ToolSample> drained_;             // the step's samples, for the journal; reserved to the ring's capacity
    std::vector<ToolSample> carried_;             // samples taken from the ring by cut_waiting(), not stepped yet
    std::size_t carried_next_ = 0;                // the first of carried_ not handed on
    bool carried_cut_ = false;                    // one of carried_ cuts
    std::unique_ptr<SculptHistory> history_;       // made at start() on the chosen backend
    std::size_t history_budget_ = compute::UndoHistory::kDefaultBudgetBytes;
    SpscRing<SculptRequest> requests_{64};
    bool idle_close_ = true;                         // !strokes_end_on_release
    std::vector<SculptRequest> held_requests_;       // requests waiting for the local tool's release
    std::atomic<std::size_t> held_count_{0};         // held_requests_.size(), for requests_held()
    bool remove_islands_ = false;                    // remove_islands
    std::vector<SculptMark> follow_;                 // follow_marks
    std::size_t next_mark_ = 0;                      // the first of follow_ not yet taken
    bool following_ = false;                         // follow_marks was called (even with no marks)
    double last_change_t_s_ = 0.0;                 // device time of the newest sample of a batch that changed the model
    bool stroke_changed_ = false;                  // the open stroke changed the model
    UndoClock undo_clock_;                         // when each undo step was made and undone (SculptLive::undo_times)
    // The open stroke pushes clay (ToolOp::kPush): the haptic loop feels the surface as it was when the stroke began
    // (Popescu, Burdea, Bouzit 3.3: force from the undeformed reference; plastic, so the reference becomes the
    // deformed surface when the stroke ends).
    bool push_stroke_ = false;
    bool holding_reference() const { return push_stroke_ && history_ && history_->stroke_open(); }
    std::function<CheckpointFile(const compute::TriDexel&)> checkpoint_write_;
    std::function<std::string(const compute::TriDexel&)> saver_;
    std::function<void(const ActiveSurface&)> surface_observer_;
    mutable std::mutex save_mutex_;
    mutable std::mutex live_mutex_;
    SculptLive live_;
    SaveStatus save_status_;
    bool journal_noted_ = false, checkpoint_noted_ = false;
    double checkpoint_interval_s_ = 0.0;
    bool changed_since_checkpoint_ = false;
    std::chrono::steady_clock::time_point checkpoint_last_{};
    compute::JournalWriter* journal_ = nullptr;
    std::vector<compute::ToolStreamSink*> streams_;
    std::vector<std::shared_ptr<const compute::MeshTool>> mesh_tools_;  // ToolShape::mesh_id -> mesh
    std::shared_ptr<const compute::MeshTool> mesh_tool(std::uint32_t id) const;
    std::vector<std::shared_ptr<const compute::MeshTool>> mirrored_mesh_tools_;  // mesh_id -> mirror image, on first use
    std::shared_ptr<const compute::MeshTool> mirrored_mesh_tool(std::uint32_t id);
    compute::Contourer& contourer_;
    GpuContourShare* gpu_contour_ = nullptr;  // set: contour on the GPU instead of contourer_
    SpscRing<ToolSample>& samples_;
    TripleBuffer<ActiveSurface>& surface_;
    bool have_prev_ = false;
    ToolSample prev_{};                    // the newest sample of local_site_ (the active surface follows it)
    std::uint8_t local_site_ = 0;          // this session's own tool's site
    SiteStrokes sites_;                    // each site's sweeps, and whose strokes the history holds
    SiteIntake* intake_ = nullptr;         // use_site_intake
    std::vector<SiteEntry> site_entries_;  // drained from intake_, reused
    std::function<void(const SculptRefusal&)> refusal_observer_;
    bool follower_ = false;                // follow_host
    FollowerOutlet outlet_;
    std::vector<ToolSample> own_;          // follow_host: this pass's own samples
    std::uint64_t last_closed_serial_ = 0; // the newest stroke closed (serial != 0)
    std::function<void(SculptSnapshot&&)> snapshot_out_;  // a host: where snapshots go
    std::optional<FollowStart> follow_start_;               // a late follower: installed at start()
    void take_snapshot(std::uint8_t site);
    SculptSnapshot snapshot_now(std::uint8_t site) const;  // the model, history and sweeps as they stand
    void serve_snapshot_asks();                             // an asked snapshot, when no stroke is open
    std::function<void(SculptSnapshot&&)> ask_out_;         // use_snapshot_asks
    std::atomic<std::uint64_t> snapshot_asks_{0};           // ask_snapshot calls so far
    std::uint64_t snapshot_asks_served_ = 0;                // of them, served by a snapshot
    Vec3 published_centre_m_;
    double tool_radius_m_ = 0.0;  // for the window's extent until the first sample
    double tool_span_m_ = 0.0;
    std::uint64_t sequence_ = 0;
    SculptStats stats_;
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> passes_{0};
    std::atomic<std::size_t> lod_pending_{0};
    std::exception_ptr failure_;  // first exception on the thread, rethrown by stop()
    std::thread thread_;
    TripleBuffer<MeshFrame>* mesh_out_ = nullptr;  // renderer hand-off; nullptr = no mesh publishing
    ChangeSignal* mesh_sculpted_ = nullptr;        // notified after a publish with a sculpted change
    double mesh_interval_s_ = 0.0;
    bool mesh_pending_ = false;                     // contoured since the last mesh publish
    std::uint64_t mesh_version_ = 0;
    SampleTimes pending_sample_;      // MeshFrame::oldest_sample_s and oldest_sample_t_s of the next publish
    SampleTimes last_oldest_sample_;  // the same of the last publish
    MeshForm mesh_form_ = MeshForm::kWhole;
    compute::TileSurfaceCache tile_cache_;                              // kTiles: rebuilt per changed tile
    std::unique_ptr<compute::StartupRefiner> refiner_;                  // coarse-first start-up while it runs
    std::unique_ptr<compute::DeferredContour> deferral_;                // strokes drawn coarse (stroke_coarse)
    compute::DetailRequests* detail_ = nullptr;                         // refine_on_demand
    compute::DrawnGroups* drawn_ = nullptr;                             // follow_drawn_groups
    std::vector<std::shared_ptr<const compute::TileSurface>> shared_tiles_;  // kTiles: last published, by id
    std::vector<std::shared_ptr<const compute::TileGroupSurface>> shared_groups_;  // kTiles: last published, by id
    std::chrono::steady_clock::time_point mesh_last_{};
};

}  // namespace tridex::app
