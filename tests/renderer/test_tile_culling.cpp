// Tile culling: frustum planes of the off-axis eyes, the conservative box test, per-eye drawing of workpiece
// tiles with exact counts, and re-upload of a tile only when its version changes.
#include <gtest/gtest.h>

#include <algorithm>

#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "core/error.hpp"
#include "core/primitives.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "renderer/scene/tile_culling.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr double kEyeSeparation = 0.065;

Aabb box(const Vec3& lo, const Vec3& hi) {
    Aabb b;
    b.add(lo);
    b.add(hi);
    return b;
}

Mat4 clip_from_world(const Vec3& eye) {
    const EyeView v = off_axis_view(test::small_screen(), eye, 0.05, 20.0);
    return v.projection * v.view;
}

// Clip-space containment of one point (Vulkan: -w <= x, y <= w, 0 <= z <= w).
bool point_inside(const Mat4& m, const Vec3& p) {
    const glm::dvec4 c = m * glm::dvec4(p, 1.0);
    return c.w > 0.0 && std::abs(c.x) <= c.w && std::abs(c.y) <= c.w && c.z >= 0.0 && c.z <= c.w;
}

TEST(TileCulling, FrustumOfACentredEyeAgainstBoxes) {
    // Eye 0.5 m in front of the 0.4 m x 0.3 m screen's centre; near 0.05 m, far 20 m (plane z = -19.5).
    const Frustum f = frustum_from_clip(clip_from_world(Vec3(0.0, 0.0, 0.5)));
    EXPECT_TRUE(may_be_visible(f, box(Vec3(-0.01), Vec3(0.01))));
    // In the screen plane the frustum is exactly the screen: x = -0.2 is its left edge.
    EXPECT_FALSE(may_be_visible(f, box(Vec3(-0.3, -0.01, -0.001), Vec3(-0.201, 0.01, 0.001))));
    EXPECT_TRUE(may_be_visible(f, box(Vec3(-0.3, -0.01, -0.001), Vec3(-0.199, 0.01, 0.001))));
    EXPECT_FALSE(may_be_visible(f, box(Vec3(-0.01, 0.151, -0.001), Vec3(0.01, 0.2, 0.001))));  // above the top
    EXPECT_FALSE(may_be_visible(f, box(Vec3(-0.01, -0.01, 0.46), Vec3(0.01, 0.01, 0.7))));    // nearer than near
    EXPECT_TRUE(may_be_visible(f, box(Vec3(-0.01, -0.01, 0.44), Vec3(0.01, 0.01, 0.7))));     // crosses near
    EXPECT_FALSE(may_be_visible(f, box(Vec3(-0.01, -0.01, -30.0), Vec3(0.01, 0.01, -19.6)))); // beyond far
    EXPECT_FALSE(may_be_visible(f, Aabb{}));                                                  // empty
    EXPECT_THROW(may_be_visible(f, box(Vec3(0.0), Vec3(0.0, 0.0, std::numeric_limits<double>::infinity()))), Error);
    Mat4 bad(1.0);
    bad[2][1] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(frustum_from_clip(bad), Error);
}

TEST(TileCulling, NeverRejectsABoxWithAPointInside) {
    // Conservative: for 3000 random boxes, whenever one of 27 sample points (corners, edge and face centres,
    // centre) is inside the frustum, the box must be kept.
    const Mat4 m = clip_from_world(Vec3(0.1, 0.12, 0.5));
    const Frustum f = frustum_from_clip(m);
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> pos(-0.35, 0.45), ext(0.001, 0.2);
    int kept = 0, rejected = 0;
    for (int i = 0; i < 3000; ++i) {
        const Vec3 lo(pos(rng), pos(rng), pos(rng));
        const Aabb b = box(lo, lo + Vec3(ext(rng), ext(rng), ext(rng)));
        bool any_inside = false;
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c)
                for (int d = 0; d < 3; ++d)
                    any_inside = any_inside || point_inside(m, b.lo + b.size() * Vec3(a / 2.0, c / 2.0, d / 2.0));
        const bool visible = may_be_visible(f, b);
        if (any_inside) {
            EXPECT_TRUE(visible) << i;
        }
        (visible ? kept : rejected) += 1;
    }
    std::printf("[culling] %d of 3000 random boxes kept, %d rejected\n", kept, rejected);
    EXPECT_GT(rejected, 300);  // the test exercises both outcomes
    EXPECT_GT(kept, 300);
}

// Five box tiles for the test head (0, 0, 0.5) and eyes at x = -/+0.0325: A at the screen centre (both eyes),
// B near the left edge halfway to the viewer (left eye only), C its mirror image (right eye only), D behind
// the head (neither), E far to the side (neither). Each tile has its own material so its pixels are
// recognisable: A clay (0), B green (2), C blue (3), D and E red (1).
struct FiveTiles {
    std::vector<TriMesh> meshes;
    std::vector<std::vector<std::uint8_t>> materials;
    std::vector<TileMesh> tiles;

    FiveTiles() {
        const Aabb boxes[5] = {box(Vec3(-0.03, -0.03, -0.03), Vec3(0.03, 0.03, 0.03)),
                               box(Vec3(-0.112, -0.01, 0.24), Vec3(-0.095, 0.01, 0.26)),
                               box(Vec3(0.095, -0.01, 0.24), Vec3(0.112, 0.01, 0.26)),
                               box(Vec3(-0.05, -0.05, 0.6), Vec3(0.05, 0.05, 0.7)),
                               box(Vec3(0.9, -0.05, -0.05), Vec3(1.0, 0.05, 0.05))};
        const std::uint8_t ids[5] = {0, 2, 3, 1, 1};
        for (int i = 0; i < 5; ++i) {
            meshes.push_back(box_mesh(boxes[i]));
            materials.emplace_back(meshes.back().positions.size(), ids[i]);
        }
        for (int i = 0; i < 5; ++i)
            tiles.push_back(TileMesh{&meshes[i], boxes[i], 1, &materials[i], static_cast<std::uint64_t>(100 + i)});
    }
};

std::size_t count_pixels(const Image& img, bool (*match)(const std::uint8_t*)) {
    std::size_t n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) n += match(img.at(x, y)) ? 1 : 0;
    return n;
}
bool greenish(const std::uint8_t* p) { return p[1] > p[0] + 30 && p[1] > p[2] + 30; }
bool bluish(const std::uint8_t* p) { return p[2] > p[0] + 40 && p[2] > p[1] + 20; }

TEST(TileCulling, TileSeenByOneEyeIsDrawnOnlyInThatEyeWithExactCounts) {
    gpu::Context ctx = gpu::Context::create({});
    {
        const FiveTiles five;
        SceneView v;
        v.show_workspace = false;
        v.tiles = five.tiles;
        const Pose head{Vec3(0.0, 0.0, 0.5)};
        for (EyeStrategy s : {EyeStrategy::kPassPerEye, EyeStrategy::kInstancedLayer, EyeStrategy::kMultiview}) {
            OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 160, 120, s);
            if (r.strategy() != s) continue;  // not supported here, or its self-test failed
            SCOPED_TRACE(std::string(to_string(s)));
            v.cull_tiles = true;
            const StereoImages culled = r.render(v, test::small_screen(), head, kEyeSeparation);
            if (s == EyeStrategy::kMultiview) {
                // One view mask for both eyes: a tile either eye sees is drawn (and counted) in both.
                EXPECT_EQ(culled.stats.tiles[0].drawn, 3u);
                EXPECT_EQ(culled.stats.tiles[0].skipped, 2u);
            } else {
                EXPECT_EQ(culled.stats.tiles[0].drawn, 2u);    // A, B
                EXPECT_EQ(culled.stats.tiles[0].skipped, 3u);  // C, D, E
                EXPECT_EQ(culled.stats.tiles[1].drawn, 2u);    // A, C
                EXPECT_EQ(culled.stats.tiles[1].skipped, 3u);  // B, D, E
            }
            // B (green) shows in the left eye only, C (blue) in the right eye only.
            EXPECT_GT(count_pixels(culled.left, greenish), 20u);
            EXPECT_EQ(count_pixels(culled.left, bluish), 0u);
            EXPECT_GT(count_pixels(culled.right, bluish), 20u);
            EXPECT_EQ(count_pixels(culled.right, greenish), 0u);

            // Without culling every tile is drawn in both eyes, and the images are the same pixel for pixel.
            v.cull_tiles = false;
            const StereoImages all = r.render(v, test::small_screen(), head, kEyeSeparation);
            for (int e = 0; e < 2; ++e) {
                EXPECT_EQ(all.stats.tiles[e].drawn, 5u);
                EXPECT_EQ(all.stats.tiles[e].skipped, 0u);
            }
            EXPECT_EQ(compare_images(all.left, culled.left, 0).within, 160u * 120u);
            EXPECT_EQ(compare_images(all.right, culled.right, 0).within, 160u * 120u);
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// A tile is uploaded when a frame first draws it, and again only when its version changes: the tiles culled in
// both eyes are never uploaded until a frame draws them.
TEST(TileCulling, TilesAreUploadedWhenDrawnOnceAndAgainOnlyWhenTheirVersionChanges) {
    gpu::Context ctx = gpu::Context::create({});
    {
        FiveTiles five;
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 64, 48);
        SceneView v;
        v.show_workspace = false;
        v.tiles = five.tiles;
        const Pose head{Vec3(0.0, 0.0, 0.5)};
        const auto frame = [&] { return r.render(v, test::small_screen(), head, kEyeSeparation); };

        const StereoImages first = frame();
        // The tiles either eye draws: each uploaded once.
        const std::size_t seen = first.stats.tile_uploads;
        EXPECT_GE(seen, std::max(first.stats.tiles[0].drawn, first.stats.tiles[1].drawn));
        EXPECT_LE(seen, first.stats.tiles[0].drawn + first.stats.tiles[1].drawn);
        ASSERT_LT(seen, 5u) << "some tiles are culled in both eyes";
        EXPECT_EQ(frame().stats.tile_uploads, 0u);

        // Moving tile A's vertices without a new version is not seen (no upload, same image)...
        for (Vec3& p : five.meshes[0].positions) p.x += 0.05;
        const StereoImages stale = frame();
        EXPECT_EQ(stale.stats.tile_uploads, 0u);
        EXPECT_EQ(compare_images(stale.left, first.left, 0).within, 64u * 48u);
        // ...a new version is: one upload, and the image changes.
        five.tiles[0].version = 2;
        const StereoImages moved = frame();
        EXPECT_EQ(moved.stats.tile_uploads, 1u);
        EXPECT_LT(compare_images(moved.left, first.left, 0).within, 64u * 48u);
        EXPECT_EQ(frame().stats.tile_uploads, 0u);

        // Without culling the tiles no eye sees are drawn too: uploaded now, once.
        v.cull_tiles = false;
        EXPECT_EQ(frame().stats.tile_uploads, 5u - seen);
        EXPECT_EQ(frame().stats.tile_uploads, 0u);
        // Dropping a tile frees it; listing it again uploads it again.
        v.tiles = std::span<const TileMesh>(five.tiles).first(4);
        EXPECT_EQ(frame().stats.tile_uploads, 0u);
        v.tiles = five.tiles;
        EXPECT_EQ(frame().stats.tile_uploads, 1u);
        EXPECT_EQ(r.tile_uploads_total(), 7u);
        // The same tiles in another order: found by id, nothing uploaded, the same picture; then a changed version
        // in that order is uploaded once.
        const StereoImages in_order = frame();
        std::vector<TileMesh> reversed(five.tiles.rbegin(), five.tiles.rend());
        v.tiles = reversed;
        const StereoImages shuffled = frame();
        EXPECT_EQ(shuffled.stats.tile_uploads, 0u);
        EXPECT_EQ(compare_images(shuffled.left, in_order.left, 0).within, 64u * 48u);
        reversed[1].version = 3;
        EXPECT_EQ(frame().stats.tile_uploads, 1u);
        EXPECT_EQ(frame().stats.tile_uploads, 0u);
        v.tiles = five.tiles;
        EXPECT_EQ(frame().stats.tile_uploads, 1u) << "the tile's version went back";
        v.cull_tiles = true;

        // Duplicate ids and bad materials are user errors naming the field; the renderer stays usable.
        std::vector<TileMesh> dup = {five.tiles[0], five.tiles[0]};
        v.tiles = dup;
        EXPECT_THROW(frame(), Error);
        std::vector<std::uint8_t> bad_ids(8, 9);
        std::vector<TileMesh> bad = {five.tiles[1]};
        bad[0].materials = &bad_ids;
        bad[0].version = 7;
        v.tiles = bad;
        try {
            frame();
            ADD_FAILURE() << "material id 9 accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("SceneView.tiles[0]"), std::string::npos) << e.what();
        }
        v.tiles = five.tiles;
        EXPECT_EQ(frame().stats.tiles[0].drawn + frame().stats.tiles[0].skipped, 5u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
