// The sculpt thread's coarse-first start-up (SculptThread::use_tile_lod with LodWorkerOptions::coarse_first): the first
// mesh publish holds no tile, only the groups with the coarsest levels over the whole model; a stroke during the
// refinement works, and the session ends with the mesh a start-up that contoured everything first ends with.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <cmath>
#include <thread>

#include "compute/mesh/scan_convert.hpp"
#include "compute/runtime/detail_requests.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "journal_stream.hpp"

namespace tridex::app {
namespace {

const int kTop = compute::LodWorkerOptions{}.coarse_max_depth;  // the sessions' coarsest depth

compute::TriDexel box_model() { return test::box_model(128); }

// A wavy carving path across the box's +z face, 300 samples.
std::vector<ToolSample> stream() { return test::wavy_cut(300); }

struct Ended {
    TriMesh mesh;        // the Contourer's mesh of the final model
    MeshFrame first;     // the first mesh published
    MeshFrame last;      // the last
    SculptStats stats;
};

// Per-tile meshes published to `meshes` with coarse group levels at every size: coarse first or not, strokes drawn
// coarse or not.
void use_coarse_tiles(SculptThread& t, const compute::TriDexel& m, bool coarse_first, TripleBuffer<MeshFrame>& meshes,
                      bool stroke_coarse = false) {
    compute::LodWorkerOptions lod;
    lod.lod.cell_m = m.lattice.cell_m;
    lod.coarse_groups_from_cells = 1;
    lod.coarse_first = coarse_first;
    lod.stroke_coarse = stroke_coarse;
    t.use_tile_lod(lod);
    t.publish_mesh_to(meshes, 0.0, MeshForm::kTiles);
}

// 100 samples each: a push stroke along the first third of the wavy path, a subtract stroke along the second, and
// the first push again. A push's last group is held until its close: the subtract's first sample closes the first
// push, stop() the second.
std::vector<ToolSample> push_cut_push() {
    std::vector<ToolSample> s = stream();
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (i < 100 || i >= 200) s[i].op = ToolOp::kPush;
        if (i >= 200) s[i].position = s[i - 200].position;
    }
    return s;
}

// A session with per-tile meshes and coarse group levels: coarse first or everything contoured first; strokes drawn
// coarse or contoured at every step; with `top_drawn`, frames that draw every coarsest group within the bound
// (compute::DrawnGroups, offered from this thread while the sculpt thread runs).
Ended session(bool coarse_first, bool stroke_coarse = false, const std::vector<ToolSample>& samples = stream(),
              bool top_drawn = false) {
    compute::TriDexel m = box_model();
    compute::Contourer contourer(m);
    if (!coarse_first) contourer.update(m);
    SpscRing<ToolSample> ring(1024);
    TripleBuffer<ActiveSurface> surface;
    TripleBuffer<MeshFrame> meshes;
    SculptThread t(m, contourer, ring, surface, Vec3(0.0, 0.0, 0.07));
    use_coarse_tiles(t, m, coarse_first, meshes, stroke_coarse);
    compute::DrawnGroups drawn;
    if (top_drawn) t.follow_drawn_groups(drawn);
    Ended e;
    e.first = meshes.latest();
    std::vector<std::uint64_t> top;
    for (const auto& g : e.first.groups)
        if (g->depth == kTop) top.push_back(g->id);
    t.start();
    std::size_t k = 0;
    for (const ToolSample& s : samples) {  // strokes while the tiles are being contoured
        if (top_drawn && k++ % 50 == 0) drawn.offer(top);
        while (!ring.try_push(s)) std::this_thread::yield();
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    t.stop();
    e.stats = t.stats();
    e.last = meshes.latest();
    e.mesh = contourer.mesh();
    return e;
}

TEST(SculptThreadStartup, TheFirstMeshIsCoarseAndTheLastEqualsAFullStartUpBitForBit) {
    const Ended coarse = session(true), full = session(false);
    // The first publish: no tile, every group over the model, the coarsest ones with their level, drawn whatever
    // their error (nothing under them can stand in yet).
    EXPECT_TRUE(coarse.first.tiles.empty());
    EXPECT_FALSE(full.first.tiles.empty());
    ASSERT_FALSE(coarse.first.groups.empty());
    std::size_t top = 0, coarse_triangles = 0;
    for (const auto& g : coarse.first.groups) {
        if (g->depth != kTop) continue;
        ++top;
        ASSERT_EQ(g->lods.size(), 1u);
        EXPECT_FALSE(g->children_cover);
        coarse_triangles += g->lods[0].mesh.triangles.size();
    }
    EXPECT_GE(top, 1u);
    EXPECT_GT(coarse_triangles, 0u);
    EXPECT_LT(16 * coarse_triangles, full.first.triangles);
    // The stroke carved the same model, and the last mesh is the full start-up's, bit for bit.
    EXPECT_EQ(coarse.stats.steps > 0, full.stats.steps > 0);
    EXPECT_GT(coarse.stats.startup_tiles_refined, 0u);
    EXPECT_EQ(full.stats.startup_tiles_refined, 0u);
    EXPECT_GE(coarse.stats.startup_refined_s, coarse.first.published_s);
    EXPECT_EQ(coarse.mesh.positions, full.mesh.positions);
    EXPECT_EQ(coarse.mesh.triangles, full.mesh.triangles);
    ASSERT_EQ(coarse.last.tiles.size(), full.last.tiles.size());
    EXPECT_EQ(coarse.last.triangles, full.last.triangles);
    for (std::size_t i = 0; i < coarse.last.tiles.size(); ++i) {
        EXPECT_EQ(coarse.last.tiles[i]->id, full.last.tiles[i]->id);
        EXPECT_EQ(coarse.last.tiles[i]->mesh.triangles.size(), full.last.tiles[i]->mesh.triangles.size());
    }
    for (const auto& g : coarse.last.groups) EXPECT_TRUE(g->children_cover) << g->id;
}

// On demand (the frames' DetailRequests): no tile is contoured until a group is asked for; then its tiles, and no
// region beyond their neighbours; stop() contours the rest, and the contour equals a whole one bit for bit.
TEST(SculptThreadStartup, OnDemandContoursOnlyTheGroupsAskedForUntilStop) {
    compute::TriDexel m = box_model();
    compute::Contourer contourer(m);
    SpscRing<ToolSample> ring(16);
    TripleBuffer<ActiveSurface> surface;
    TripleBuffer<MeshFrame> meshes;
    compute::DetailRequests requests;
    SculptThread t(m, contourer, ring, surface, Vec3(0.0, 0.0, 0.07));
    t.refine_on_demand(requests);
    use_coarse_tiles(t, m, true, meshes);
    t.start();
    // Wait until every coarse depth is read (the depth-1 groups have their levels).
    const auto until = [&](const std::function<bool(const MeshFrame&)>& ready) {
        const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (std::chrono::steady_clock::now() < end) {
            if (ready(meshes.latest())) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        return false;
    };
    std::uint64_t asked = 0;
    std::vector<std::uint64_t> children;
    const bool read = until([&](const MeshFrame& f) {
        for (const auto& g : f.groups)
            if (g->depth == 1 && !g->lods.empty() && !g->children_cover) {
                asked = g->id;
                children = g->children;
                return true;
            }
        return false;
    });
    if (!read) t.stop();
    ASSERT_TRUE(read) << "the depth-1 groups never got their levels";
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_TRUE(meshes.latest().tiles.empty()) << "no tile before a frame asks for one";
    const std::vector<std::uint64_t> ids{asked};
    requests.offer(ids);
    const bool arrived = until([&](const MeshFrame& f) {
        std::size_t found = 0;
        for (const auto& tile : f.tiles) found += std::count(children.begin(), children.end(), tile->id);
        return found > 0;
    });
    const MeshFrame after = meshes.latest();
    t.stop();
    ASSERT_TRUE(arrived) << "the tiles of group " << asked << " never arrived";
    EXPECT_LE(after.tiles.size(), 64u) << "only the group's tiles and their neighbours are contoured";
    const SculptStats stats = t.stats();
    EXPECT_GT(stats.startup_tiles_refined, 0u);
    compute::TriDexel whole = box_model();
    compute::Contourer all(whole);
    all.update(whole);
    EXPECT_EQ(contourer.mesh().positions, all.mesh().positions);
    EXPECT_EQ(contourer.mesh().triangles, all.mesh().triangles);
}

// A stroke drawn coarse: its tiles wait while it is open and are contoured after it (stop() contours what is left);
// the session ends with the same contour and tiles, bit for bit, as one that contoured every step, with a full or a
// coarse-first start-up.
TEST(SculptThreadStartup, AStrokeDrawnCoarseEndsWithTheContourOfEveryStep) {
    const Ended every = session(false, false);
    EXPECT_EQ(every.stats.tiles_deferred, 0u);
    for (const bool coarse_first : {false, true}) {
        const Ended coarse = session(coarse_first, true);
        EXPECT_GT(coarse.stats.steps, 0u);
        EXPECT_GT(coarse.stats.tiles_deferred, 0u) << "coarse first " << coarse_first;
        EXPECT_GT(coarse.stats.deferred_tiles_contoured, 0u) << "coarse first " << coarse_first;
        EXPECT_EQ(coarse.mesh.positions, every.mesh.positions) << "coarse first " << coarse_first;
        EXPECT_EQ(coarse.mesh.triangles, every.mesh.triangles) << "coarse first " << coarse_first;
        ASSERT_EQ(coarse.last.tiles.size(), every.last.tiles.size()) << "coarse first " << coarse_first;
        for (std::size_t i = 0; i < coarse.last.tiles.size(); ++i) {
            EXPECT_EQ(coarse.last.tiles[i]->id, every.last.tiles[i]->id);
            EXPECT_EQ(coarse.last.tiles[i]->mesh.triangles.size(), every.last.tiles[i]->mesh.triangles.size());
        }
        for (const auto& g : coarse.last.groups) EXPECT_TRUE(g->children_cover) << g->id;
    }
    // Frames that draw the coarsest groups leave the levels under them for later: the contour ends the same.
    const Ended top = session(false, true, stream(), true);
    EXPECT_GT(top.stats.tiles_deferred, 0u);
    EXPECT_EQ(top.mesh.positions, every.mesh.positions);
    EXPECT_EQ(top.mesh.triangles, every.mesh.triangles);
    ASSERT_EQ(top.last.tiles.size(), every.last.tiles.size());
    for (std::size_t i = 0; i < top.last.tiles.size(); ++i) {
        EXPECT_EQ(top.last.tiles[i]->mesh.triangles.size(), every.last.tiles[i]->mesh.triangles.size());
    }
    for (const auto& g : top.last.groups) EXPECT_TRUE(g->children_cover) << g->id;
}

// The change a stroke's close makes (here a push's held group) is deferred as the stroke's steps were, not contoured
// at the close with the deferred tiles beside it; the last stroke's, closed by stop(), too. Both sessions end with the
// contour of one that contoured every change at once.
TEST(SculptThreadStartup, AStrokesCloseIsDeferredTooAndStopContoursIt) {
    const Ended every = session(false, false, push_cut_push());
    EXPECT_GT(every.stats.tiles_recontoured, 0u);
    const Ended coarse = session(false, true, push_cut_push());
    EXPECT_EQ(coarse.stats.tiles_recontoured, 0u) << "no tile contoured at a step or a close";
    EXPECT_GT(coarse.stats.tiles_deferred, 0u);
    EXPECT_GT(coarse.stats.deferred_tiles_contoured, 0u);
    EXPECT_EQ(coarse.mesh.positions, every.mesh.positions);
    EXPECT_EQ(coarse.mesh.triangles, every.mesh.triangles);
    ASSERT_EQ(coarse.last.tiles.size(), every.last.tiles.size());
    for (std::size_t i = 0; i < coarse.last.tiles.size(); ++i) {
        EXPECT_EQ(coarse.last.tiles[i]->id, every.last.tiles[i]->id);
        EXPECT_EQ(coarse.last.tiles[i]->mesh.triangles.size(), every.last.tiles[i]->mesh.triangles.size());
    }
}

TEST(SculptThreadStartup, CoarseFirstNeedsCoarseGroups) {
    compute::TriDexel m = box_model();
    compute::Contourer contourer(m);
    SpscRing<ToolSample> ring(16);
    TripleBuffer<ActiveSurface> surface;
    SculptThread t(m, contourer, ring, surface, Vec3(0.0));
    compute::LodWorkerOptions lod;
    lod.lod.cell_m = m.lattice.cell_m;
    lod.coarse_groups_from_cells = 0;  // simplified groups
    lod.coarse_first = true;
    EXPECT_THROW(t.use_tile_lod(lod), Error);
}

}  // namespace
}  // namespace tridex::app
