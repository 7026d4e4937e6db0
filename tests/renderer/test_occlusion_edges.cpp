// The ambient occlusion up to the image's edges: close up, where the occlusion sphere covers many pixels, a sample
// pair reaching past the edge is drawn in towards its point rather than left out, so the shading changes smoothly
// there instead of stepping along rectangles inset from the edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "core/tri_mesh.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image.hpp"
#include "renderer/scene/primitive_meshes.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr int kW = 320, kH = 240;

double luma(const Image& img, int x, int y) {
    const std::uint8_t* c = &img.rgba[(static_cast<std::size_t>(y) * img.width + x) * 4];
    return 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2];
}

// A ball of radius 0.4 m just behind the test screen fills the view; with a 6 cm occlusion sphere (about 130 pixels
// across) its shading with the occlusion, divided by its shading without, is the occlusion's colour scale per pixel.
// Between neighbouring pixels that scale changes by less than 5 % (the pixels next to the edge, where a pair's
// offsets shrink to a pixel or two, change most), nowhere by the step a pair leaving the image used to make.
TEST(OcclusionEdges, TheScaleChangesSmoothlyUpToTheImagesEdges) {
    gpu::Context ctx = gpu::Context::create({});
    TriMesh ball = unit_sphere(96, 192);
    for (Vec3& p : ball.positions) p = Vec3(0.01, -0.01, -0.35) + 0.4 * p;
    SceneView v;
    v.workpiece = &ball;
    v.show_workspace = false;
    v.eye_count = 1;
    v.occlusion_radius_m = 0.06;
    const Pose head{Vec3(0.0, 0.0, 0.5), Quat(1.0, 0.0, 0.0, 0.0)};
    OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH, EyeStrategy::kPassPerEye);
    const Image with = r.render(v, test::small_screen(), head, 0.0).left;
    v.occlusion_strength = 0.0;
    const Image without = r.render(v, test::small_screen(), head, 0.0).left;
    write_png("occlusion_edges_left.png", with);
    double worst = 0.0, lowest = 2.0, highest = 0.0;
    int wx = 0, wy = 0, covered = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double here = luma(without, x, y);
            if (here < 40.0) continue;  // background or too dark to divide by
            ++covered;
            const double s = luma(with, x, y) / here;
            lowest = std::min(lowest, s);
            highest = std::max(highest, s);
            for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
                if (x + dx >= kW || y + dy >= kH || luma(without, x + dx, y + dy) < 40.0) continue;
                const double jump = std::abs(luma(with, x + dx, y + dy) / luma(without, x + dx, y + dy) - s);
                if (jump > worst) {
                    worst = jump;
                    wx = x;
                    wy = y;
                }
            }
        }
    std::printf("occlusion scale %.3f .. %.3f over %d pixels; largest change between neighbours %.4f at (%d, %d)\n",
                lowest, highest, covered, worst, wx, wy);
    EXPECT_GT(covered, kW * kH * 9 / 10);  // the ball fills the view
    EXPECT_GT(highest - lowest, 0.05);     // the occlusion shades it
    EXPECT_LT(worst, 0.05);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
