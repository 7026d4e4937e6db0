// A render rank's replica contours only the changed tiles its viewports can see (with the tiles next to them, and
// the rest of their group of changed tiles); the rest wait for a view that needs them, and the tiles it draws are
// those of a replica that contours everything.
#include <gtest/gtest.h>

#include <vector>

#include "app/scene/run_scene.hpp"
#include "app/scene/session_spec.hpp"
#include "app/session/cluster/cluster_replica.hpp"
#include "app/support/assets.hpp"
#include "compute/contour/contour_dual.hpp"

namespace tridex::app {
namespace {

constexpr double kViewEdgeX = -0.03;  // the view sees x <= this, m

// Two grooves across the bunny, far apart: one at the left end (x -0.09 .. -0.05), one at the right (0.04 .. 0.08),
// the tool lifted between them.
FrameMessage two_grooves() {
    FrameMessage m;
    compute::JournalRecord r;
    r.kind = compute::JournalKind::kBatch;
    auto add = [&](double x, ToolOp op) {
        ToolSample s;
        s.t_s = static_cast<double>(r.samples.size()) * 1e-3;
        s.position = Vec3(x, 0.0, 0.05);
        s.tool.radius_m = 0.008;
        s.op = op;
        r.samples.push_back(s);
    };
    for (int i = 0; i <= 20; ++i) add(-0.09 + 0.04 * i / 20.0, ToolOp::kSubtract);
    add(0.04, ToolOp::kNone);
    for (int i = 0; i <= 20; ++i) add(0.04 + 0.04 * i / 20.0, ToolOp::kSubtract);
    m.records.push_back(r);
    return m;
}

// Everything with x <= kViewEdgeX (a frustum whose other five planes hold every point).
renderer::Frustum left_end() {
    renderer::Frustum f;
    for (glm::dvec4& p : f.planes) p = glm::dvec4(0.0, 0.0, 0.0, 1.0);
    f.planes[0] = glm::dvec4(-1.0, 0.0, 0.0, kViewEdgeX);
    return f;
}

TEST(ClusterReplica, ContoursOnlyTheChangedTilesItsViewsNeedAndTheRestLater) {
    SessionSpec spec = RunScene::default_spec();
    spec.mesh_path = default_mesh_path();
    spec.resolution = 96;
    const std::string json = spec_to_json(spec);
    ClusterReplica viewed(json), all(json);
    ASSERT_EQ(viewed.digest(), all.digest());
    const std::uint64_t first = viewed.tiles_contoured();
    EXPECT_GT(first, 0u);

    const FrameMessage m = two_grooves();
    viewed.apply(m);
    all.apply(m);
    ASSERT_EQ(viewed.digest(), all.digest());
    const renderer::Frustum frusta[] = {left_end()};
    viewed.contour(frusta);
    all.contour();
    const std::uint64_t partly = viewed.tiles_contoured() - first;
    const std::uint64_t whole = all.tiles_contoured() - first;
    std::printf("[cluster replica] the grooves changed %llu tiles; a view of the left end contoured %llu and left %zu\n",
                static_cast<unsigned long long>(whole), static_cast<unsigned long long>(partly), viewed.tiles_deferred());
    EXPECT_GT(viewed.tiles_deferred(), 0u);
    EXPECT_LT(partly, whole);
    EXPECT_EQ(partly + viewed.tiles_deferred(), whole);

    // Every tile the view can see is the same as the full replica's.
    const compute::Lattice& l = viewed.workpiece().model.lattice;
    const compute::TileGrid& g = viewed.workpiece().model.tiles;
    constexpr int kT = compute::TileGrid::kTileCells;
    int seen = 0;
    for (int tz = 0; tz < g.tiles[2]; ++tz)
        for (int ty = 0; ty < g.tiles[1]; ++ty)
            for (int tx = 0; tx < g.tiles[0]; ++tx) {
                const double hi_x = l.to_world(Vec3((tx + 1) * kT + 1, 0, 0)).x;
                if (hi_x > kViewEdgeX) continue;  // not wholly within the view
                const std::size_t t = g.index(tx, ty, tz);
                const TriMesh a = viewed.contourer().tile_mesh(t), b = all.contourer().tile_mesh(t);
                EXPECT_EQ(a.positions, b.positions) << "tile " << t;
                EXPECT_EQ(a.triangles, b.triangles) << "tile " << t;
                ++seen;
            }
    EXPECT_GT(seen, 0);

    // A view of everything contours the rest: the same mesh as the replica that contoured every change at once.
    viewed.contour();
    EXPECT_EQ(viewed.tiles_deferred(), 0u);
    const TriMesh a = viewed.contourer().mesh(), b = all.contourer().mesh();
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.triangles, b.triangles);
}

}  // namespace
}  // namespace tridex::app
