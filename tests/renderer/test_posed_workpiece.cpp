// A posed workpiece (SceneView::workpiece_pose) draws as its triangles moved by the pose would: the whole mesh and
// culled tiles alike, with the same per-eye culling counts, within a code or two of rounding per channel.
#include <gtest/gtest.h>

#include <vector>

#include "core/error.hpp"
#include "core/pose.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr double kEyeSeparation = 0.065;

TriMesh moved(const TriMesh& m, const Pose& p) {
    TriMesh out = m;
    for (Vec3& v : out.positions) v = p.apply(v);
    return out;
}

Aabb box(const Vec3& lo, const Vec3& hi) {
    Aabb b;
    b.add(lo);
    b.add(hi);
    return b;
}

// Turned 25 degrees about y and 10 about x, moved 2 cm right: a pose that keeps the centre tile in view and the
// tiles behind the head and far to the side out of it.
const Pose kPose{Vec3(0.02, 0.0, 0.0), glm::angleAxis(glm::radians(25.0), Vec3(0.0, 1.0, 0.0)) *
                                           glm::angleAxis(glm::radians(10.0), Vec3(1.0, 0.0, 0.0))};

TEST(PosedWorkpiece, TheWholeMeshDrawsAsTheMovedMesh) {
    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 160, 120);
        const TriMesh cube = test::test_cube();
        const TriMesh placed_cube = moved(cube, kPose);
        SceneView posed = test::test_scene(cube);
        posed.workpiece_pose = kPose;
        posed.occlusion_strength = 0.0;
        SceneView baked = test::test_scene(placed_cube);
        baked.occlusion_strength = 0.0;
        const StereoImages a = r.render(posed, test::small_screen(), test::test_head(), kEyeSeparation);
        const StereoImages b = r.render(baked, test::small_screen(), test::test_head(), kEyeSeparation);
        for (int e = 0; e < 2; ++e) {
            const ImageComparison c = compare_images(e ? a.right : a.left, e ? b.right : b.left, 2);
            EXPECT_LE(c.max_channel_diff, 2) << "eye " << e;
        }
        // Unposed, the picture differs: the test compares something.
        SceneView plain = test::test_scene(cube);
        plain.occlusion_strength = 0.0;
        const StereoImages p = r.render(plain, test::small_screen(), test::test_head(), kEyeSeparation);
        EXPECT_GT(compare_images(p.left, b.left, 2).max_channel_diff, 40);
        // A pose that is not rigid and finite is refused.
        SceneView bad = posed;
        bad.workpiece_pose.orientation = Quat(2.0, 0.0, 0.0, 0.0);
        EXPECT_THROW((void)r.render(bad, test::small_screen(), test::test_head(), kEyeSeparation), Error);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(PosedWorkpiece, CulledTilesDrawAsTheMovedTilesWithTheSameCounts) {
    gpu::Context ctx = gpu::Context::create({});
    {
        // In the model frame: a tile at the screen centre, one behind the head, one far to the side.
        const Aabb boxes[3] = {box(Vec3(-0.03), Vec3(0.03)), box(Vec3(-0.05, -0.05, 0.6), Vec3(0.05, 0.05, 0.7)),
                               box(Vec3(0.9, -0.05, -0.05), Vec3(1.0, 0.05, 0.05))};
        std::vector<TriMesh> model, world;
        for (const Aabb& b : boxes) {
            model.push_back(test::flat_shaded(box_mesh(b)));
            world.push_back(moved(model.back(), kPose));
        }
        std::vector<TileMesh> model_tiles, world_tiles;
        for (std::size_t i = 0; i < 3; ++i) {
            model_tiles.push_back(TileMesh{&model[i], boxes[i], 1, nullptr, 10 + i});
            world_tiles.push_back(TileMesh{&world[i], placed(boxes[i], kPose), 1, nullptr, 10 + i});
        }
        const Pose head{Vec3(0.0, 0.0, 0.5)};
        OffscreenStereoRenderer ra = OffscreenStereoRenderer::create(ctx, 160, 120);
        OffscreenStereoRenderer rb = OffscreenStereoRenderer::create(ctx, 160, 120);
        SceneView posed;
        posed.show_workspace = false;
        posed.occlusion_strength = 0.0;
        posed.cull_tiles = true;
        posed.tiles = model_tiles;
        posed.workpiece_pose = kPose;
        SceneView baked = posed;
        baked.tiles = world_tiles;
        baked.workpiece_pose = Pose{};
        const StereoImages a = ra.render(posed, test::small_screen(), head, kEyeSeparation);
        const StereoImages b = rb.render(baked, test::small_screen(), head, kEyeSeparation);
        for (int e = 0; e < 2; ++e) {
            EXPECT_EQ(a.stats.tiles[e].drawn, 1u) << "eye " << e;
            EXPECT_EQ(a.stats.tiles[e].skipped, 2u) << "eye " << e;
            EXPECT_EQ(a.stats.tiles[e].drawn, b.stats.tiles[e].drawn);
            EXPECT_EQ(a.stats.tile_triangles[e], b.stats.tile_triangles[e]);
            EXPECT_LE(compare_images(e ? a.right : a.left, e ? b.right : b.left, 2).max_channel_diff, 2) << "eye " << e;
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
