// The sculpt thread's coarse-first start-up (SculptThread::use_tile_lod with LodWorkerOptions::coarse_first): the first
// mesh publish holds no tile, only the groups with the coarsest levels over the whole model; a stroke during the
// refinement works, and the session ends with the mesh a start-up that contoured everything first ends with.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "compute/mesh/scan_convert.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "journal_stream.hpp"

namespace tridex::app {
namespace {

constexpr int kTop = compute::CoarseLevelOptions{}.max_depth;

compute::TriDexel box_model() { return test::box_model(128); }

// A wavy carving path across the box's +z face, 300 samples.
std::vector<ToolSample> stream() { return test::wavy_cut(300); }

struct Ended {
    TriMesh mesh;        // the Contourer's mesh of the final model
    MeshFrame first;     // the first mesh published
    MeshFrame last;      // the last
    SculptStats stats;
};

// A session with per-tile meshes and coarse group levels: coarse first or everything contoured first.
Ended session(bool coarse_first) {
    compute::TriDexel m = box_model();
    compute::Contourer contourer(m);
    if (!coarse_first) contourer.update(m);
    SpscRing<ToolSample> ring(1024);
    TripleBuffer<ActiveSurface> surface;
    TripleBuffer<MeshFrame> meshes;
    SculptThread t(m, contourer, ring, surface, Vec3(0.0, 0.0, 0.07));
    compute::LodWorkerOptions lod;
    lod.lod.cell_m = m.lattice.cell_m;
    lod.coarse_groups_from_cells = 1;
    lod.coarse_first = coarse_first;
    t.use_tile_lod(lod);
    t.publish_mesh_to(meshes, 0.0, MeshForm::kTiles);
    Ended e;
    e.first = meshes.latest();
    t.start();
    for (const ToolSample& s : stream()) {  // a stroke while the tiles are being contoured
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
