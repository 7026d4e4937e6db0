// tests/app/test_gpu_contour_lod.cpp - levels of detail on the GPU-contour path: the tiles read back from the GPU
// contour are its buffers' content (same triangles as the CPU contour, float positions that round-trip exactly),
// only redone tiles are read again, a frame draws a tile from its levels only while they are the buffers' content,
// and the levels drawn beside the indirect tiles match the full-resolution contour with no cracks, validation on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <vector>

#include "app/commands/demo/demo.hpp"
#include "app/scene/stroke.hpp"
#include "app/session/view/gpu_tile_split.hpp"
#include "app/session/batch/session.hpp"
#include "app/session/view/tile_view.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/contour/contour_tiles.hpp"
#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/runtime/gpu_contour_share.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"
#include "lod_render_compare.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {
namespace {

compute::Sweep ball_sweep(const Vec3& a, const Vec3& b, double radius_m) {
    compute::Sweep s;
    s.op = ToolOp::kSubtract;
    s.tool = compute::SweepTool{compute::ToolKind::kBall, radius_m, 0.0};
    s.path_m = Segment{a, b};
    return s;
}

// A groove along the planned stroke of the bunny at N = 64.
std::vector<compute::Sweep> groove(const compute::TriDexel& model) {
    StrokeParams sp;
    sp.length_m = 0.06;
    sp.depth_m = 0.004;
    sp.tool_radius_m = 0.006;
    const StrokePlan plan = plan_stroke(model, sp);
    std::vector<compute::Sweep> batch;
    for (std::size_t i = 1; i < plan.world_m.size(); ++i)
        batch.push_back(ball_sweep(plan.world_m[i - 1], plan.world_m[i], 0.006));
    return batch;
}

std::size_t dirty_count(const compute::TileGrid& grid) {
    return static_cast<std::size_t>(std::count_if(grid.dirty.begin(), grid.dirty.end(), [](auto d) { return d != 0; }));
}

TEST(GpuContourLod, ReadBackTilesAreTheBuffersContentAndOnlyRedoneTilesAreReadAgain) {
    gpu::ContextOptions opt;
    opt.validation = true;
    gpu::Context ctx = gpu::Context::create(opt);
    Workpiece wp = prepare_workpiece(default_mesh_path(), 64, 0.12, Vec3(0.0, 0.0, 0.05));
    compute::GpuSculptor sculptor(ctx, wp.model);
    sculptor.apply(groove(wp.model));
    GpuContourShare share(ctx, sculptor.slabs(), wp.model);
    ASSERT_GT(share.update_all(), 0u);
    wp.model.clear_dirty();

    compute::TileSurfaceCache cache;
    EXPECT_THROW(share.refresh_tiles(cache), Error);  // nothing is copied out unless asked
    share.read_back_tiles();                      // copies the contour made so far
    const std::size_t read = share.refresh_tiles(cache);
    std::fill(wp.model.tiles.dirty.begin(), wp.model.tiles.dirty.end(), std::uint8_t{1});
    compute::Contourer cpu(wp.model);
    cpu.update(wp.model);
    wp.model.clear_dirty();
    std::size_t nonempty = 0;
    for (std::size_t t = 0; t < cpu.tile_count(); ++t) nonempty += cpu.tile_triangle_count(t) > 0 ? 1 : 0;
    EXPECT_EQ(read, nonempty);
    ASSERT_EQ(cache.tiles().size(), nonempty);
    const compute::Lattice& lat = wp.model.lattice;
    std::map<std::uint64_t, std::uint64_t> versions;
    for (const compute::TileSurface& s : cache.tiles()) {
        // The GPU contour has the CPU contour's triangles, and every vertex is a float grid position as drawn.
        EXPECT_EQ(s.mesh.triangles.size(), cpu.tile_triangle_count(s.id)) << "tile " << s.id;
        EXPECT_EQ(s.materials.size(), s.mesh.positions.size());
        for (const Vec3& p : s.mesh.positions) {
            const glm::vec3 g((p - lat.origin_m) / lat.cell_m);
            ASSERT_EQ(lat.origin_m + Vec3(g) * lat.cell_m, p) << "tile " << s.id;
        }
        EXPECT_NE(s.source_version, 0u);
        EXPECT_EQ(s.source_version, share.tile_version(s.id));
        EXPECT_FALSE(s.lods_built);  // no levels asked for
        versions[s.id] = s.source_version;
    }
    EXPECT_EQ(share.refresh_tiles(cache), 0u);  // nothing redone: nothing read

    // A second cut: only its dirty tiles are redone, get new versions and are read again.
    const Vec3 c = wp.model.lattice.to_world(Vec3(32.0, 40.0, 32.0));
    const std::vector<compute::Sweep> cut = {ball_sweep(c - Vec3(0.02, 0.0, 0.0), c + Vec3(0.02, 0.0, 0.0), 0.01)};
    sculptor.apply(cut);
    const std::size_t dirty = dirty_count(wp.model.tiles);
    ASSERT_GT(dirty, 0u);
    ASSERT_LT(dirty, wp.model.tiles.count());
    share.update_dirty(wp.model.tiles);
    std::vector<std::uint8_t> was_dirty(wp.model.tiles.dirty.begin(), wp.model.tiles.dirty.end());
    wp.model.clear_dirty();
    const std::size_t again = share.refresh_tiles(cache);
    std::printf("[gpu-contour lod] %zu tiles read at first, %zu dirty tiles, %zu read again\n", read, dirty, again);
    EXPECT_GT(again, 0u);
    EXPECT_LE(again, dirty);
    for (const compute::TileSurface& s : cache.tiles()) {
        EXPECT_EQ(s.source_version, share.tile_version(s.id));
        const auto v = versions.find(s.id);
        if (was_dirty[s.id] == 0) {
            ASSERT_NE(v, versions.end()) << "tile " << s.id;
            EXPECT_EQ(s.source_version, v->second) << "tile " << s.id;
        } else if (v != versions.end()) {
            EXPECT_NE(s.source_version, v->second) << "tile " << s.id;
        }
    }
    EXPECT_THROW(share.tile_version(wp.model.tiles.count()), Error);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

std::shared_ptr<const compute::TileSurface> tile(std::uint64_t id, std::uint64_t source_version, bool built) {
    auto s = std::make_shared<compute::TileSurface>();
    s->id = id;
    s->version = source_version + 1000;
    s->source_version = source_version;
    s->lods_built = built;
    return s;
}

std::shared_ptr<const compute::TileGroupSurface> group(int depth, std::uint64_t index,
                                                       std::vector<std::uint64_t> children) {
    auto g = std::make_shared<compute::TileGroupSurface>();
    g->depth = depth;
    g->id = compute::tile_group_id(depth, index);
    g->children = std::move(children);
    return g;
}

TEST(GpuContourLod, AFrameDrawsATileFromItsLevelsOnlyWhileTheyAreTheBuffersContent) {
    renderer::IndirectWorkpiece iw;
    for (std::uint32_t id : {0u, 1u, 2u, 3u, 5u}) iw.tiles.push_back(renderer::IndirectTile{id, 30, Aabb{}, 100 + id});
    iw.triangles = 50;
    // 0: current and built; 1: built for an older contour; 2: not built yet; 3: current; 4: gone from the buffers;
    // 5: not read back yet.
    const std::vector<std::shared_ptr<const compute::TileSurface>> tiles = {
        tile(0, 100, true), tile(1, 90, true), tile(2, 102, false), tile(3, 103, true), tile(4, 104, true)};
    const std::vector<std::shared_ptr<const compute::TileGroupSurface>> groups = {
        group(1, 0, {0, 3}),  // every tile current: drawn from its levels
        group(1, 1, {0, 1}),  // tile 1 is stale
        group(2, 0, {compute::tile_group_id(1, 0)}),
        group(2, 1, {compute::tile_group_id(1, 0), compute::tile_group_id(1, 1)}),
        group(1, 2, {4})};  // tile 4 no longer in the buffers
    GpuTileSplit split;
    split_gpu_tiles(tiles, groups, iw, split);
    std::vector<std::uint64_t> drawn, left, groups_drawn;
    for (const auto& t : split.tiles) drawn.push_back(t->id);
    for (const auto& t : iw.tiles) left.push_back(t.id);
    for (const auto& g : split.groups) groups_drawn.push_back(g->id);
    EXPECT_EQ(drawn, (std::vector<std::uint64_t>{0, 3}));
    EXPECT_EQ(left, (std::vector<std::uint64_t>{1, 2, 5}));
    EXPECT_EQ(groups_drawn, (std::vector<std::uint64_t>{compute::tile_group_id(1, 0), compute::tile_group_id(2, 0)}));
    EXPECT_EQ(iw.triangles, 50u);  // the whole contour, whichever way its tiles are drawn
    // Reused storage; an empty publish leaves every tile to the buffers.
    split_gpu_tiles({}, {}, iw, split);
    EXPECT_TRUE(split.tiles.empty());
    EXPECT_TRUE(split.groups.empty());
    EXPECT_EQ(iw.tiles.size(), 3u);
}

TEST(GpuContourLod, LevelsBesideTheIndirectTilesMatchTheFullContourWithoutCracks) {
    gpu::ContextOptions opt;
    opt.validation = true;
    gpu::Context ctx = gpu::Context::create(opt);
    Workpiece wp = prepare_workpiece(default_mesh_path(), 128, 0.3, Vec3(0.0, 0.0, 0.3));
    compute::GpuSculptor sculptor(ctx, wp.model);
    GpuContourShare share(ctx, sculptor.slabs(), wp.model);
    ASSERT_GT(share.update_all(), 0u);
    wp.model.clear_dirty();
    compute::TileSurfaceCache cache;
    compute::TileLodOptions lo;
    lo.cell_m = wp.model.lattice.cell_m;
    cache.enable_lod(lo);  // refresh builds the levels at once
    share.read_back_tiles();
    share.refresh_tiles(cache);
    ASSERT_FALSE(cache.groups().empty());
    std::vector<std::shared_ptr<const compute::TileSurface>> tiles;
    std::vector<std::shared_ptr<const compute::TileGroupSurface>> groups;
    const auto publish = [&] {
        tiles.clear();
        groups.clear();
        for (const compute::TileSurface& s : cache.tiles())
            tiles.push_back(std::make_shared<const compute::TileSurface>(s));
        for (const compute::TileGroupSurface& g : cache.groups())
            groups.push_back(std::make_shared<const compute::TileGroupSurface>(g));
    };
    publish();

    renderer::OffscreenStereoRenderer r = renderer::OffscreenStereoRenderer::create(ctx, 640, 360);
    const renderer::Screen screen = renderer::Screen::powerwall();
    Pose head;
    head.position = Vec3(0.0, 0.15, 0.65);
    renderer::SceneView scene;
    scene.show_workspace = false;
    const renderer::StereoImages empty = r.render(scene, screen, head, 0.065);
    const std::uint8_t bg[3] = {empty.left.rgba[0], empty.left.rgba[1], empty.left.rgba[2]};

    // One frame as the session draws it: the buffers locked, the current tiles from their levels, the rest indirect.
    const auto render = [&](bool levels, std::size_t* indirect_left) {
        renderer::IndirectWorkpiece iw;
        auto lock = share.lock_frame(iw);
        renderer::SceneView v;
        v.show_workspace = false;
        v.indirect_workpiece = &iw;
        GpuTileSplit split;
        TileView view;
        if (levels) {
            split_gpu_tiles(tiles, groups, iw, split);
            tile_view_of(split.tiles, split.groups, true, view);
            v.tiles = view.tiles;
            v.tile_groups = view.groups;
            v.tiles_from_indirect = true;
        }
        if (indirect_left) *indirect_left = iw.tiles.size();
        return r.render(v, screen, head, 0.065);
    };
    for (const double z : {0.65, 1.6}) {
        head.position = Vec3(0.0, 0.15, z);
        std::size_t left = 0;
        const renderer::StereoImages lod = render(true, &left);
        const renderer::StereoImages full = render(false, nullptr);
        const LodImageDiff d = compare_lod_images(lod, full, bg);
        const double mismatch = static_cast<double>(d.mismatched) / static_cast<double>(d.pixels);
        std::printf(
            "[gpu-contour lod] head z %.2f m: groups drawn L %zu R %zu, triangles L %zu of %zu, %zu tiles "
            "indirect, silhouette mismatch %.4f%%, holes %zu, uploads %zu\n",
            z, lod.stats.groups_drawn[0], lod.stats.groups_drawn[1], lod.stats.tile_triangles[0],
            full.stats.tile_triangles[0], left, 100.0 * mismatch, d.holes, lod.stats.tile_uploads);
        EXPECT_EQ(left, 0u);  // every tile's levels are current
        EXPECT_GT(lod.stats.groups_drawn[0], 0u) << "z " << z;
        EXPECT_LT(2 * lod.stats.tile_triangles[0], full.stats.tile_triangles[0]) << "z " << z;
        EXPECT_LE(mismatch, 0.005) << "z " << z;
        EXPECT_LE(d.holes, z < 1.0 ? 0u : 2u) << "z " << z;
    }

    // A cut re-contours some tiles on the GPU, not yet read back: those are drawn from the buffers at full
    // resolution beside their neighbours' levels, and the surface stays closed where they meet.
    head.position = Vec3(0.0, 0.15, 0.65);
    const Vec3 c = wp.model.lattice.to_world(Vec3(64.0, 80.0, 64.0));
    const std::vector<compute::Sweep> cut = {ball_sweep(c - Vec3(0.05, 0.0, 0.0), c + Vec3(0.05, 0.0, 0.0), 0.02)};
    sculptor.apply(cut);
    share.update_dirty(wp.model.tiles);
    wp.model.clear_dirty();
    std::size_t left = 0;
    const renderer::StereoImages mixed = render(true, &left);
    const renderer::StereoImages full = render(false, nullptr);
    const LodImageDiff d = compare_lod_images(mixed, full, bg);
    const double mismatch = static_cast<double>(d.mismatched) / static_cast<double>(d.pixels);
    std::printf("[gpu-contour lod] after a cut: %zu tiles indirect, silhouette mismatch %.4f%%, holes %zu\n", left,
                100.0 * mismatch, d.holes);
    EXPECT_GT(left, 0u);
    EXPECT_LT(left, tiles.size());
    EXPECT_LE(mismatch, 0.005);
    EXPECT_EQ(d.holes, 0u);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::app
