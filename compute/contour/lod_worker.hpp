// compute/contour/lod_worker.hpp - levels of detail built on worker threads of their own, off the sculpt and
// render threads: jobs in, finished levels out, nobody waits.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <list>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <vector>

#include "compute/contour/tile_lod.hpp"
#include "core/math.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::compute {

/// One piece of a group's surface, owned by its job (a copy of a tile's full mesh or of a level: see LodPart).
struct LodJobPart {
    TriMesh mesh;                        ///< world m, CCW from outside
    std::vector<std::uint8_t> materials; ///< per mesh vertex, or empty
    std::vector<Vec3> normals;           ///< per mesh vertex unit normals, or empty (the mesh's own)
    double error_m = 0.0;                ///< distance between this piece and the surface it stands for, m
};

/// What one job builds: the levels of a tile's mesh (build_tile_lod) or of a group (build_group_lod of its parts).
/// Self-contained (it owns copies of its inputs), so the caller may change its own meshes while it runs.
struct LodJob {
    bool group = false;        ///< false: a tile (mesh, materials); true: a group (parts)
    std::uint64_t id = 0;      ///< the tile's or group's id (TileSurface::id, TileGroupSurface::id)
    std::uint64_t token = 0;   ///< the caller's mark of the input's state, handed back with the result
    TriMesh mesh;              ///< tile: its full mesh (put in vertex-cache order before its levels are built)
    std::vector<std::uint8_t> materials;  ///< tile: per vertex, or empty
    std::vector<LodJobPart> parts;        ///< group: its pieces
    /// Tile: false puts the mesh in vertex-cache order and builds no levels (the result's levels are empty), for
    /// tiles whose coarser levels are their depth-1 group's (TileSurfaceCache, coarse groups from depth 1).
    bool levels = true;
    std::vector<Vec3> normals;  ///< tile: per vertex unit normals (TileSurface::normals), or empty (the mesh's own)
};

/// A finished job.
struct LodResult {
    bool group = false;
    std::uint64_t id = 0;
    std::uint64_t token = 0;           ///< LodJob::token
    std::vector<TileLodLevel> levels;  ///< finest first (empty: the mesh does not simplify)
    /// Tile: the job's mesh with its triangles in vertex-cache order (order_for_vertex_cache; the same vertices and
    /// triangles), the mesh the levels were built from. Empty for a group.
    TriMesh mesh;
    double build_ms = 0.0;             ///< wall time of the build on its worker, ms
};

/// How a LodWorker runs.
/// LodWorkerOptions::coarse_groups_from_cells by default.
constexpr int kCoarseGroupsFromCells = 512;

/// True when groups of tiles take their levels from the model read at coarser strides (TileSurfaceCache::
/// use_coarse_groups): from_cells > 0 and the lattice has at least from_cells cells along its longest side.
constexpr bool coarse_groups_apply(const std::array<int, 3>& cells, int from_cells) {
    return from_cells > 0 && std::max({cells[0], cells[1], cells[2]}) >= from_cells;
}

struct LodWorkerOptions {
    TileLodOptions lod;  ///< how levels are made (cell_m must be finite and > 0)
    /// Worker threads (>= 1): two let start-up use both cores of a small machine; a stroke's jobs are small.
    int threads = 2;
    /// Linux nice value of the worker threads once start-up's levels are built (end_startup(); 0..19, higher =
    /// lower priority): frames, sculpting and the haptic loop (SCHED_FIFO when granted) go first when the cores
    /// are busy. Ignored elsewhere.
    int nice = 5;
    /// Their nice value until end_startup() (0..nice): start-up's levels take the whole model's tiles and groups,
    /// and every frame until they arrive draws the full meshes, so they go at the priority of the frames. Each
    /// thread lowers itself to `nice` before its first job after end_startup() (lowering needs no privilege).
    int startup_nice = 0;
    /// TileSurfaceCache::build_lods_in_background: a group of tiles that changed after the first refresh (a
    /// stroke's) is queued only once no tile under it has changed for this long, s (0..10; 0 = as soon as its
    /// tiles have their levels). A stroke re-contours the same tiles step after step, and a group's levels are
    /// made from all of its tiles, so without it most of a group's builds are outdated before they finish. The
    /// tiles themselves wait only tile_settle_s; while a group waits they stand for it. Start-up's groups never wait.
    double group_settle_s = 0.25;
    /// TileSurfaceCache::build_lods_in_background: a tile re-contoured after the first refresh (a stroke's) is
    /// queued only once it has not changed for this long, s (0..10; 0 = at once). While the tool stays in a tile,
    /// each carving step re-contours it and outdates the levels being built for it; the tile is drawn at full
    /// resolution until its levels arrive, so waiting costs a few hundred triangles per carved tile and saves the
    /// builds no frame would draw. Start-up's tiles never wait.
    double tile_settle_s = 0.05;
    /// Groups take their levels from the model read at coarser strides (TileSurfaceCache::use_coarse_groups) when
    /// the model has at least this many cells along its longest side and is contoured on the CPU; 0 = never.
    /// Simplifying every tile's and group's levels no longer keeps up with a stroke from there on.
    int coarse_groups_from_cells = kCoarseGroupsFromCells;
    /// With coarse groups: the coarsest group depth (CoarseLevelOptions::max_depth, 1..6). Depth 4 reads every 16th
    /// ray, for views where a pixel spans many cells of a fine lattice (docs/design/lod.md, "Depths 1-4 in a
    /// session"). Regions of a coarse-first start-up stay depth-3 groups (at most 512 tiles each).
    int coarse_max_depth = 4;
    /// With coarse groups: start-up publishes a first mesh of the coarsest group levels before any tile is contoured,
    /// then contours the tiles region by region (compute::StartupRefiner; docs/design/lod.md, "Coarse first at
    /// start-up"). The Contourer must not have contoured the model yet.
    bool coarse_first = false;
    /// With coarse groups: while a stroke is open its tiles' full-resolution contour waits (compute::DeferredContour)
    /// and the coarse levels over them, rebuilt with each step down to TileSurfaceCache::kDeferredCoarseDepth, draw
    /// the stroke; the tiles are contoured after the stroke closes, or while it is open where a frame asks for more
    /// detail (docs/design/lod.md, "Strokes drawn coarse").
    bool stroke_coarse = false;
    /// Called on a worker thread before each job (tests: hold the worker to show that nobody waits for it).
    std::function<void(const LodJob&)> before_job;
};

/// Builds levels of detail on threads of its own (named "tridex-lod"). submit() queues a job and returns at once;
/// take() hands back the finished ones. A job for an id already waiting (not yet started) replaces it, so a tile
/// re-contoured again and again while a stroke passes over it is built once for its newest mesh. Jobs run in
/// queue order; `urgent` ones (a stroke's tiles) go ahead of those queued at start-up. All members are
/// thread-safe (one mutex, held only to move jobs and results); the destructor drops the waiting jobs and joins
/// the threads after the running ones finish.
class LodWorker {
public:
    /// Starts the threads. Throws tridex::Error when options.lod.cell_m is not finite and > 0, threads < 1,
    /// nice is outside 0..19 or startup_nice outside 0..nice.
    explicit LodWorker(LodWorkerOptions options);
    ~LodWorker();
    LodWorker(const LodWorker&) = delete;
    LodWorker& operator=(const LodWorker&) = delete;

    /// Queues `job` (at the front when urgent), replacing a waiting job with the same group flag and id.
    void submit(LodJob job, bool urgent);
    /// Drops the waiting (not yet started) job with this group flag and id; true when there was one. A running
    /// job is not stopped: its result still arrives.
    bool cancel(bool group, std::uint64_t id);
    /// Moves the finished results into `out` (appended, in order of completion) and returns how many. Rethrows,
    /// once, the first exception a job threw (its result is then missing; the others are kept).
    std::size_t take(std::vector<LodResult>& out);
    /// Jobs queued or running.
    std::size_t outstanding() const;
    /// Start-up's levels are built: each thread lowers itself from startup_nice to nice before its next job.
    /// Thread-safe; later calls do nothing.
    void end_startup() { startup_over_.store(true, std::memory_order_release); }

private:
    void run();

    LodWorkerOptions options_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::list<LodJob> queue_;  // waiting jobs, in the order they start
    // Each waiting job by (group flag, id): submit() and cancel() find the one they replace or drop at once.
    std::unordered_map<std::uint64_t, std::list<LodJob>::iterator> waiting_tiles_, waiting_groups_;
    std::unordered_map<std::uint64_t, std::list<LodJob>::iterator>& waiting(bool group) {
        return group ? waiting_groups_ : waiting_tiles_;
    }
    std::vector<LodResult> done_;
    std::size_t running_ = 0;
    std::exception_ptr failure_;
    bool stop_ = false;
    std::atomic<bool> startup_over_{false};
    std::vector<std::thread> threads_;
};

}  // namespace tridex::compute
