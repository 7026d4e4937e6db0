// Tests of compute/contour/lod_worker and TileSurfaceCache's background building: a stroke's groups wait for its
// tiles to settle and its tiles wait to stop changing, cancel() drops only waiting jobs, the workers drop to their
// nice value after start-up, start-up's levels are counted apart from a stroke's, outdated builds are counted and
// replaced.
#include <gtest/gtest.h>

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/contour/lod_worker.hpp"
#include "core/error.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

// True when every tile of `cache` has its levels.
bool all_tiles_built(const TileSurfaceCache& cache) {
    for (const TileSurface& t : cache.tiles())
        if (!t.lods_built) return false;
    return true;
}

// A LodWorker refuses a settling time (`field`) outside 0..10 s.
void expect_settle_refused(double LodWorkerOptions::*field) {
    LodWorkerOptions bad;
    bad.lod.cell_m = 1e-3;
    for (const double s : {-0.1, 11.0, std::nan("")}) {
        bad.*field = s;
        EXPECT_THROW(LodWorker{bad}, Error) << s;
    }
}

// Waits (at most 20 s) until `worker` has no job queued or running and takes the results. These tests' jobs have
// empty meshes, which a build may refuse: only which jobs ran, and on what thread, matters to them.
std::vector<LodResult> drain(LodWorker& worker) {
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (worker.outstanding() > 0 && std::chrono::steady_clock::now() < limit)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::vector<LodResult> out;
    try {
        worker.take(out);
    } catch (const Error&) {
    }
    return out;
}

// A box in a 40-cell lattice, contoured, whose tile cache builds its levels on a background worker: `move` changes
// the box's corners as a stroke would (every tile marked dirty, re-contoured, the cache refreshed), and
// `collect_until` takes the worker's results in until `done` holds (at most 20 s).
struct BackgroundBox {
    TriDexel model = empty_model(cube_lattice(40));
    Vec3 lo{3.3, 4.4, 2.6}, hi{40 - 3.7, 40 - 2.2, 40 - 4.1};
    Contourer contourer{model};
    TileSurfaceCache cache;

    explicit BackgroundBox(const LodWorkerOptions& worker) {
        fill_rays(model, [&](int a, int u, int v) { return box_chord(lo, hi, a, u, v); });
        contourer.update(model);
        TileLodOptions o;
        o.cell_m = model.lattice.cell_m;
        cache.enable_lod(o);
        cache.build_lods_in_background(worker);
        cache.refresh(contourer);
    }
    std::size_t move(const Vec3& d_lo, const Vec3& d_hi) {
        lo = lo + d_lo;
        hi = hi + d_hi;
        fill_rays(model, [&](int a, int u, int v) { return box_chord(lo, hi, a, u, v); });
        std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});  // as a Boolean marks them
        contourer.update(model);
        return cache.refresh(contourer);
    }
    bool collect_until(const std::function<bool()>& done) {
        const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (!done() && std::chrono::steady_clock::now() < limit) {
            cache.collect_lods();
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        return done();
    }
};

// A stroke re-contours tiles step after step: the groups over them wait until their tiles have been quiet for
// group_settle_s before their levels are built, while the tiles' own levels are built at once. Start-up's groups
// never wait.
TEST(TileLod, StrokeGroupsWaitUntilTheirTilesSettle) {
    for (const double settle : {10.0, 0.05}) {
        SCOPED_TRACE("group_settle_s " + std::to_string(settle));
        LodWorkerOptions w;
        w.group_settle_s = settle;
        BackgroundBox box(w);
        TileSurfaceCache& cache = box.cache;
        const auto settled = [&](const std::function<bool()>& done) { return box.collect_until(done); };
        ASSERT_TRUE(settled([&] { return cache.lod_pending() == 0; }));  // start-up: within 20 s
        ASSERT_GT(cache.groups().size(), 1u);
        std::map<std::uint64_t, bool> had_levels;  // per group before the stroke
        for (const TileGroupSurface& g : cache.groups()) had_levels[g.id] = !g.lods.empty();
        // The stroke: one face of the box moves in, re-contouring the tiles along it.
        ASSERT_GT(box.move(Vec3(0.0), Vec3(-1.3, 0.0, 0.0)), 0u);
        const auto tiles_built = [&] { return all_tiles_built(cache); };
        ASSERT_TRUE(settled(tiles_built));
        const std::size_t waiting = cache.lod_pending();  // groups only: every tile has its levels
        EXPECT_GT(waiting, 0u);
        EXPECT_LT(waiting, cache.groups().size());  // those over the moved face only
        if (settle > 1.0) {
            // However often their results are asked for, the changed groups still wait, without levels.
            for (int i = 0; i < 50; ++i) {
                cache.collect_lods();
                std::this_thread::sleep_for(std::chrono::milliseconds(2));
            }
            EXPECT_EQ(cache.lod_pending(), waiting);
            std::size_t without = 0;
            for (const TileGroupSurface& g : cache.groups()) without += had_levels[g.id] && g.lods.empty() ? 1 : 0;
            EXPECT_GT(without, 0u);  // groups that had levels lost them to the stroke and wait
            EXPECT_LE(without, waiting);
        } else {
            EXPECT_TRUE(settled([&] { return cache.lod_pending() == 0; }));
            for (const TileGroupSurface& g : cache.groups())
                EXPECT_EQ(!g.lods.empty(), had_levels[g.id]) << "group " << g.id;
        }
    }
    expect_settle_refused(&LodWorkerOptions::group_settle_s);
}

// A stroke's tiles are queued only once they have not changed for tile_settle_s: a tile re-contoured step after
// step is built once, for its last mesh, and its levels' latency counts from that re-contour. Start-up's tiles
// never wait.
TEST(TileLod, StrokeTilesWaitUntilTheySettle) {
    // 2 s: far longer than the five steps take, even under a sanitizer.
    for (const double settle : {10.0, 2.0}) {
        SCOPED_TRACE("tile_settle_s " + std::to_string(settle));
        LodWorkerOptions w;
        w.tile_settle_s = settle;
        w.group_settle_s = 10.0;  // the stroke's groups wait for the whole test: only tiles are built
        BackgroundBox box(w);
        TileSurfaceCache& cache = box.cache;
        ASSERT_TRUE(box.collect_until([&] { return cache.lod_pending() == 0; }));  // start-up: within 20 s
        const auto tiles_built = [&] { return all_tiles_built(cache); };
        const std::size_t built_before = cache.lod_tiles_built();
        // Five steps of a stroke, each re-contouring the tiles along one face, with results taken in between.
        std::size_t changed = 0;
        for (int step = 0; step < 5; ++step) {
            changed = box.move(Vec3(0.0), Vec3(-0.3, 0.0, 0.0));
            ASSERT_GT(changed, 0u);
            cache.collect_lods();
        }
        std::size_t waiting = 0;
        for (const TileSurface& t : cache.tiles()) waiting += t.lods_built ? 0 : 1;
        EXPECT_EQ(waiting, changed);  // the last step's tiles: none was built while the stroke went on
        if (settle > 5.0) {
            for (int i = 0; i < 50; ++i) {
                cache.collect_lods();
                std::this_thread::sleep_for(std::chrono::milliseconds(2));
            }
            std::size_t still = 0;
            for (const TileSurface& t : cache.tiles()) still += t.lods_built ? 0 : 1;
            EXPECT_EQ(still, changed);
            EXPECT_EQ(cache.lod_tiles_built(), built_before);
        } else {
            ASSERT_TRUE(box.collect_until(tiles_built));
            // Each re-contoured tile was built once, however many steps changed it; nothing built was outdated.
            EXPECT_EQ(cache.lod_tiles_built() - built_before, changed);
            EXPECT_EQ(cache.lod_discarded(), 0u);
            // Their latency counts from the last re-contour, so it includes the settling.
            EXPECT_EQ(cache.lod_latency_ms().count(), cache.lod_tiles_built() - built_before);
            EXPECT_GE(cache.lod_latency_ms().min_ms(), 1e3 * settle * 0.9);
        }
    }
    expect_settle_refused(&LodWorkerOptions::tile_settle_s);
}

// With a background worker a re-contoured tile is published in the contour's order (the sculpt thread does not
// spend its time ordering it) and comes back in vertex-cache order with its levels: the same triangles, each with
// its corners in order, and the mesh order_for_vertex_cache makes of the contour's.
TEST(TileLod, TheWorkerPutsATilesMeshInVertexCacheOrder) {
    LodWorkerOptions w;
    w.tile_settle_s = 0.0;
    w.group_settle_s = 10.0;
    BackgroundBox box(w);
    TileSurfaceCache& cache = box.cache;
    ASSERT_TRUE(box.collect_until([&] { return all_tiles_built(cache); }));
    ASSERT_GT(box.move(Vec3(0.0), Vec3(-0.3, 0.0, 0.0)), 0u);
    std::size_t reordered = 0, checked = 0;
    for (const TileSurface& t : cache.tiles()) {
        if (t.lods_built) continue;  // unchanged by the step
        std::vector<std::uint8_t> materials;
        const TriMesh contour = box.contourer.tile_mesh(t.id, materials);
        EXPECT_EQ(t.mesh.triangles, contour.triangles) << t.id;  // as contoured
        ++checked;
    }
    ASSERT_GT(checked, 0u);
    ASSERT_TRUE(box.collect_until([&] { return all_tiles_built(cache); }));
    for (const TileSurface& t : cache.tiles()) {
        std::vector<std::uint8_t> materials;
        TriMesh ordered = box.contourer.tile_mesh(t.id, materials);
        EXPECT_EQ(t.mesh.positions, ordered.positions) << t.id;
        const bool was_ordered = ordered.triangles != t.mesh.triangles;
        order_for_vertex_cache(ordered);
        EXPECT_EQ(t.mesh.triangles, ordered.triangles) << t.id;
        reordered += was_ordered ? 1 : 0;
    }
    EXPECT_GT(reordered, 0u);  // the order differs from the contour's somewhere, so the check above means something
}

// cancel() drops a waiting job (its result never arrives) and leaves a running one alone.
TEST(TileLod, CancelDropsOnlyAWaitingJob) {
    std::atomic<bool> open{false};
    std::atomic<int> started{0};
    LodWorkerOptions w;
    w.lod.cell_m = 1e-3;
    w.threads = 1;
    w.before_job = [&](const LodJob&) {
        ++started;
        while (!open.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    };
    LodWorker worker(w);
    worker.submit(LodJob{false, 1, 0, {}, {}, {}, true, {}}, false);
    while (started.load() < 1) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    worker.submit(LodJob{false, 2, 0, {}, {}, {}, true, {}}, false);
    worker.submit(LodJob{true, 2, 0, {}, {}, {}, true, {}}, false);
    EXPECT_FALSE(worker.cancel(false, 1));  // running
    EXPECT_TRUE(worker.cancel(false, 2));   // waiting: the tile's job, not the group's with the same id
    EXPECT_FALSE(worker.cancel(false, 2));
    EXPECT_FALSE(worker.cancel(false, 3));
    EXPECT_EQ(worker.outstanding(), 2u);
    open.store(true);
    for (const LodResult& r : drain(worker)) EXPECT_FALSE(!r.group && r.id == 2);
}

#if defined(__linux__)
// The workers run start-up's jobs at startup_nice and drop to nice before their first job after end_startup().
TEST(TileLod, WorkersDropToTheirNiceValueOnceStartupIsOver) {
    std::mutex lock;
    std::vector<int> seen;  // each job's thread's nice value
    LodWorkerOptions w;
    w.lod.cell_m = 1e-3;
    w.threads = 1;
    w.nice = 7;
    w.startup_nice = 2;
    w.before_job = [&](const LodJob&) {
        const int n = getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)));
        const std::lock_guard<std::mutex> hold(lock);
        seen.push_back(n);
    };
    LodWorker worker(w);
    const auto run_job = [&](std::uint64_t id) {
        worker.submit(LodJob{false, id, 0, {}, {}, {}, true, {}}, false);
        drain(worker);
    };
    run_job(1);
    worker.end_startup();
    run_job(2);
    run_job(3);
    const int base = getpriority(PRIO_PROCESS, 0);  // the process's own (raising above it needs a privilege)
    ASSERT_EQ(seen.size(), 3u);
    EXPECT_EQ(seen[0], std::max(base, 2));
    EXPECT_EQ(seen[1], std::max(base, 7));
    EXPECT_EQ(seen[2], std::max(base, 7));
    LodWorkerOptions bad = w;
    bad.startup_nice = 8;
    EXPECT_THROW(LodWorker{bad}, Error);
    bad.startup_nice = -1;
    EXPECT_THROW(LodWorker{bad}, Error);
}
#endif

// Start-up's levels are done when every tile and group the first refresh left waiting has them, or was changed by a
// stroke since (then it is the stroke's, and its group may wait to settle): a stroke during start-up never holds
// start-up back.
TEST(TileLod, StartupLevelsAreCountedApartFromAStrokes) {
    std::atomic<bool> open{false};
    LodWorkerOptions w;
    w.group_settle_s = 10.0;  // the stroke's groups wait for the whole test
    w.before_job = [&](const LodJob&) {
        while (!open.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    };
    BackgroundBox box(w);
    TileSurfaceCache& cache = box.cache;
    const std::size_t startup = cache.startup_lod_pending();
    EXPECT_EQ(startup, cache.lod_pending());  // every tile and group of start-up waits
    EXPECT_GT(startup, cache.groups().size());
    // A stroke moves one face while start-up's jobs are held: its tiles and their groups leave start-up's count.
    ASSERT_GT(box.move(Vec3(0.0), Vec3(-1.3, 0.0, 0.0)), 0u);
    const std::size_t after = cache.startup_lod_pending();
    EXPECT_LT(after, startup);
    EXPECT_GT(after, 0u);
    open.store(true);
    ASSERT_TRUE(box.collect_until([&] { return cache.startup_lod_pending() == 0; }));
    ASSERT_TRUE(box.collect_until([&] {
        for (const TileSurface& t : cache.tiles())
            if (!t.lods_built) return false;
        return true;
    }));
    EXPECT_GT(cache.lod_pending(), 0u);  // the stroke's groups still settle; start-up is done
    EXPECT_EQ(cache.startup_lod_pending(), 0u);
}

// A build that finishes after its tile changed again is thrown away and counted (lod_discarded); its newer job
// gives the tile its levels.
TEST(TileLod, OutdatedBuildsAreCountedAndReplaced) {
    std::atomic<bool> open{false};
    std::atomic<int> started{0};
    LodWorkerOptions w;
    w.before_job = [&](const LodJob&) {  // the workers hold their first jobs until the model has changed
        ++started;
        while (!open.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    };
    BackgroundBox box(w);
    while (started.load() < w.threads) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    // Every tile changes while the first jobs run: those builds are outdated when they finish.
    box.move(Vec3(0.4, 0.3, 0.2), Vec3(0.4, 0.3, 0.2));
    open.store(true);
    ASSERT_TRUE(box.collect_until([&] { return box.cache.lod_pending() == 0; }));
    EXPECT_GE(box.cache.lod_discarded(), static_cast<std::size_t>(w.threads));
    for (const TileSurface& t : box.cache.tiles()) EXPECT_TRUE(t.lods_built) << "tile " << t.id;
}

}  // namespace
}  // namespace tridex::compute
