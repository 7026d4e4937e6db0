// compute/contour/contour_tiles.hpp - the contoured surface as per-tile meshes for a renderer, rebuilt only
// where it changed.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "compute/contour/coarse_levels.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/lod_worker.hpp"
#include "compute/contour/tile_group_lod.hpp"
#include "compute/contour/tile_lod.hpp"
#include "compute/contour/tile_mesh_source.hpp"
#include "core/aabb.hpp"
#include "core/duration_histogram.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// One tile's part of the contoured surface, ready for a renderer: the triangles the tile owns, with the
/// vertices they use (its own and its neighbours'), world metres, CCW from outside.
struct TileSurface {
    std::uint64_t id = 0;       ///< tile index in the model's TileGrid (stable across updates)
    std::uint64_t version = 0;  ///< changes whenever this tile's mesh or a vertex it borrows from a neighbour changed
    /// The source's tile version the mesh was read at (TileMeshSource::tile_version; `version` also changes when
    /// the levels arrive, this does not).
    std::uint64_t source_version = 0;
    Aabb bounds_m;              ///< box of mesh.positions, m
    /// The tile's triangles (compact vertex list), in vertex-cache order (order_for_vertex_cache) once its levels are
    /// built by a background worker, or at once without one.
    TriMesh mesh;
    /// Material id per mesh vertex (size = mesh.positions.size(); Contourer::mesh_materials' rule).
    std::vector<std::uint8_t> materials;
    /// Unit normal per mesh vertex: the whole surface's area-weighted normal there, the neighbour tiles' triangles
    /// included (TileMeshSource::tile_mesh), so that tiles sharing a vertex shade it alike; empty when the source
    /// gives none (a renderer then takes the mesh's own normals).
    std::vector<Vec3> normals;
    /// Coarser levels of detail of mesh, finest first (build_tile_lod; empty unless the cache builds them).
    std::vector<TileLodLevel> lods;
    /// true once the levels of this mesh were built (`lods` may then still be empty: the mesh does not simplify).
    bool lods_built = false;
};

/// Levels of detail over a group of neighbouring tiles: 2^depth tiles along each axis, aligned to multiples
/// of 2^depth (tile (tx, ty, tz) is in the depth-d group (tx >> d, ty >> d, tz >> d)). A renderer draws one of
/// the group's levels instead of all its tiles when that level's error is small enough; its outer border is
/// the tiles' full-resolution border (build_group_lod), so it meets any neighbour without cracks.
struct TileGroupSurface {
    static constexpr std::uint64_t kNone = ~std::uint64_t{0};
    std::uint64_t id = 0;              ///< tile_group_id(depth, linear group index); unique among tile and group ids
    int depth = 1;                     ///< 1: 2x2x2 tiles; d: 2^d tiles along each axis
    std::array<int, 3> coords{};       ///< group coordinates at its depth
    /// Changes whenever lods change (a tile under the group changed: the levels are dropped at once, then
    /// rebuilt) or the group first appears. Values from fresh_tile_version().
    std::uint64_t version = 0;
    Aabb bounds_m;                     ///< box of the meshes of every tile under the group, m
    std::vector<std::uint64_t> children;  ///< ascending: tile ids (depth 1) or group ids (depth > 1), non-empty only
    std::uint64_t parent = kNone;      ///< id of the group one depth up, kNone at the deepest depth
    /// Levels over the whole group, finest first (build_group_lod); empty: not built yet, or the group does
    /// not simplify (its children are drawn instead).
    std::vector<TileLodLevel> lods;
    /// true when the tiles and smaller groups under it can draw all of its surface without it (always, outside
    /// start-up's coarse-first refinement). false while some tile under it has not been contoured yet
    /// (TileSurfaceCache::expect_tiles) and the groups under it cannot stand in for it: a renderer then draws one
    /// of its levels, whatever that level's error on screen.
    bool children_cover = true;
    /// true while its levels are dropped or not built yet and will be (re)built: a change reached it, or its depth
    /// waits to be read or simplified. A renderer then draws an enclosing group's level rather than this group's
    /// children at full resolution (renderer::TileGroup::levels_waiting).
    bool levels_waiting = false;
};

/// The id of the depth-d group with linear index `index` in that depth's group grid: the depth in the top
/// byte, so group ids never equal tile ids and sort by depth first.
constexpr std::uint64_t tile_group_id(int depth, std::uint64_t index) {
    return (static_cast<std::uint64_t>(depth) << 56) | index;
}

/// The depth of the group with id `id` (tile_group_id's top byte).
constexpr int tile_group_depth(std::uint64_t id) { return static_cast<int>(id >> 56); }

/// The linear index, in its depth's group grid, of the group with id `id` (tile_group_id's lower 56 bits).
constexpr std::uint64_t tile_group_index(std::uint64_t id) { return id & ((std::uint64_t{1} << 56) - 1); }

/// A Contourer as a TileMeshSource (its tiles as they are). Valid while the Contourer lives.
class ContourerTiles final : public TileMeshSource {
public:
    explicit ContourerTiles(const Contourer& c) : c_(c) {}
    std::size_t tile_count() const override { return c_.tile_count(); }
    std::array<int, 3> tile_dims() const override { return c_.tile_dims(); }
    std::size_t tile_triangle_count(std::size_t t) const override { return c_.tile_triangle_count(t); }
    std::uint64_t tile_version(std::size_t t) const override { return c_.tile_version(t); }
    TriMesh tile_mesh(std::size_t t, std::vector<std::uint8_t>& materials, std::vector<Vec3>& normals) const override {
        return c_.tile_mesh(t, materials, normals);
    }
    bool changed_since(std::uint64_t mark, std::vector<std::uint64_t>& out) const override {
        return c_.tiles_changed_since(mark, out);
    }
    std::uint64_t change_view() const override { return c_.change_id(); }

private:
    const Contourer& c_;
};

/// Keeps TileSurfaces for every non-empty tile of a Contourer, rebuilding only tiles whose contour changed
/// (Contourer::tile_version, which also changes when only materials changed). Versions are unique per process, so one cache may follow a new Contourer
/// (e.g. after a reset): its tiles then all count as changed.
class TileSurfaceCache {
public:
    /// Rebuilds the tiles whose version changed since the last refresh (all on the first call) and drops
    /// tiles that became empty. Returns the number of tiles rebuilt. O(changed tiles' triangles) plus a
    /// scan of the tile versions: of the tiles the source says may have changed since the last refresh
    /// (TileMeshSource::changed_since, under the same change_view) and the cache's own, or of every tile when it
    /// cannot say. Throws tridex::Error as Contourer::tile_mesh (the cache is then unchanged).
    std::size_t refresh(const Contourer& contourer);
    /// As refresh(contourer), from any tiled surface (e.g. the GPU contour read back). Throws as its tile_mesh.
    std::size_t refresh(const TileMeshSource& source);
    /// The current tiles, ordered by id. refresh() may move them: references and pointers into it (e.g. to
    /// a tile's mesh) are valid until the next refresh().
    const std::vector<TileSurface>& tiles() const { return tiles_; }
    /// Total triangles over tiles().
    std::size_t triangle_count() const;
    /// Tiles whose triangle count and version the last refresh() read from its source: those the source named as
    /// maybe changed (TileMeshSource::changed_since), or every tile.
    std::size_t last_refresh_visits() const { return last_visited_; }
    /// Groups whose cover (TileGroupSurface::children_cover) and waiting error the last pass over them looked at.
    /// While start-up's tiles are expected each pass looks at every group; after, only at those over a stroke's
    /// hidden tiles (defer_tiles), those the last pass left uncovered and the next few whose level waits to be
    /// measured.
    std::size_t last_group_pass_visits() const { return last_group_pass_visits_; }
    /// For tests: true makes every pass look at every group, as during start-up (false: the default).
    void pass_every_group(bool every) { pass_every_group_ = every; }
    /// Groups over the current tiles (empty unless enable_lod() with TileLodOptions::group_depth > 0), ordered
    /// by id (so by depth, finest first). Each refresh() keeps the groups none of whose tiles changed and drops
    /// the levels of the others (new version); their levels are rebuilt where the tiles' are. References are
    /// valid until the next refresh().
    const std::vector<TileGroupSurface>& groups() const { return groups_; }

    /// From the next refresh() on, builds the levels of detail (TileSurface::lods, build_tile_lod) of every
    /// tile it rebuilds; call it before the first refresh() so that every tile has them. Large refreshes
    /// (kParallelLodTiles tiles or more, e.g. the first) spread the builds over the machine's cores.
    /// Throws tridex::Error when options.cell_m is not finite and > 0.
    void enable_lod(const TileLodOptions& options);
    /// True after enable_lod().
    bool lod_enabled() const { return lod_; }
    /// Tiles whose levels were built since construction, and the elapsed wall time of those builds, ms
    /// (a build spread over several cores counts its elapsed time once).
    std::size_t lod_tiles_built() const { return lod_tiles_built_; }
    double lod_build_ms() const { return lod_build_ms_; }
    /// Groups whose levels were built since construction (their time is in lod_build_ms()).
    std::size_t lod_groups_built() const { return lod_groups_built_; }
    /// Background building: finished builds thrown away because their tile or group had changed (or gone) since
    /// the job was queued.
    std::size_t lod_discarded() const { return lod_discarded_; }
    /// Rebuilt tiles from which a refresh() builds the levels on every core.
    static constexpr std::size_t kParallelLodTiles = 64;

    /// true: refresh() builds no levels; the tiles it rebuilds wait (full mesh only, TileSurface::lods empty)
    /// until build_pending_lods() builds theirs, so that neither start-up nor a stroke's re-contour waits for
    /// them. false (the default): refresh() builds them at once.
    void defer_lods(bool on) { defer_ = on; }
    /// Tiles and groups whose levels wait for build_pending_lods() (0 unless defer_lods(true) and enable_lod()).
    std::size_t lod_pending() const;
    /// Builds the levels of up to max_tiles waiting tiles (in tile order; on every core from kParallelLodTiles
    /// tiles), and gives each of them a new TileSurface::version (fresh_tile_version(): the published content
    /// changed) while refresh() keeps comparing with the Contourer's version. When no tile waits, builds the
    /// levels of one waiting group whose tiles and smaller groups are all built (finest depth first) and gives
    /// it a new version. Returns the tiles and groups built.
    /// Throws as build_tile_lod (those tiles or that group then keep waiting).
    std::size_t build_pending_lods(std::size_t max_tiles);

    /// From now on the levels are built on a LodWorker of the cache's own (made with `worker`, whose `lod` is
    /// replaced by enable_lod()'s options), never by refresh() or build_pending_lods(): the first refresh()
    /// queues a job per tile, later ones (a stroke's) each tile they rebuild once it has not changed for
    /// LodWorkerOptions::tile_settle_s, ahead of the first's (collect_lods() queues those); collect_lods() takes
    /// the finished ones in and queues each group whose tiles and smaller groups all have theirs (a group a stroke
    /// changed once none of its tiles has changed for LodWorkerOptions::group_settle_s; once start-up's are all
    /// in, the worker's threads drop to LodWorkerOptions::nice, LodWorker::end_startup). Neither waits
    /// for a build. Call after enable_lod() and before the first refresh(). Throws tridex::Error without
    /// enable_lod() or as LodWorker (threads, nice).
    void build_lods_in_background(LodWorkerOptions worker = {});
    /// Background building (build_lods_in_background): queues the stroke's tiles that have not changed for
    /// LodWorkerOptions::tile_settle_s, takes in the levels the worker finished (a tile or group
    /// still as it was when its job was queued gets them and a new version, as build_pending_lods gives; a
    /// stale result is dropped, its newer job is queued), then queues the groups that became ready. Returns the
    /// tiles and groups that got levels. Rethrows the first exception a job threw. O(results + groups).
    /// With coarse groups (use_coarse_groups), it also rebuilds the coarse levels that wait; `stroke_open` (a stroke
    /// is being carved): only those whose coarse tiles are contoured already and read after every change, so no
    /// coarse contour or re-read holds the stroke's samples (see kCoarseContourSliceS, kCoarseUpdateTiles).
    /// `yield` (may be empty): true when the caller's own work waits (a cut): the coarse re-read and the levels that
    /// contour their coarse tiles stop after their current batch or level, as when the slice ends.
    std::size_t collect_lods(bool stroke_open = false, const std::function<bool()>& yield = {});
    /// Background building: per tile or group that got its levels from the worker, the wall time from the refresh()
    /// that re-contoured the tile (its settling included) or from collect_lods() queueing the group's job to
    /// collect_lods() taking the levels in, ms; for a stroke's tiles and groups only, not start-up's; in
    /// DurationHistogram::latency bins.
    const DurationHistogram& lod_latency_ms() const { return lod_latency_ms_; }
    /// From now on the groups of depth options.min_depth and deeper take their levels from the model read at coarser
    /// strides (CoarseGroupLevels: a depth-d group's level is the contour of every 2^d-th ray, with a ring and a
    /// skirt), not from simplifying their tiles: they have their level from the first refresh() on, whether or not
    /// their tiles have theirs. Shallower groups keep simplified levels (as without this call).
    /// The first refresh() builds the levels of the groups of kCoarseStartupDepth and deeper; collect_lods() those of
    /// the finer groups, kCoarseStartupLevelsPerCollect at a time, without waiting.
    /// A refresh() that changes tiles re-reads the coarsest model through them and rebuilds the levels of the
    /// coarsest groups within reach at once (a stroke is drawn coarse, not at full resolution, where a coarse level
    /// is within the pixel bound), as every refresh() does for a coarsest group whose children changed; it drops the
    /// level of every finer group within reach (its children are drawn), and collect_lods() re-reads the finer coarse
    /// models (kCoarseUpdateTiles at a time, between strokes) and then rebuilds those levels, at most
    /// kCoarseLevelsPerCollect at a time, once no tile has changed for LodWorkerOptions::group_settle_s (0 without a
    /// worker). group_depth becomes options.max_depth. `model` is the one the Contourer given to refresh() contours;
    /// it must outlive the cache and not change during refresh() or collect_lods(). Call after enable_lod() and
    /// before the first refresh(). Throws tridex::Error without enable_lod(), after a refresh(), or as
    /// CoarseGroupLevels.
    /// coarse_first: only the coarsest depth's model is read now (the first refresh() gives those groups their levels);
    /// build_coarse_depth() reads the finer ones later, and their groups get their levels through collect_lods().
    /// With options.min_depth 1 the tiles get no simplified levels of their own: a tile's coarser level is its depth-1
    /// group's, and the worker only puts a tile's mesh in vertex-cache order (tile_levels()).
    void use_coarse_groups(const TriDexel& model, const CoarseLevelOptions& options = {}, bool coarse_first = false);
    /// Coarse-first start-up: reads the coarsest depth not read yet (use_coarse_groups with coarse_first); its groups
    /// then get their levels through collect_lods(), at most kCoarseStartupLevelsPerCollect per call
    /// (kCoarseLevelsPerCollect once a stroke changed tiles). Returns false when every depth is read. Reading depth 1
    /// costs about a quarter of the model's whole contour.
    bool build_coarse_depth();
    /// Coarse-first start-up (after use_coarse_groups, before the first refresh()): tiles of the model that hold
    /// surface but are not contoured yet (compute::StartupRefiner::pending_tiles). The groups over them exist from
    /// the first refresh() on, with their coarse levels, and say where no tile stands in for them yet
    /// (TileGroupSurface::children_cover). Throws tridex::Error after a refresh() or without coarse groups.
    void expect_tiles(const std::vector<std::uint64_t>& ids);
    /// Tiles a stroke changed whose full-resolution contour waits (compute::DeferredContour::defer): the next
    /// refresh() counts them as changed whether or not its source shows them, rebuilds the coarse levels over them
    /// down to kDeferredCoarseDepth at once, and they are expected, as start-up's tiles, until they arrive (the groups
    /// over them stand in, with the start-up's provisional error until their tiles are in). Throws tridex::Error
    /// without coarse groups or before the first refresh().
    void defer_tiles(const std::vector<std::uint64_t>& ids);
    /// The finest coarse depth whose levels a refresh() with deferred tiles rebuilds at once (when the coarse levels
    /// reach it; the coarsest depth otherwise): the stroke is drawn from these until its tiles arrive.
    static constexpr int kDeferredCoarseDepth = 3;
    /// Groups a frame drew over its pixel bound because nothing under them could stand in
    /// (renderer::FrameStats::groups_wanting_detail, through compute::DetailRequests). The next refresh() with
    /// deferred tiles (defer_tiles) also rebuilds the waiting levels one depth under each, down to
    /// kDeferredDetailDepth, re-reading that depth's coarse model around them first: a stroke is drawn finer than
    /// kDeferredCoarseDepth only where a frame needs it, and start-up's waiting levels come where a frame needs
    /// them though a stroke is open. Replaces the ids given before; unknown ids are ignored.
    void want_detail(std::vector<std::uint64_t> group_ids) { detail_wanted_ = std::move(group_ids); }
    /// Groups the latest frames drew at one of their levels within the pixel bound (renderer::FrameStats::
    /// groups_at_level, through compute::DrawnGroups): while a stroke's tiles are hidden (defer_tiles), a refresh()
    /// leaves the waiting levels of groups whose parent is among them for settle_coarse_levels() (the frames did not
    /// need them, and draw the parent in a waiting child's place: renderer::groups_standing_in). The coarsest depth is
    /// always rebuilt. Replaces the ids given before; an empty list keeps them.
    void frames_drew(std::vector<std::uint64_t> group_ids);
    /// With coarse groups: true lets collect_lods() build the waiting levels of groups out of reach of the tiles
    /// changed since the levels last settled (coarse_reach: a coarse-first start-up's finer depths, far from a
    /// stroke) while tiles keep changing, instead of waiting until none has changed for LodWorkerOptions::
    /// group_settle_s; those within reach still wait. For a caller whose frames hold no stroke's samples (a cluster
    /// render rank, whose records change tiles in every frame of a stroke). Default false.
    void build_away_from_changes(bool on) { build_away_ = on; }
    /// The finest coarse depth want_detail() brings a stroke's groups to.
    static constexpr int kDeferredDetailDepth = 2;
    /// At most this many levels under the groups of want_detail() are rebuilt by a refresh() (the finest first).
    static constexpr std::size_t kDeferredDetailLevels = 16;
    /// Expected tiles that the next refresh() may show (contoured with their neighbours,
    /// StartupRefiner::take_newly_publishable, DeferredContour::take_visible): they arrive as start-up's tiles, not as
    /// changes (no group level is dropped for them), and start-up's levels are queued once no start-up tile is
    /// expected (the groups stand in until then); a deferred stroke's tiles get theirs as a stroke's. One without
    /// triangles is simply no longer expected. Ids not expected are ignored.
    void arrive(const std::vector<std::uint64_t>& ids);
    /// Expected tiles that changed before their first contour (a stroke's, StartupRefiner::pending_among): no longer
    /// expected, so the refresh() that shows them counts them as changed, as any stroke's tiles.
    void stop_expecting(const std::vector<std::uint64_t>& ids);
    /// Tiles expected and not arrived yet (0 outside a coarse-first start-up and deferred strokes).
    std::size_t expected_tiles() const { return expected_.size(); }
    /// True after use_coarse_groups().
    bool coarse_groups() const { return coarse_ != nullptr; }
    /// Coarse depths, counted from the coarsest, whose groups a refresh() that changes their tiles rebuilds at once.
    static constexpr int kCoarseDepthsAtOnce = 1;
    /// Coarse group levels rebuilt by collect_lods() at most at a time after a stroke (each reads its coarse tile
    /// and the 26 around), and while start-up's finest groups wait for theirs.
    static constexpr std::size_t kCoarseLevelsPerCollect = 8, kCoarseStartupLevelsPerCollect = 32;
    /// A coarse level of a depth read by build_coarse_depth() first contours the coarse tiles it takes that were
    /// never contoured (CoarseGroupLevels::read_around: up to 27 blocks of 2x2x2 coarse tiles). collect_lods() builds
    /// such levels one after another for at most this long a pass (s; at least one), after those that only read,
    /// and none while a stroke is open.
    static constexpr double kCoarseContourSliceS = 0.04;
    /// After a stroke, collect_lods() re-reads the finer coarse models through the changed tiles this many tiles at a
    /// time (CoarseGroupLevels::update), for at most kCoarseContourSliceS a pass (at least one batch), never while a
    /// stroke is open; the waiting levels are rebuilt once every changed tile is read.
    static constexpr std::size_t kCoarseUpdateTiles = 16;
    /// The first refresh() builds the coarse levels of the groups of this depth and deeper at once (the coarsest
    /// ones, which a first frame of the whole workpiece draws); those of finer groups follow through collect_lods().
    static constexpr int kCoarseStartupDepth = 2;
    /// Coarse-first start-up: the errors of levels built before their tiles were in that collect_lods() or
    /// refresh() measures at most at a time once those tiles are in (each reads its group's tile vertices).
    static constexpr std::size_t kStartupErrorsPerPass = 4;
    /// Coarse-first start-up: a level deeper than the finest coarse depth built before its group's tiles are in
    /// takes this many coarse cells as its error until it is measured or estimated from the finest levels under it:
    /// a typical group's measured error lies well under it, the largest two-sided distance over a whole model
    /// (`tridex bench --coarse`) somewhat over it; the level's own estimate (one coarse cell) would have frames draw
    /// the finest groups nearly everywhere while the tiles are contoured. A level of the finest depth is measured
    /// against the model's own surface points in its box instead (compute::dexel_surface_error), and again against
    /// its tiles once they are in.
    static constexpr double kStartupErrorCoarseCells = 0.25;
    /// Coarse-first start-up: the most levels of groups deeper than the finest coarse depth whose estimate
    /// update_startup_groups() raises at a time, from the finest depth's levels once they are read (each samples the
    /// finest levels under its group).
    static constexpr std::size_t kStartupEstimatesPerPass = 16;
    /// Groups of the finest coarse depth whose coarse read found no surface though their tiles not in yet (start-up's
    /// or a stroke's hidden ones) hold some (a feature thinner than the stride), ascending, until those tiles are in.
    /// Nothing stands in for them: their caller contours their tiles (compute::refine_wanted_groups) as it does for
    /// the groups a frame wants finer, whatever the frames ask.
    std::vector<std::uint64_t> missed_surface_groups() const;
    /// Groups waiting for their coarse level (dropped by a stroke, not yet rebuilt).
    std::size_t coarse_waiting() const { return coarse_stale_.size(); }
    /// Coarse-first start-up: the level errors the passes over the groups' cover have measured (kStartupErrorsPerPass)
    /// or estimated (kStartupEstimatesPerPass) since the cache was made. The passes of a refresh() whose tiles a
    /// stroke hides (defer_tiles) and of collect_lods() with `stroke_open` do neither.
    std::size_t startup_errors_rated() const { return startup_errors_rated_; }
    /// Background building: the tiles and groups that the first refresh() left waiting for their levels and that
    /// still wait without having changed since (a later change makes one a stroke's, timed by lod_latency_ms()):
    /// 0 once start-up's levels are all built, however busy a stroke keeps the worker. 0 before the first refresh.
    /// In a coarse-first start-up the tiles still expected count too.
    std::size_t startup_lod_pending() const { return startup_waiting_.size() + startup_expected(); }

private:
    void build_lods(const std::vector<TileSurface*>& tiles);
    // Brings groups_ up to date: regroups those over `touched_tiles` (tiles that appeared, vanished, changed their
    // mesh or stopped being expected) and those `changed_tiles` makes stale, or every group at the first refresh or
    // after the grid changed. A stale group, or one whose children changed, loses its levels.
    void update_groups(const std::array<int, 3>& dims, const std::vector<std::uint64_t>& changed_tiles,
                       const std::vector<std::uint64_t>& touched_tiles);
    // Every group over tiles_ and expected_, with its children and bounds (no levels), sorted by id.
    std::vector<TileGroupSurface> all_groups(const std::array<int, 3>& dims, int depth_max) const;
    // The groups among `ids` (sorted) that have children now, with their children and bounds (no levels), sorted by
    // id; a group not among `ids` is read from groups_ as it stands.
    std::vector<TileGroupSurface> regrouped(const std::array<int, 3>& dims, int depth_max,
                                            const std::vector<std::uint64_t>& ids) const;
    void build_group_lods(const std::vector<std::size_t>& groups);
    void gather_group_parts(const TileGroupSurface& group, std::vector<LodPart>& parts) const;
    // Runs job(0..count-1), on every core from kParallelLodTiles jobs; rethrows the first failure.
    static void run_lod_jobs(std::size_t count, const std::function<void(std::size_t)>& job);
    bool group_ready(std::size_t g) const;
    // Background: jobs for tiles_ entries; those in arrived_ are start-up's (expect_tiles).
    void queue_tile_lods(const std::vector<std::size_t>& fresh);
    void queue_ready_groups();                                   // background: jobs for groups now ready
    void queue_settled_tiles(std::chrono::steady_clock::time_point now);  // background: a stroke's quiet tiles
    // What a refresh read from its source: the tiles to rebuild (ascending id; id and versions set, no mesh yet),
    // the indices in tiles_ of the tiles that have no triangles any more or lie past the source's last tile, and how
    // many tiles it read.
    struct TileRead {
        std::vector<TileSurface> rebuilt;
        std::vector<std::size_t> gone;
        std::size_t visited = 0;
    };
    // The tiles the source records as changed since the last refresh when it can say, else every tile. Only reads.
    TileRead read_tile_changes(const TileMeshSource& source) const;
    // Puts the rebuilt tiles (meshes read) in tiles_ and drops the gone ones, each rebuilt tile `pending` for its
    // levels; in place when no tile comes or goes. Returns the rebuilt tiles' indices in tiles_, ascending.
    std::vector<std::size_t> place_read_tiles(TileRead&& read, bool pending);
    LodJob tile_job(std::size_t i) const;  // the job for tiles_[i]'s levels: copies of its mesh and materials
    // The key of a tile's (group false) or group's job in queued_ and startup_waiting_.
    static std::uint64_t lod_key(bool group, std::uint64_t id);
    std::vector<TileGroupSurface> groups_;
    int groups_depth_ = 0;                         // the group depth groups_ was built with
    std::vector<std::uint64_t> expected_left_;     // tiles no longer expected since the last refresh (arrive, ...)
    std::vector<bool> group_pending_;              // per groups_ entry: levels wait for build_pending_lods()
    std::vector<TileSurface> tiles_;
    std::vector<std::uint64_t> contour_versions_;  // per tiles_ entry: the Contourer's version it was built from
    std::vector<bool> pending_;                    // per tiles_ entry: levels wait for build_pending_lods()
    // The tiles `source` says may have changed since the last refresh() (ascending, no repeats) into `tiles`, when it
    // can say (TileMeshSource::changed_since under the same change_view): true; else false.
    bool changed_since_last(const TileMeshSource& source, std::vector<std::uint64_t>& tiles) const;
    std::uint64_t change_mark_ = 0;  // fresh_tile_version() when the last refresh began reading
    std::uint64_t change_view_ = 0;  // the source's change_view() then
    std::size_t last_visited_ = 0;   // last_refresh_visits()
    bool defer_ = false;
    bool lod_ = false;
    TileLodOptions lod_options_{};
    std::size_t lod_tiles_built_ = 0;
    std::size_t lod_groups_built_ = 0;
    std::size_t lod_discarded_ = 0;
    double lod_build_ms_ = 0.0;
    std::unique_ptr<LodWorker> worker_;            // background building; null: refresh / build_pending_lods
    struct Queued {                                // a background job waiting for its result
        std::chrono::steady_clock::time_point at;  // when it was queued
        bool after_start;                          // queued after the first refresh
    };
    std::unordered_map<std::uint64_t, Queued> queued_;   // per lod_key: the newest job
    std::unordered_set<std::uint64_t> startup_waiting_;  // lod_keys of start-up's entries still waiting (background)
    std::vector<bool> group_queued_;               // per groups_ entry: its job is queued (background)
    std::vector<std::chrono::steady_clock::time_point> group_changed_at_;  // per groups_ entry: last change
    std::chrono::steady_clock::duration group_settle_{};  // LodWorkerOptions::group_settle_s
    bool build_away_ = false;                             // build_away_from_changes
    // build_away_from_changes: the groups within reach of coarse_changed_, as found after the change at
    // away_reach_at_ (a coarse_changed_at_).
    std::unordered_set<std::uint64_t> away_reach_;
    std::chrono::steady_clock::time_point away_reach_at_{};
    std::chrono::steady_clock::duration tile_settle_{};   // LodWorkerOptions::tile_settle_s
    // A stroke's tiles whose jobs wait for them to settle: tile id -> when it last changed.
    std::unordered_map<std::uint64_t, std::chrono::steady_clock::time_point> settling_;
    // When the first of them may be queued (max: none waits).
    std::chrono::steady_clock::time_point tile_due_ = std::chrono::steady_clock::time_point::max();
    // When the first ready group that waits for its tiles to settle may be queued (max: none waits).
    std::chrono::steady_clock::time_point settle_due_ = std::chrono::steady_clock::time_point::max();
    bool refreshed_ = false;                       // refresh() ran at least once
    // Coarse group levels (use_coarse_groups): the levels, the model they read, the fine tiles changed since they
    // last read it (ascending, no repeats), the groups waiting for a level, and when a tile last changed.
    std::unique_ptr<CoarseGroupLevels> coarse_;
    const TriDexel* coarse_model_ = nullptr;
    std::vector<std::uint64_t> coarse_changed_;
    // Tiles of coarse_changed_ -> the finest depth their latest change was read at (the coarsest depths at once; a
    // finer one around the levels a stroke's refresh rebuilds or asks for there), so that a read at a finer depth
    // skips the tiles read there since they last changed. A tile not in it is read at every depth.
    std::unordered_map<std::uint64_t, int> coarse_read_to_;
    // The tiles of `tiles` (ascending) whose latest change is not read at `depth` yet, ascending.
    std::vector<std::uint64_t> unread_at(const std::vector<std::uint64_t>& tiles, int depth) const;
    // Reads the coarse models through `tiles` (ascending) at `depth` and the coarser depths, and records it.
    void read_coarse_at(const std::vector<std::uint64_t>& tiles, int depth);
    std::vector<std::uint64_t> detail_wanted_;  // want_detail(), taken by the next refresh() with deferred tiles
    std::vector<std::uint64_t> frames_drew_;    // frames_drew(), ascending
    std::unordered_set<std::uint64_t> coarse_stale_;
    std::chrono::steady_clock::time_point coarse_changed_at_{};
    std::array<int, 3> coarse_dims_{};  // the tile grid's dimensions at the last refresh
    // Coarse mode: builds the levels of the groups `ids` (gone ones skipped), each job on every core from
    // kParallelLodTiles, with its measured error; takes them out of coarse_stale_ and counts them in
    // lod_groups_built_; returns how many were built.
    std::size_t rebuild_coarse_levels(const std::vector<std::uint64_t>& ids);
    // Coarse mode: the largest distance from sampled vertices of the group's tiles to `level`, m.
    double coarse_level_error(const TileGroupSurface& group, const TileLodLevel& level) const;
    // Coarse mode, for a group of the finest coarse depth whose tiles are not all in: the largest distance from
    // sampled surface points of the model in its box (its rays' interval ends, dexel_surface_error) to `level`, m.
    double coarse_level_dexel_error(const TileGroupSurface& group, const TileLodLevel& level) const;
    // Coarse-first start-up, for a group deeper than the finest coarse depth whose tiles are not all in: the largest
    // distance from sampled vertices of the finest depth's levels under it (their own triangles) to `level`, plus
    // the largest of those levels' own errors (at least their start-up estimate), m; nullopt while one of them waits
    // for its level.
    std::optional<double> coarse_level_estimate(const TileGroupSurface& group, const TileLodLevel& level) const;
    // Coarse mode: the groups within reach of the changed tiles (their coarse contour or their ring can change).
    std::unordered_set<std::uint64_t> coarse_reach(const std::array<int, 3>& dims,
                                                   const std::vector<std::uint64_t>& changed_tiles) const;
    // Coarse mode, in a refresh() after start-up's that changed `changed` (fine tile ids in a grid of `dims` tiles,
    // ascending; may be empty): rebuilds every waiting level of the coarsest kCoarseDepthsAtOnce depths (wherever it
    // is: a regrouping drops them too), and, within the change's reach (coarse_reach), down to kDeferredCoarseDepth
    // when `stroke_hidden` (defer_tiles, but not under a group in frames_drew_), not the finer depths' other waiting
    // ones (a coarse-first start-up's, left to settle_coarse_levels), after re-reading the coarsest models through
    // `changed` and a finer one through the changed tiles around the levels rebuilt there; returns how many.
    std::size_t rebuild_coarsest_now(const std::array<int, 3>& dims, const std::vector<std::uint64_t>& changed,
                                     bool stroke_hidden);
    // Coarse mode, with a stroke's tiles hidden: up to kDeferredDetailLevels waiting groups one depth under those of
    // detail_wanted_ (not finer than kDeferredDetailDepth), their depths' coarse models re-read through the changed
    // tiles around them (coarse_changed_; `from` or finer); empties detail_wanted_. Returns their ids.
    std::vector<std::uint64_t> wanted_finer_groups(const std::array<int, 3>& dims, int from);
    // Coarse mode: rebuilds up to kCoarseLevelsPerCollect waiting groups once settled; returns how many.
    std::size_t settle_coarse_levels(std::chrono::steady_clock::time_point now, bool stroke_open,
                                     const std::function<bool()>& yield);
    DurationHistogram lod_latency_ms_ = DurationHistogram::latency();
    // Coarse-first start-up (expect_tiles): tiles still expected, those arriving with the next refresh, groups whose
    // level's error was measured before all their tiles were in, and whether the groups' flags need another pass.
    std::unordered_set<std::uint64_t> expected_;
    std::unordered_set<std::uint64_t> arrived_;
    // Deferred strokes (defer_tiles): the expected tiles that are a stroke's, those of them arriving with the next
    // refresh, and the changes the next refresh counts.
    std::unordered_set<std::uint64_t> stroke_expected_;
    std::unordered_set<std::uint64_t> stroke_arrived_;
    std::vector<std::uint64_t> stroke_changes_;
    std::size_t startup_expected() const { return expected_.size() - stroke_expected_.size(); }
    // Whether tiles get simplified levels of their own: not when coarse groups start at depth 1 (use_coarse_groups).
    bool tile_levels() const { return !coarse_ || coarse_->min_depth() > 1; }
    bool startup_arrival(std::uint64_t id) const { return arrived_.count(id) != 0 && stroke_arrived_.count(id) == 0; }
    std::unordered_set<std::uint64_t> provisional_;
    std::unordered_set<std::uint64_t> estimated_;  // provisional levels estimated from the finest levels under them
    std::unordered_set<std::uint64_t> missed_;     // finest groups whose provisional read found no surface
    std::unordered_map<std::uint64_t, double> dropped_error_;  // provisional levels dropped by a change: their error, m
    bool startup_groups_ = false;
    bool remeasure_more_ = false;          // update_startup_groups left levels' errors to measure or estimate
    std::vector<std::uint64_t> deferred_;  // arrived tiles whose level jobs wait until no tile is expected
    void queue_deferred_tiles();           // background: jobs for deferred_ (start-up's)
    // Coarse-first: per groups_ entry, true when every tile under it is in tiles_ (none expected).
    // startup_only: as if no stroke's tile were expected (defer_tiles).
    std::vector<bool> groups_refined(bool startup_only = false) const;
    // The same for one group, walking only the groups and tiles under it.
    bool group_refined(const TileGroupSurface& group, bool startup_only = false) const;
    // Whether tile `id` is expected and not in yet (startup_only: not counting a stroke's expected tiles).
    bool tile_expected(std::uint64_t id, bool startup_only) const {
        return expected_.count(id) != 0 && !(startup_only && stroke_expected_.count(id) != 0);
    }
    // Coarse-first: sets each group's children_cover and, with `measure`, re-measures the error of up to
    // kStartupErrorsPerPass levels built before their tiles were all in and raises up to kStartupEstimatesPerPass
    // estimates (new versions where any changed). Without `measure` (a pass in a stroke's path: a refresh whose
    // tiles a stroke hides, collect_lods with the stroke open) only the cover is set, and remeasure_more_ marks that
    // errors may wait for a later pass.
    void update_startup_groups(bool measure = true);
    // What one pass of update_startup_groups has measured, estimated and tried to estimate.
    struct ErrorsRated {
        std::size_t measured = 0, estimated = 0, tried = 0;
        // Whether the pass has made or tried as many estimates as it may.
        bool estimates_full() const {
            return estimated == kStartupEstimatesPerPass || tried > 4 * kStartupEstimatesPerPass;
        }
    };
    // One group's part of a measuring pass: its level's error measured if it is `refined` and provisional, or its
    // estimate raised if it is deeper than the finest coarse depth and start-up's tiles under it are expected; within
    // the pass's bounds, else remeasure_more_ is set.
    void rate_startup_error(TileGroupSurface& group, bool refined, ErrorsRated& rated);
    // Whether rate_startup_error might measure (`refined`) or estimate `group`'s level: it is provisional, and for an
    // estimate deeper than the finest coarse depth, not estimated yet and with a level. Walks nothing under it, so
    // true may be too many (start-up's tiles under it all in), never too few.
    bool startup_error_may_wait(const TileGroupSurface& group, bool refined) const;
    // Once no start-up tile is expected: the groups update_startup_groups() must visit (indices into groups_,
    // ascending), and per each whether it is refined. Those are the groups over an expected tile (a stroke's, not
    // refined), those its last pass left uncovered and the first refined ones whose level waits to be measured (as
    // many as a pass measures, and one more); any other group is refined and covered, and is not measured now.
    void stroke_pass_groups(std::vector<std::size_t>& visit, std::vector<bool>& refined) const;
    std::vector<std::uint64_t> uncovered_;  // groups update_startup_groups' last pass left with children_cover false
    std::size_t last_group_pass_visits_ = 0;
    std::size_t startup_errors_rated_ = 0;  // level errors measured or estimated: startup_errors_rated()
    bool pass_every_group_ = false;
    // Coarse-first: the box of expected tile `id` grown by a cell (its mesh may borrow vertices that far), m.
    Aabb expected_tile_box(std::uint64_t id, const std::array<int, 3>& dims) const;
};

}  // namespace tridex::compute
