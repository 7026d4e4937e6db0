// app/session/cluster/cluster_replica.hpp - a render rank's copy of the session's model: built from the session spec,
// carved by the replicated tool sample stream, contoured tile by tile and drawn through a viewport of the wall.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "app/scene/workpiece_source.hpp"
#include "app/session/cluster/cluster_config.hpp"
#include "app/session/cluster/frame_message.hpp"
#include "app/session/view/tile_view.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/deferred_contour.hpp"
#include "compute/contour/startup_refine.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/runtime/detail_requests.hpp"
#include "renderer/output/stereo_sink.hpp"
#include "renderer/scene/tile_culling.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

/// How a replica contours what it draws where its groups take coarse levels (lod.on and the model has
/// lod.coarse_groups_from_cells cells or more; the cluster config's "startup" and "stroke_contour"). Ignored elsewhere.
struct ReplicaContour {
    /// Start coarse first: no tile is contoured at construction; the first view draws the coarsest group levels, and
    /// each contour() after it reads one finer coarse depth or contours the tiles under the groups the frames want
    /// finer (want_detail), as the desk's start-up does (docs/design/lod.md, "Coarse first at start-up").
    bool coarse_first = false;
    /// Draw strokes coarse: the tiles a stroke changes wait, hidden, while it is open (and its close), and the coarse
    /// group levels over them stand in, finer where the frames want it (want_detail, frames_drew), as the desk draws a
    /// stroke (docs/design/lod.md, "Strokes drawn coarse"). Changed tiles still waiting for a view when a stroke's
    /// records come are deferred with them.
    bool stroke_coarse = false;
};

/// The model of a session as a render rank holds it. Applying rank 0's records in order gives rank 0's model bit
/// for bit (JournalApplier on the CPU reference Booleans, the session's island setting and undo budget).
class ClusterReplica {
public:
    /// Builds the session's workpiece from its spec (spec_to_json's text; prepare_session_workpiece: the same mesh
    /// or saved model file, scan-converted the same way) and contours it. Throws tridex::Error when the spec is
    /// malformed or its workpiece cannot be read or differs from the recorded checksums. With lod.on (the cluster config's "lod", lod_choice), the tiles' and
    /// groups' levels are built on worker threads of their own (compute::LodWorker) and taken in by contour(), so
    /// neither a frame nor the records wait for them.
    /// `late`: the render rank joined a running wall (a hello with HelloMessage::first_record and the history): the
    /// spec's model is the one it joined with, the undo history and each site's sweeps start from the hello's, and
    /// the first record applied is first_record. Throws tridex::Error as well for malformed history bytes.
    /// `how`: a coarse-first start-up and strokes drawn coarse (ReplicaContour).
    explicit ClusterReplica(const std::string& spec_json, const LodChoice& lod = {}, const HelloMessage* late = nullptr,
                            const ReplicaContour& how = {});
    ~ClusterReplica();

    /// The model's digest (compute::model_digest).
    std::uint64_t digest() const;
    /// Applies `m`'s records; when m carries a check, compares the digest after m.check_after records with it and
    /// returns this replica's digest when they differ (nullopt when equal or unchecked). Throws tridex::Error as
    /// JournalApplier::apply (a record the model refuses).
    std::optional<std::uint64_t> apply(const FrameMessage& m);
    /// Re-contours the tiles the records changed that `frusta` need: each group of changed tiles (26-connected) is
    /// contoured whole when one of its tiles, or a tile next to one, may be visible in one of them (the tile's lattice
    /// box grown by a cell, renderer::may_be_visible); the other groups stay marked and wait for a view that needs
    /// them (neighbouring tiles share the vertices on their border, so a group is never split). No frusta: every
    /// changed tile. The tiles drawn by view(); with levels of detail, the levels the worker finished are taken in
    /// first, and the groups' coarse levels out of reach of the changes are rebuilt while tiles keep changing
    /// (TileSurfaceCache::build_away_from_changes), those within reach once they settle. Throws tridex::Error when a
    /// frustum's box test does.
    /// Strokes drawn coarse (ReplicaContour::stroke_coarse): while the records applied since the last contour() had
    /// a stroke open, the tiles they changed are not contoured but deferred (compute::DeferredContour), and the
    /// coarse levels over them are rebuilt instead (TileSurfaceCache::defer_tiles; one depth finer under the groups
    /// want_detail() named, the waiting levels of those under a group frames_drew() named left for later). The
    /// deferred tiles under the groups want_detail() named are contoured within the slice below; once no stroke is
    /// open, those a view may see (or next to one) too, oldest first. Other deferred tiles wait for a view, as
    /// changed tiles do. A change outside a stroke takes the deferred tiles among its tiles or next to one along, and
    /// its group of changed tiles is then contoured now whatever the views (a tile released from the deferral shows
    /// its mesh), so no waiting tile lies next to a deferred one.
    /// During a coarse-first start-up, first: the changed tiles contoured now that start-up has not contoured bring
    /// the start-up tiles of the depth-1 groups they reach (compute::StartupRefiner::contour_with_change, drawn at full
    /// resolution; a waiting group those join is contoured now too), while start-up's tiles in a waiting group stay
    /// start-up's; then one finer coarse depth is read, or, once every depth is, the tiles under the groups
    /// want_detail() named are contoured, finest group first, a block of 4x4x4 tiles at a time, for up to
    /// kStartupSliceS after the first block, with those of the groups whose coarse read missed a surface their tiles
    /// hold (TileSurfaceCache::missed_surface_groups) where a view may see one of their tiles. A tile arrives (the
    /// groups over it stop standing in) once it and its neighbours are contoured (StartupRefiner::publishable) and no
    /// stroke holds it.
    void contour(std::span<const renderer::Frustum> frusta = {});
    /// The groups the last frames drew over their pixel bound because no finer level or tile could stand in yet
    /// (renderer::FrameStats::groups_wanting_detail, of every viewport), added to those the next contour() refines
    /// (which then forgets them: frames name them again; at most compute::DetailRequests::kMaxIds wait). Nothing
    /// unless the replica started coarse first or draws strokes coarse.
    void want_detail(std::span<const std::uint64_t> group_ids);
    /// Strokes drawn coarse: the groups the last frames drew at a level within their pixel bound
    /// (renderer::FrameStats::groups_at_level, of every viewport), added to those the next contour() hands the tile
    /// cache (TileSurfaceCache::frames_drew). Nothing otherwise.
    void frames_drew(std::span<const std::uint64_t> group_ids);
    /// Contours everything held back: reads every coarse depth a coarse-first start-up has not read yet, contours
    /// every tile it has left, the changed tiles waiting for a view and a stroke's deferred tiles. The contour then
    /// equals, bit for bit, that of a replica that contoured everything at once.
    void finish_contour();
    /// Groups waiting for their coarse level (a coarse-first start-up's finer depths, a stroke's; 0 without coarse
    /// groups).
    std::size_t coarse_levels_waiting() const { return tiles_.coarse_waiting(); }
    /// Tiles a coarse-first start-up has not contoured yet (0 outside one, and once it is done).
    std::size_t startup_pending() const;
    /// Tiles a coarse-first start-up has contoured so far (on demand, with changes, or by finish_contour).
    std::uint64_t startup_tiles_refined() const { return startup_refined_; }
    /// True when this replica started coarse first (coarse_first and coarse groups apply).
    bool started_coarse() const { return started_coarse_; }
    /// The most time one contour() spends on start-up's refinement beyond its first unit of work, s.
    static constexpr double kStartupSliceS = 0.03;
    /// Changed tiles the last contour() left for a later view (0 after one without frusta), a stroke's deferred tiles
    /// not included.
    std::size_t tiles_deferred() const { return deferred_; }
    /// True when this replica draws strokes coarse (ReplicaContour::stroke_coarse and coarse groups apply).
    bool strokes_coarse() const { return deferral_ != nullptr; }
    /// Strokes drawn coarse: tiles a stroke changed whose contour waits now.
    std::size_t stroke_tiles_waiting() const;
    /// Strokes drawn coarse: tile deferrals so far (a tile changed in several contour() calls counts in each).
    std::uint64_t stroke_tiles_deferred() const { return stroke_deferred_; }
    /// Strokes drawn coarse: deferred tiles contoured so far (by the slice, with a change or with start-up's tiles).
    std::uint64_t stroke_tiles_contoured() const { return stroke_contoured_; }
    /// Tiles contoured by every contour() so far (the first, at construction, included).
    std::uint64_t tiles_contoured() const { return contoured_; }
    /// Tiles and groups whose start-up levels are not built yet (0 without levels of detail; during a coarse-first
    /// start-up, its tiles not contoured yet count too).
    std::size_t lod_pending() const;
    /// The contour (its tiles as the last contour() left them).
    const compute::Contourer& contourer() const { return *contourer_; }
    /// What frame `m` draws: the contoured tiles, the tool as rank 0 drew it, no workspace box or overlay.
    renderer::SceneView view(const FrameMessage& m) const;
    /// The session's reference objects this replica could not load (its meshes are read from the paths rank 0's spec
    /// names), one line each: those are not drawn here. Empty when all are.
    const std::vector<std::string>& reference_notes() const { return reference_notes_; }
    /// The camera of viewport `v` for frame `m`: its screen and eye(s), moved with the scene's navigation
    /// (navigated_camera), a single-eye viewport drawn as a mono view from that eye.
    static renderer::StereoCamera camera(const ClusterViewport& v, const FrameMessage& m);
    /// Moves the exit of the first interval found by one float step: a replica that no longer holds rank 0's model,
    /// for testing the digest check (TRIDEX_CLUSTER_FAULT=RANK:FRAME:diverge). Nothing when the model is empty.
    void diverge();
    /// Samples and records applied so far.
    const compute::JournalApplyStats& applied() const;
    /// The workpiece (its model as carved so far).
    const Workpiece& workpiece() const { return wp_; }

private:
    void load_references(const SessionSpec& spec);
    void update(std::span<const renderer::Frustum> frusta, bool refine);  // contour(); without the slice
    // contour()'s slice (the model's dirty flags clear): start-up's depth or wanted tiles, a stroke's deferred ones
    // (`visible`: per tile, whether a view may see it; empty for every tile).
    void refine_held(const std::vector<std::uint64_t>& wanted, const std::vector<std::uint8_t>& visible, bool stroke);
    // The tile cache from the contour, seen through start-up's refinement and a stroke's deferral.
    void refresh_tiles(const std::vector<std::uint64_t>& wanted, bool stroke);

    Workpiece wp_;
    std::unique_ptr<compute::JournalApplier> applier_;
    std::unique_ptr<compute::Contourer> contourer_;
    compute::TileSurfaceCache tiles_;
    TileView tile_view_;
    bool lod_ = false;
    std::vector<TriMesh> reference_meshes_;                  // the session's reference objects, own frames
    std::vector<renderer::SceneObject> reference_objects_;   // ... placed by their poses, drawn by view()
    std::vector<std::string> reference_notes_;               // references not drawn here, and why
    std::unique_ptr<compute::StartupRefiner> refiner_;       // a coarse-first start-up while it runs
    std::unique_ptr<compute::DeferredContour> deferral_;     // strokes drawn coarse
    compute::DetailRequests wanted_;                         // groups the frames want finer (want_detail)
    compute::DrawnGroups drawn_;                             // groups the frames drew at a level (frames_drew)
    bool stroke_changes_ = false;  // the records applied since the last contour() had a stroke open
    std::uint64_t stroke_deferred_ = 0;
    std::uint64_t stroke_contoured_ = 0;
    bool started_coarse_ = false;
    std::uint64_t startup_refined_ = 0;
    std::size_t deferred_ = 0;
    std::uint64_t contoured_ = 0;
};

}  // namespace tridex::app
