// The sculpt thread hands the contoured mesh to the renderer: at once, throttled while carving, and always the
// final state at stop().
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <thread>
#include <vector>

#include "compute/runtime/sculpt_thread.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

namespace tridex::app {
namespace {

compute::TriDexel box_model() {
    const Aabb box{Vec3(-0.05), Vec3(0.05)};
    compute::TriDexel m = compute::TriDexel::empty(compute::Lattice::around(box, 32), std::size_t(1) << 30);
    compute::scan_convert(box_mesh(box), m);
    return m;
}

// A box model contoured, a sample ring, the two hand-offs and a sculpt thread over them (not started).
struct Rig {
    compute::TriDexel m = box_model();
    compute::Contourer contourer{m};
    double v0 = 0.0;  // the box's volume as contoured, m^3
    SpscRing<ToolSample> ring;
    TripleBuffer<ActiveSurface> surface;
    TripleBuffer<MeshFrame> meshes;
    SculptThread t;
    explicit Rig(std::size_t ring_size = 1024)
        : v0(contoured(contourer, m)), ring(ring_size), t(m, contourer, ring, surface, Vec3(0.0)) {}
    static double contoured(compute::Contourer& c, compute::TriDexel& model) {
        c.update(model);
        return signed_volume(c.mesh());
    }
};

// 200 samples carving a straight groove across the +z face.
void push_groove(SpscRing<ToolSample>& ring) {
    for (int i = 0; i < 200; ++i) {
        ToolSample s;
        s.t_s = i * 1e-3;
        s.position = Vec3(-0.06 + 0.12 * i / 199.0, 0.0, 0.048);
        s.tool.radius_m = 0.008;
        s.op = ToolOp::kSubtract;
        ASSERT_TRUE(ring.try_push(s));
    }
}

// Samples [first, first + n) of a groove across the +z face, each made (ToolSample::made_s) at 100 s + its index ms.
void push_cut(SpscRing<ToolSample>& ring, int first, int n) {
    for (int i = first; i < first + n; ++i) {
        ToolSample s;
        s.t_s = i * 1e-3;
        s.made_s = 100.0 + i * 1e-3;
        s.position = Vec3(-0.06 + 0.12 * i / 199.0, 0.0, 0.048);
        s.tool.radius_m = 0.008;
        s.op = ToolOp::kSubtract;
        ASSERT_TRUE(ring.try_push(s));
    }
}

// Waits until the thread has run two more passes (a step that drained what was pushed, then one more).
void wait_passes(const SculptThread& t) {
    const std::uint64_t from = t.passes();
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (t.passes() < from + 2 && std::chrono::steady_clock::now() < limit)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_GE(t.passes(), from + 2);
}

TEST(RunHandoff, AVersionNeverTakenPassesItsOldestSampleOn) {
    Rig rig;
    auto& [m, contourer, v0, ring, surface, meshes, t] = rig;
    t.publish_mesh_to(meshes, 0.0);  // every changing step publishes; nothing reads until the end
    t.start();
    for (int chunk = 0; chunk < 4; ++chunk) {
        push_cut(ring, chunk * 50, 50);
        wait_passes(t);
    }
    t.stop();
    ASSERT_GE(t.stats().steps, 2u);  // several versions were replaced unread
    const MeshFrame& last = meshes.latest();
    // Every version but the last was replaced unread: the last carries the groove's first sample.
    EXPECT_DOUBLE_EQ(last.oldest_sample_s, 100.0);
    EXPECT_DOUBLE_EQ(last.oldest_sample_t_s, 0.0);
}

TEST(RunHandoff, ASculptedChangeSkipsTheIntervalOnceTheLastVersionWasTaken) {
    Rig rig;
    auto& [m, contourer, v0, ring, surface, meshes, t] = rig;
    ChangeSignal sculpted;
    t.publish_mesh_to(meshes, 1000.0, MeshForm::kWhole, &sculpted);  // an interval no test outlasts
    EXPECT_EQ(meshes.latest().version, 1u);  // the renderer takes the hand-off
    EXPECT_EQ(sculpted.count(), 0u);         // the first publish carries no sculpted change
    t.start();
    push_cut(ring, 0, 60);
    // The renderer may wait for the change instead of polling.
    ASSERT_TRUE(sculpted.wait_past(0, std::chrono::steady_clock::now() + std::chrono::seconds(60)));
    wait_passes(t);
    const MeshFrame& second = meshes.latest();  // published at once: the renderer had taken version 1
    EXPECT_EQ(second.version, 2u);
    EXPECT_DOUBLE_EQ(second.oldest_sample_s, 100.0);
    push_cut(ring, 60, 60);
    wait_passes(t);  // version 3, at once again; not taken
    push_cut(ring, 120, 80);
    wait_passes(t);  // waits for the interval: version 3 was not taken
    t.stop();        // the final state is published, with version 3's oldest sample
    EXPECT_EQ(t.stats().mesh_publishes, 4u);
    EXPECT_EQ(sculpted.count(), 3u);  // every publish after the first carried a sculpted change
    const MeshFrame& last = meshes.latest();
    EXPECT_EQ(last.version, 4u);
    // Version 2 was taken, so its samples are not carried; version 3's oldest, the second chunk's first sample, is
    // (or one of the first chunk's, had the thread drained that chunk in two steps).
    EXPECT_GT(last.oldest_sample_s, 100.0);
    EXPECT_LE(last.oldest_sample_s, 100.0 + 60e-3 + 1e-9);
}

TEST(RunHandoff, PublishesNowThenTheFinalMesh) {
    Rig rig;
    auto& [m, contourer, v0, ring, surface, meshes, t] = rig;
    EXPECT_EQ(meshes.latest().version, 0u);
    t.publish_mesh_to(meshes, 1000.0);  // an interval no test outlasts: only the first and the final publish
    const MeshFrame& first = meshes.latest();
    EXPECT_EQ(first.version, 1u);
    EXPECT_NEAR(signed_volume(first.mesh), v0, 1e-12);
    push_groove(ring);
    t.start();
    EXPECT_THROW(t.publish_mesh_to(meshes, 0.0), Error);  // not while running
    t.stop();
    const MeshFrame& last = meshes.latest();
    EXPECT_EQ(last.version, 2u);
    EXPECT_EQ(t.stats().mesh_publishes, 2u);
    EXPECT_EQ(t.stats().mesh_publish_ms.count(), 2u);
    const TriMesh now = contourer.mesh();
    EXPECT_EQ(last.mesh.triangles.size(), now.triangles.size());
    EXPECT_NEAR(signed_volume(last.mesh), signed_volume(now), 1e-15);
    EXPECT_LT(signed_volume(last.mesh), v0 - 1e-6);  // the groove is in the published mesh
}

TEST(RunHandoff, ZeroIntervalPublishesAfterEveryChange) {
    Rig rig;
    auto& [m, contourer, v0, ring, surface, meshes, t] = rig;
    t.publish_mesh_to(meshes, 0.0);
    push_groove(ring);
    t.start();
    t.stop();
    // One publish at hand-off plus one per changing step (steps that contoured).
    EXPECT_EQ(t.stats().mesh_publishes, 1u + t.stats().steps);
    EXPECT_EQ(meshes.latest().version, t.stats().mesh_publishes);
}

TEST(RunHandoff, TilesGetTheirLevelsFromTheWorker) {
    Rig rig;
    auto& [m, contourer, v0, ring, surface, meshes, t] = rig;
    compute::LodWorkerOptions worker;
    worker.lod.cell_m = m.lattice.cell_m;
    const compute::TileLodOptions& lod = worker.lod;
    t.use_tile_lod(worker);
    t.publish_mesh_to(meshes, 1000.0, MeshForm::kTiles);
    // The first publish does not wait for levels: full meshes only.
    const std::vector<std::shared_ptr<const compute::TileSurface>> before = meshes.latest().tiles;
    ASSERT_FALSE(before.empty());
    for (const auto& tile : before) EXPECT_TRUE(tile->lods.empty());
    EXPECT_EQ(t.stats().lod_tiles_built, 0u);
    // The groove's samples wait in the ring: the thread carves while the worker builds the levels.
    push_groove(ring);
    t.start();
    EXPECT_THROW(t.use_tile_lod(worker), Error);  // not while running
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while ((t.passes() < 2 || t.lod_tiles_pending() > 0) && std::chrono::steady_clock::now() < limit)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_EQ(t.lod_tiles_pending(), 0u);
    t.stop();
    const std::vector<std::shared_ptr<const compute::TileSurface>>& after = meshes.latest().tiles;
    // Every current tile was built once (the groove's tiles only after the groove), and was published again
    // with a new version so that a renderer uploads its levels.
    std::size_t with_levels = 0;
    for (const auto& tile : after) {
        with_levels += tile->lods.empty() ? 0 : 1;
        const auto old = std::find_if(before.begin(), before.end(), [&](const auto& b) { return b->id == tile->id; });
        if (old != before.end()) {
            EXPECT_NE((*old)->version, tile->version);
        }
    }
    EXPECT_GT(with_levels, 0u);  // the box's faces simplify
    // The groups of tiles are published too. The final publish re-contoured the groove's tiles (their levels wait
    // again): a group has levels unless a tile under it has none now.
    const std::vector<std::shared_ptr<const compute::TileGroupSurface>>& groups = meshes.latest().groups;
    ASSERT_FALSE(groups.empty());
    std::map<std::uint64_t, const compute::TileGroupSurface*> by_id;
    for (const auto& g : groups) by_id[g->id] = g.get();
    std::map<std::uint64_t, const compute::TileSurface*> tile_by_id;
    for (const auto& tile : after) tile_by_id[tile->id] = tile.get();
    const std::function<bool(const compute::TileGroupSurface&)> waits = [&](const compute::TileGroupSurface& g) {
        for (const std::uint64_t c : g.children)
            if (g.depth == 1 ? tile_by_id.at(c)->lods.empty() && tile_by_id.at(c)->mesh.triangles.size() >= lod.min_triangles
                             : waits(*by_id.at(c)))
                return true;
        return false;
    };
    std::size_t waiting = 0;
    for (const auto& g : groups) {
        if (g->depth == 1 && !waits(*g)) {
            EXPECT_FALSE(g->lods.empty()) << "group " << g->id;
        }
        waiting += waits(*g) ? 1 : 0;
        if (waits(*g)) {
            EXPECT_TRUE(g->lods.empty()) << "group " << g->id;  // never the shape before the groove
        }
    }
    EXPECT_GT(waiting, 0u);
    EXPECT_EQ(t.stats().lod_tiles_built, after.size());
    EXPECT_GT(t.stats().lod_build_ms, 0.0);
}

// Waits (up to 60 s) until `done` holds; false when it never did.
bool wait_for(const std::function<bool()>& done) {
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!done()) {
        if (std::chrono::steady_clock::now() > limit) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
}

TEST(RunHandoff, SculptedTilesGetLevelsWithoutAnyoneWaitingForThem) {
    Rig rig;
    auto& [m, contourer, v0, ring, surface, meshes, t] = rig;
    // The worker is held at its first job until the groove is carved and published: the sculpt thread must not
    // wait for it.
    std::atomic<bool> open{false};
    compute::LodWorkerOptions worker;
    worker.lod.cell_m = m.lattice.cell_m;
    worker.before_job = [&](const compute::LodJob&) {
        while (!open.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    };
    t.use_tile_lod(worker);
    t.publish_mesh_to(meshes, 0.0, MeshForm::kTiles);
    std::map<std::uint64_t, std::uint64_t> first_version;
    for (const auto& tile : meshes.latest().tiles) first_version[tile->id] = tile->version;
    push_groove(ring);
    t.start();
    ASSERT_TRUE(wait_for([&] { return ring.size() == 0 && meshes.latest().sculpt_steps > 0 && t.passes() > 4; }));
    std::set<std::uint64_t> carved;  // tiles the groove re-contoured
    for (const auto& tile : meshes.latest().tiles) {
        EXPECT_TRUE(tile->lods.empty()) << "tile " << tile->id;  // the worker has built nothing yet
        if (!first_version.count(tile->id) || first_version[tile->id] != tile->version) carved.insert(tile->id);
    }
    ASSERT_FALSE(carved.empty());
    EXPECT_GT(t.lod_tiles_pending(), 0u);
    open.store(true);
    ASSERT_TRUE(wait_for([&] { return t.lod_tiles_pending() == 0; }));
    ASSERT_TRUE(wait_for([&] {  // the mesh publish that carries the last levels
        for (const auto& tile : meshes.latest().tiles)
            if (carved.count(tile->id) && tile->lods.empty()) return false;
        return true;
    }));
    t.stop();
    // Every carved tile has levels of its carved mesh: each level's vertices are vertices of that mesh.
    for (const auto& tile : meshes.latest().tiles) {
        if (!carved.count(tile->id)) continue;
        std::set<std::array<double, 3>> full;
        for (const Vec3& p : tile->mesh.positions) full.insert({p.x, p.y, p.z});
        for (const compute::TileLodLevel& l : tile->lods)
            for (const Vec3& p : l.mesh.positions) EXPECT_TRUE(full.count({p.x, p.y, p.z})) << "tile " << tile->id;
    }
    // The groups over them have levels again (the box's faces simplify across tiles).
    std::size_t groups_with_levels = 0;
    for (const auto& g : meshes.latest().groups) groups_with_levels += g->lods.empty() ? 0 : 1;
    EXPECT_GT(groups_with_levels, 0u);
    EXPECT_EQ(t.stats().lod_pending, 0u);
    EXPECT_GE(t.stats().lod_latency_ms.count(), carved.size());  // the carved tiles were queued after start-up
    EXPECT_GE(t.stats().lod_all_built_s, 0.0);
}

TEST(RunHandoff, BadIntervalIsRefused) {
    Rig rig(16);
    auto& [m, contourer, v0, ring, surface, meshes, t] = rig;
    EXPECT_THROW(t.publish_mesh_to(meshes, -1.0), Error);
    EXPECT_THROW(t.publish_mesh_to(meshes, std::nan("")), Error);
    EXPECT_EQ(meshes.latest().version, 0u);
}

}  // namespace
}  // namespace tridex::app
