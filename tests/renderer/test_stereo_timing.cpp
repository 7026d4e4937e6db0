// Measures a 1024x768 stereo frame of a ~150k-triangle mesh on lavapipe and checks what it shows.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "gpu/context.hpp"
#include "renderer/image/image.hpp"
#include "renderer/scene/primitive_meshes.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::renderer {
namespace {

TEST(StereoTiming, Frame1024x768Of150kTriangles) {
    gpu::Context ctx = gpu::Context::create({});
    // UV sphere, 250 rings x 300 segments = 149,400 triangles, radius 0.4 m at the screen centre.
    TriMesh mesh = unit_sphere(250, 300);
    for (Vec3& p : mesh.positions) p *= 0.4;
    ASSERT_EQ(mesh.triangles.size(), 149400u);
    SceneView scene;
    scene.workpiece = &mesh;
    scene.tool_centre_m = Vec3(0.3, 0.3, 0.45);
    scene.tool_radius_m = 0.05;
    scene.workspace_m.add(Vec3(-0.6, -0.5, -0.3));
    scene.workspace_m.add(Vec3(0.6, 0.5, 0.6));
    const Pose head{Vec3(0.1, 0.2, 2.0)};
    for (EyeStrategy preferred : {EyeStrategy::kPassPerEye, EyeStrategy::kInstancedLayer}) {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 1024, 768, preferred);
        StereoImages e;
        std::vector<double> ms;
        for (int i = 0; i < 5; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            e = r.render(scene, Screen::powerwall(), head, 0.065);
            ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        std::sort(ms.begin(), ms.end());
        const std::string name(to_string(r.strategy()));
        std::printf("[timing] 1024x768 stereo, %zu triangles, strategy %s, validation %s: median %.1f ms, "
                    "min %.1f ms (5 frames, including mesh upload and readback)\n",
                    mesh.triangles.size(), name.c_str(), ctx.validation_enabled() ? "on" : "off", ms[2], ms[0]);
        RecordProperty("median_ms_" + name, std::to_string(ms[2]));
        write_png((std::filesystem::current_path() / ("stereo_timing_" + name + ".png")).string(),
                  side_by_side(e.left, e.right));

        // The sphere covers the image centre in both eyes: lit clay colour (red > blue), not the clear colour.
        for (const Image* img : {&e.left, &e.right}) {
            const std::uint8_t* p = img->at(512, 384);
            EXPECT_GT(p[0], p[2] + 40) << int(p[0]) << "," << int(p[1]) << "," << int(p[2]);
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
