// Tile buffers come from a pool: 2500 tiles (5000 vertex and index buffers) live in a couple of memory allocations,
// re-uploads and removals reuse them, the tile draws merge into a few multi-draws, and the tiles draw the same
// picture as one mesh of the same boxes.
#include <gtest/gtest.h>

#include <vector>

#include "core/primitives.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/stereo/draw_batching.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr int kSide = 50;  // kSide x kSide tiles

struct Grid {
    std::vector<TriMesh> meshes;
    std::vector<TileMesh> tiles;
    TriMesh whole;
    Grid() {
        meshes.reserve(kSide * kSide);
        for (int j = 0; j < kSide; ++j)
            for (int i = 0; i < kSide; ++i) {
                // A 4 mm cube every 6 mm over a 0.3 m square in the screen plane.
                const Vec3 lo(-0.15 + 0.006 * i, -0.15 + 0.006 * j, -0.002);
                Aabb b;
                b.add(lo);
                b.add(lo + Vec3(0.004));
                meshes.push_back(box_mesh(b));
                const auto base = static_cast<std::uint32_t>(whole.positions.size());
                whole.positions.insert(whole.positions.end(), meshes.back().positions.begin(),
                                       meshes.back().positions.end());
                for (auto t : meshes.back().triangles) whole.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
                tiles.push_back(TileMesh{&meshes.back(), b, 1, nullptr, static_cast<std::uint64_t>(j * kSide + i)});
            }
    }
};

TEST(TilePool, ThousandsOfTilesInAFewAllocations) {
    gpu::Context ctx = gpu::Context::create({});
    {
        Grid g;
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 200, 150);
        SceneView v;
        v.show_workspace = false;
        v.tiles = g.tiles;
        const Pose head{Vec3(0.0, 0.0, 0.5)};
        const StereoImages tiled = r.render(v, test::small_screen(), head, 0.064);
        std::printf("%zu tiles: %zu buffers in %zu memory allocations\n", g.tiles.size(), r.tile_buffers(),
                    r.tile_memory_blocks());
        EXPECT_EQ(r.tile_buffers(), 2u * g.tiles.size());
        EXPECT_GE(r.tile_memory_blocks(), 1u);
        EXPECT_LE(r.tile_memory_blocks(), 2u);  // 2500 x (24 vertices x 28 B + 36 indices x 4 B) is about 2 MB
        // The tiles of one block share its buffer: with multi-draw indirect the 2500 tile draws record as a run
        // per block (the picture is checked below against the single mesh).
        const FrameStats stats = r.draw(v, test::small_screen(), head, 0.064);
        if (multi_draw_supported(ctx)) {
            EXPECT_LE(stats.draws, 2u + r.tile_memory_blocks());  // the tile runs, the overlay panel and its text
            EXPECT_GE(stats.draws_merged, g.tiles.size() - 2 * r.tile_memory_blocks());
        } else {
            EXPECT_EQ(stats.draws_merged, 0u);
        }

        // The same boxes as one mesh: the same picture.
        SceneView one;
        one.show_workspace = false;
        one.workpiece = &g.whole;
        const StereoImages whole = r.render(one, test::small_screen(), head, 0.064);
        EXPECT_EQ(compare_images(tiled.left, whole.left, 1).within, static_cast<std::size_t>(200 * 150));
        EXPECT_EQ(compare_images(tiled.right, whole.right, 1).within, static_cast<std::size_t>(200 * 150));

        // Half the tiles change (larger meshes: new buffers), the rest stay: still a few allocations.
        std::vector<TriMesh> bigger(g.meshes.begin(), g.meshes.end());
        for (std::size_t k = 0; k < g.tiles.size(); k += 2) {
            TriMesh m = g.meshes[k];
            const TriMesh copy = m;
            const auto base = static_cast<std::uint32_t>(m.positions.size());
            m.positions.insert(m.positions.end(), copy.positions.begin(), copy.positions.end());
            for (auto t : copy.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
            bigger[k] = std::move(m);
            g.tiles[k].mesh = &bigger[k];
            g.tiles[k].version = 2;
        }
        v.tiles = g.tiles;
        r.render(v, test::small_screen(), head, 0.064);
        EXPECT_EQ(r.tile_buffers(), 2u * g.tiles.size());
        EXPECT_LE(r.tile_memory_blocks(), 2u);
        // No tiles: no tile buffers; one block stays for the next ones.
        v.tiles = {};
        r.render(v, test::small_screen(), head, 0.064);
        EXPECT_EQ(r.tile_buffers(), 0u);
        EXPECT_LE(r.tile_memory_blocks(), 1u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
