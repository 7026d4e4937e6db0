// Mono = one eye's work only: SceneView.eye_count = 1 draws the left eye into layer 0 and skips the
// right eye's pass; the image equals the left eye of a stereo frame with the same head and separation, the
// FrameStats hold only eye-0 passes and tile counts, and the GPU time is about half a stereo frame's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/scene/primitive_meshes.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// A fine sphere (about 77 k triangles) of radius 0.08 m on the screen plane, split into 8 octant tiles.
struct TiledSphere {
    std::vector<TriMesh> meshes;
    std::vector<TileMesh> tiles;
    TiledSphere() {
        TriMesh sphere = unit_sphere(160, 240);
        for (Vec3& p : sphere.positions) p *= 0.08;
        meshes.resize(8);
        std::vector<std::vector<std::int64_t>> remap(8, std::vector<std::int64_t>(sphere.positions.size(), -1));
        for (const auto& t : sphere.triangles) {
            const Vec3 c = (sphere.positions[t[0]] + sphere.positions[t[1]] + sphere.positions[t[2]]) / 3.0;
            const int o = (c.x > 0 ? 1 : 0) | (c.y > 0 ? 2 : 0) | (c.z > 0 ? 4 : 0);
            auto tri = t;
            for (int k = 0; k < 3; ++k) {
                std::int64_t& m = remap[o][t[k]];
                if (m < 0) {
                    m = static_cast<std::int64_t>(meshes[o].positions.size());
                    meshes[o].positions.push_back(sphere.positions[t[k]]);
                }
                tri[k] = static_cast<std::uint32_t>(m);
            }
            meshes[o].triangles.push_back(tri);
        }
        for (int o = 0; o < 8; ++o) {
            TileMesh tm;
            tm.mesh = &meshes[o];
            for (const Vec3& p : meshes[o].positions) tm.bounds_m.add(p);
            tm.version = 1;
            tm.id = static_cast<std::uint64_t>(o);
            tiles.push_back(tm);
        }
    }
};

TEST(MonoEye, DrawsOnlyTheLeftEyeAndCostsAboutHalf) {
    gpu::Context ctx = gpu::Context::create({});
    constexpr int kW = 640, kH = 360;
    OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
    std::printf("[mono] strategy: %s\n", r.strategy_note().c_str());
    const TiledSphere sphere;
    SceneView scene;
    scene.tiles = sphere.tiles;
    const Screen screen = test::small_screen();
    const Pose head = test::test_head();

    SceneView bad = scene;
    bad.eye_count = 3;
    EXPECT_THROW(r.draw(bad, screen, head, 0.065), Error);

    const StereoImages stereo = r.render(scene, screen, head, 0.065);
    SceneView mono_scene = scene;
    mono_scene.eye_count = 1;
    const StereoImages mono = r.render(mono_scene, screen, head, 0.065);
    // The one eye is the stereo frame's left eye, bit for bit, returned as both images. (No overlay here:
    // its text shows the previous frame's time and the right eye's tile counts, which differ.)
    const ImageComparison c = compare_images(mono.left, stereo.left, 0);
    EXPECT_EQ(c.max_channel_diff, 0);
    EXPECT_EQ(compare_images(mono.right, mono.left, 0).max_channel_diff, 0);
    EXPECT_GT(compare_images(stereo.right, stereo.left, 0).max_channel_diff, 0);

    // FrameStats: only eye 0's tiles; with pass-per-eye only eye-0 passes (one shared pass otherwise).
    EXPECT_EQ(mono.stats.tiles[1].drawn + mono.stats.tiles[1].skipped, 0u);
    EXPECT_EQ(mono.stats.tiles[0].drawn, stereo.stats.tiles[0].drawn);
    EXPECT_GT(mono.stats.tiles[0].drawn, 0u);
    bool any_right = false, any_left = false;
    for (const PassTime& p : mono.stats.passes) {
        any_right = any_right || p.eye == 1;
        any_left = any_left || p.eye == 0;
    }
    EXPECT_FALSE(any_right);
    if (r.strategy() == EyeStrategy::kPassPerEye) {
        EXPECT_TRUE(any_left);
        EXPECT_EQ(mono.stats.passes.size() * 2, stereo.stats.passes.size());
    }

    // Cost: median GPU frame time of 15 frames each (interleaved, so load changes hit both alike), overlay on.
    scene.show_overlay = true;
    mono_scene.show_overlay = true;
    std::vector<double> stereo_ms, mono_ms;
    for (int i = 0; i < 15; ++i) {
        r.draw(scene, screen, head, 0.065);
        stereo_ms.push_back(r.finish().frame_ms);
        r.draw(mono_scene, screen, head, 0.065);
        mono_ms.push_back(r.finish().frame_ms);
    }
    const double s = median(stereo_ms), m = median(mono_ms);
    std::printf("[mono] %dx%d per eye, 77k-triangle sphere in 8 tiles + overlay, %s: stereo frame median %.2f ms, "
                "mono %.2f ms (ratio %.2f)\n",
                kW, kH, r.gpu_timestamps_available() ? "GPU timestamps" : "CPU clock", s, m, m / s);
    if (r.strategy() != EyeStrategy::kMultiview) {
        EXPECT_LT(m, 0.8 * s);  // about half; the bound leaves room for a shared, noisy machine
        EXPECT_GT(m, 0.2 * s);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
