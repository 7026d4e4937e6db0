// What the stereo renderer draws besides the workpiece: per-material colours (checked against the shading
// formula), the force arrow (model matrices and projected length), the proxy, the arrow meshes, per-pass
// timing, and a golden image of the full scene.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>

#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/scene/arrow_mesh.hpp"
#include "renderer/scene/force_arrow.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/scene/material_palette.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr double kEyeSeparation = 0.065;

Vec3 apply(const Mat4& m, const Vec3& p) { return Vec3(m * glm::dvec4(p, 1.0)); }

TEST(SceneItems, ArrowMeshesAreClosedOutwardSolids) {
    for (int segments : {3, 16}) {
        const TriMesh cyl = unit_cylinder(segments), cone = unit_cone(segments);
        EXPECT_EQ(cyl.triangles.size(), 4u * segments);
        EXPECT_EQ(cone.triangles.size(), 2u * segments);
        // Closed up to welding (caps have their own vertices), so check the volume: regular polygon prisms.
        const double base = 0.5 * segments * std::sin(2.0 * std::acos(-1.0) / segments);  // polygon area, r = 1
        EXPECT_NEAR(signed_volume(cyl), base, 1e-12);
        EXPECT_NEAR(signed_volume(cone), base / 3.0, 1e-12);
        EXPECT_EQ(cyl.bounds().lo.z, 0.0);
        EXPECT_EQ(cyl.bounds().hi.z, 1.0);
        EXPECT_EQ(cone.bounds().hi.z, 1.0);
    }
    EXPECT_THROW(unit_cylinder(2), Error);
    EXPECT_THROW(unit_cone(2), Error);
}

TEST(SceneItems, ForceArrowTipIsScaleTimesForceFromTheOrigin) {
    const Vec3 origin(0.01, 0.02, 0.03), force(1.0, 2.0, -2.0);  // |F| = 3 N
    const ForceArrowStyle style;
    const ForceArrowTransforms a = force_arrow(origin, force, 0.02, style);
    ASSERT_TRUE(a.visible);
    EXPECT_DOUBLE_EQ(a.length_m, 0.06);
    const Vec3 tip = apply(a.head, Vec3(0.0, 0.0, 1.0));
    EXPECT_LT(glm::length(tip - (origin + 0.02 * force)), 1e-15);
    EXPECT_LT(glm::length(apply(a.shaft, Vec3(0.0)) - origin), 1e-15);
    EXPECT_LT(glm::length(apply(a.shaft, Vec3(0.0, 0.0, 1.0)) - apply(a.head, Vec3(0.0))), 1e-15);
    EXPECT_NEAR(glm::length(tip - apply(a.head, Vec3(0.0))), style.head_length_m, 1e-15);
    EXPECT_NEAR(glm::length(Vec3(a.head[0])), style.head_radius_m, 1e-15);
    EXPECT_NEAR(glm::length(Vec3(a.shaft[1])), style.shaft_radius_m, 1e-15);
    EXPECT_GT(glm::determinant(glm::dmat3(a.head)), 0.0);  // a rotation, not a mirror: winding stays outward
    EXPECT_GT(glm::determinant(glm::dmat3(a.shaft)), 0.0);
    // Along an axis too (the perpendicular is picked differently), and a short arrow's head is half of it.
    const ForceArrowTransforms x = force_arrow(Vec3(0.0), Vec3(0.5, 0.0, 0.0), 0.02, style);
    EXPECT_DOUBLE_EQ(x.length_m, 0.01);
    EXPECT_LT(glm::length(apply(x.head, Vec3(0.0, 0.0, 1.0)) - Vec3(0.01, 0.0, 0.0)), 1e-15);
    EXPECT_NEAR(glm::length(apply(x.head, Vec3(0.0))), 0.005, 1e-15);
    EXPECT_FALSE(force_arrow(origin, Vec3(0.0), 0.02).visible);
    EXPECT_FALSE(force_arrow(origin, force, 0.0).visible);
    EXPECT_THROW(force_arrow(origin, force, -0.02), Error);
    EXPECT_THROW(force_arrow(origin, Vec3(std::numeric_limits<double>::quiet_NaN()), 0.02), Error);
    ForceArrowStyle bad;
    bad.head_radius_m = 0.0;
    EXPECT_THROW(force_arrow(origin, force, 0.02, bad), Error);
}

bool reddish(const std::uint8_t* p) { return p[0] > 60 && p[0] > p[1] + 40 && p[0] > p[2] + 40; }

TEST(SceneItems, ForceArrowProjectedLengthIsScaleTimesForce) {
    gpu::Context ctx = gpu::Context::create({});
    {
        // 160 x 120 px over the 0.4 m x 0.3 m screen: 400 px per m. The arrow lies in the screen plane along +x
        // from x = -0.1 m (pixel column 40), so its tip is at column 40 + 400 * scale * |F|.
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 160, 120);
        SceneView v;
        v.show_workspace = false;
        v.tool_centre_m = Vec3(-0.1, 0.0, 0.0);
        v.force_N = Vec3(5.0, 0.0, 0.0);
        for (double scale : {0.02, 0.01}) {
            v.force_m_per_newton = scale;
            const StereoImages e = r.render(v, test::small_screen(), Pose{Vec3(0.0, 0.0, 0.5)}, kEyeSeparation);
            for (const Image* img : {&e.left, &e.right}) {
                int lo = 1000, hi = -1;
                for (int y = 57; y <= 62; ++y)
                    for (int x = 0; x < 160; ++x)
                        if (reddish(img->at(x, y))) {
                            lo = std::min(lo, x);
                            hi = std::max(hi, x);
                        }
                const double tip = 40.0 + 400.0 * scale * 5.0;
                // The cone narrows to the tip: pixel centres 0.5 px off the axis are covered from about 1.3 px
                // before it; the flat tail starts on column 40 (up to 0.5 px of perspective from the 2.5 mm radius).
                EXPECT_NEAR(lo, 40.0, 1.0) << "scale " << scale;
                EXPECT_NEAR(hi + 1.0, tip, 2.0) << "scale " << scale;
            }
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(SceneItems, PerVertexMaterialsGiveTheirPaletteColours) {
    gpu::Context ctx = gpu::Context::create({});
    {
        constexpr int kW = 160, kH = 120;
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
        // Two squares in the screen plane facing the viewer, in ONE mesh: left vertices material 0, right 1.
        TriMesh m;
        for (double x0 : {-0.15, 0.02}) {
            const auto b = static_cast<std::uint32_t>(m.positions.size());
            m.positions.insert(m.positions.end(), {Vec3(x0, -0.1, 0.0), Vec3(x0 + 0.13, -0.1, 0.0),
                                                   Vec3(x0 + 0.13, 0.1, 0.0), Vec3(x0, 0.1, 0.0)});
            m.triangles.push_back({b, b + 1, b + 2});
            m.triangles.push_back({b, b + 2, b + 3});
        }
        const std::vector<std::uint8_t> materials = {0, 0, 0, 0, 1, 1, 1, 1};
        SceneView v;
        v.show_workspace = false;
        v.occlusion_strength = 0.0;  // the colours are checked against the lighting formula alone
        v.workpiece = &m;
        v.workpiece_materials = &materials;
        const Pose head{Vec3(0.0, 0.0, 0.5)};
        const StereoImages e = r.render(v, test::small_screen(), head, kEyeSeparation);
        const auto eyes = eye_positions(head, kEyeSeparation);
        // Every pixel whose centre is at least 1 px inside a square: within 2 (of 255) of the formula.
        int checked = 0, worst = 0;
        for (int eye = 0; eye < 2; ++eye) {
            const Image& img = eye == 0 ? e.left : e.right;
            for (int y = 22; y <= 97; ++y)
                for (int x = 0; x < kW; ++x) {
                    const bool left = x >= 21 && x <= 70, right = x >= 89 && x <= 138;
                    if (!left && !right) continue;
                    const Vec3 p(-0.2 + (x + 0.5) / kW * 0.4, 0.15 - (y + 0.5) / kH * 0.3, 0.0);
                    const auto want = test::lit_colour(material_palette()[left ? 0 : 1], p, eyes[eye]);
                    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(img.at(x, y)[c] - want[c]));
                    ++checked;
                }
        }
        std::printf("[materials] %d pixels checked, worst channel difference %d\n", checked, worst);
        EXPECT_GT(checked, 7000);
        EXPECT_LE(worst, 2);
        // The same mesh without materials is all clay: the right square changes colour.
        v.workpiece_materials = nullptr;
        const StereoImages clay = r.render(v, test::small_screen(), head, kEyeSeparation);
        EXPECT_EQ(std::memcmp(clay.left.at(40, 60), e.left.at(40, 60), 4), 0);
        EXPECT_GT(std::abs(clay.left.at(110, 60)[2] - e.left.at(110, 60)[2]), 20);
        // Wrong size or id: errors naming the field; the renderer stays usable.
        const std::vector<std::uint8_t> short_list = {0, 1};
        v.workpiece_materials = &short_list;
        EXPECT_THROW(r.render(v, test::small_screen(), head, kEyeSeparation), Error);
        const std::vector<std::uint8_t> bad_id = {0, 0, 0, 0, 1, 1, 1, kMaterialCount};
        v.workpiece_materials = &bad_id;
        try {
            r.render(v, test::small_screen(), head, kEyeSeparation);
            ADD_FAILURE() << "material id " << kMaterialCount << " accepted";
        } catch (const Error& err) {
            EXPECT_NE(std::string(err.what()).find("SceneView.workpiece"), std::string::npos) << err.what();
        }
        v.workpiece_materials = &materials;
        EXPECT_EQ(compare_images(r.render(v, test::small_screen(), head, kEyeSeparation).left, e.left, 0).within,
                  static_cast<std::size_t>(kW * kH));
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(SceneItems, ProxyIsATranslucentSphere) {
    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 64, 48);
        const Pose head{Vec3(0.0, 0.0, 0.5)};
        SceneView behind;  // the blue tool ball behind where the proxy goes
        behind.show_workspace = false;
        behind.tool_centre_m = Vec3(0.0, 0.0, -0.05);
        behind.tool_radius_m = 0.05;
        SceneView with = behind;
        with.proxy_m = Vec3(0.0, 0.0, 0.05);
        with.proxy_radius_m = 0.03;
        SceneView proxy_only = with;
        proxy_only.tool_radius_m = 0.0;
        const std::uint8_t* a = nullptr;
        const StereoImages eb = r.render(behind, test::small_screen(), head, kEyeSeparation);
        const StereoImages ew = r.render(with, test::small_screen(), head, kEyeSeparation);
        const StereoImages ep = r.render(proxy_only, test::small_screen(), head, kEyeSeparation);
        a = ew.left.at(32, 24);
        const std::uint8_t *b = eb.left.at(32, 24), *p = ep.left.at(32, 24);
        EXPECT_GT(a[0], b[0]);  // yellow tint over the ball
        EXPECT_GT(a[2], p[2]);  // the ball shows through the proxy
        EXPECT_LT(a[2], b[2]);
        with.proxy_radius_m = std::numeric_limits<double>::infinity();
        EXPECT_THROW(r.render(with, test::small_screen(), head, kEyeSeparation), Error);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(SceneItems, PassTimesFromTimestampsOrTheCpuClock) {
    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, 96, 72, EyeStrategy::kPassPerEye);
        const TriMesh cube = test::test_cube();
        SceneView v = test::test_scene(cube);
        v.show_overlay = true;
        const FrameStats before = r.draw(v, test::small_screen(), test::test_head(), kEyeSeparation);
        EXPECT_LT(before.frame_ms, 0.0);  // no frame has finished yet: no timings
        const FrameStats s = r.finish();  // this frame's own
        EXPECT_EQ(s.tiles[0].drawn, before.tiles[0].drawn);
        if (r.gpu_timestamps_available()) {
            EXPECT_EQ(s.timing, TimingSource::kGpuTimestamps);
            ASSERT_EQ(s.passes.size(), 8u);  // 4 timed parts x 2 eyes (one render pass per eye)
            const char* names[4] = {"opaque", "occlusion", "translucent", "overlay"};
            double sum = 0.0;
            for (std::size_t i = 0; i < 8; ++i) {
                EXPECT_EQ(s.passes[i].pass, names[i % 4]);
                EXPECT_EQ(s.passes[i].eye, static_cast<int>(i / 4));
                EXPECT_GE(s.passes[i].ms, 0.0);
                sum += s.passes[i].ms;
            }
            EXPECT_LE(sum, s.frame_ms + 1e-6);  // the phases lie inside the frame
            EXPECT_GT(s.frame_ms, 0.0);
            EXPECT_EQ(r.last_gpu_ms(), s.frame_ms);
            // A frame without the occlusion has no entry for it: 3 timed parts per eye.
            SceneView plain = v;
            plain.occlusion_strength = 0.0;
            r.draw(plain, test::small_screen(), test::test_head(), kEyeSeparation);
            const FrameStats p = r.finish();
            ASSERT_EQ(p.passes.size(), 6u);
            const char* plain_names[3] = {"opaque", "translucent", "overlay"};
            for (std::size_t i = 0; i < 6; ++i) {
                EXPECT_EQ(p.passes[i].pass, plain_names[i % 3]);
                EXPECT_EQ(p.passes[i].eye, static_cast<int>(i / 3));
            }
            EXPECT_EQ(p.pass_ms("occlusion"), -1.0);
            std::printf("[timing] %s: frame %.3f ms, opaque %.3f, occlusion %.3f, translucent %.3f, overlay %.3f ms\n",
                        s.timing_note.c_str(), s.frame_ms, s.pass_ms("opaque"), s.pass_ms("occlusion"),
                        s.pass_ms("translucent"), s.pass_ms("overlay"));
        }
        // One layered render pass for both eyes: one entry per phase, eye -1.
        OffscreenStereoRenderer layered = OffscreenStereoRenderer::create(ctx, 96, 72, EyeStrategy::kInstancedLayer);
        if (layered.strategy() == EyeStrategy::kInstancedLayer && layered.gpu_timestamps_available()) {
            layered.draw(v, test::small_screen(), test::test_head(), kEyeSeparation);
            const FrameStats l = layered.finish();
            ASSERT_EQ(l.passes.size(), 4u);
            for (const PassTime& p : l.passes) EXPECT_EQ(p.eye, -1);
            EXPECT_EQ(l.passes[1].pass, "occlusion");
            EXPECT_EQ(l.passes[3].pass, "overlay");
        }
        r.set_gpu_timestamps(false);
        r.draw(v, test::small_screen(), test::test_head(), kEyeSeparation);
        const FrameStats c = r.finish();
        EXPECT_EQ(c.timing, TimingSource::kCpuClock);
        ASSERT_EQ(c.passes.size(), 1u);
        EXPECT_EQ(c.passes[0].pass, "frame");
        EXPECT_GT(c.frame_ms, 0.0);
        EXPECT_EQ(c.pass_ms("opaque"), -1.0);
        EXPECT_LT(r.last_gpu_ms(), 0.0);
        EXPECT_NE(c.timing_note.find("CPU"), std::string::npos);
        EXPECT_EQ(r.last_frame_stats().frame_ms, c.frame_ms);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

std::filesystem::path golden_path(const char* name) {
    const char* data = std::getenv("TRIDEX_TEST_DATA");
    return std::filesystem::path(data ? data : "tests/data") / "golden" / name;
}

TEST(SceneItems, GoldenFullScene) {
    gpu::Context ctx = gpu::Context::create({});
    {
        constexpr int kW = 320, kH = 240;
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
        const TriMesh cube = test::test_cube();  // flat shaded: 6 vertices per face
        std::vector<std::uint8_t> materials(cube.positions.size());
        for (std::size_t i = 0; i < materials.size(); ++i) materials[i] = static_cast<std::uint8_t>((i / 6) % 3);
        // Two tiles: a small painted box left of the cube (seen), one far outside the frustum (skipped).
        Aabb near_box, far_box;
        near_box.add(Vec3(-0.17, -0.1, -0.02));
        near_box.add(Vec3(-0.13, -0.06, 0.02));
        far_box.add(Vec3(2.0, 0.0, 0.0));
        far_box.add(Vec3(2.1, 0.1, 0.1));
        const TriMesh near_mesh = box_mesh(near_box), far_mesh = box_mesh(far_box);
        const std::vector<std::uint8_t> near_ids(8, 3);
        const std::vector<TileMesh> tiles = {{&near_mesh, near_box, 1, &near_ids}, {&far_mesh, far_box, 1}};
        SceneView v = test::test_scene(cube);
        v.workpiece_materials = &materials;
        v.tiles = tiles;
        v.proxy_m = v.tool_centre_m + Vec3(-0.012, -0.01, -0.01);
        v.proxy_radius_m = v.tool_radius_m;
        v.force_N = Vec3(-2.4, 1.2, 0.5);
        v.bubble_centre_m = Vec3(0.0, 0.0, 0.01);
        v.bubble_radius_m = 0.1;
        v.show_overlay = true;
        v.haptic_rate_hz = 1000.0;
        v.sculpt_rate_hz = 60.0;
        v.frame_time_ms = 16.7;  // fixed, so the image does not depend on timing
        const StereoImages eyes = r.render(v, test::small_screen(), test::test_head(), kEyeSeparation);
        EXPECT_EQ(eyes.stats.tiles[0].drawn, 1u);
        EXPECT_EQ(eyes.stats.tiles[0].skipped, 1u);
        const Image actual = side_by_side(eyes.left, eyes.right);
        const auto out = std::filesystem::current_path() / "renderer_out";
        std::filesystem::create_directories(out);
        write_png((out / "full_scene_actual.png").string(), actual);
        // Tolerance as for the other goldens: every channel within 3 (of 255) on at least 99.5 % of the pixels.
        const auto golden_file = golden_path("stereo_full_scene_320x240.png");
        ASSERT_TRUE(std::filesystem::exists(golden_file))
            << "missing golden " << golden_file << "; candidate written to " << out / "full_scene_actual.png";
        const ImageComparison c = compare_images(actual, read_png(golden_file.string()), 3);
        std::printf("[golden] full scene: %zu/%zu pixels within 3, max channel diff %d (strategy %s)\n", c.within,
                    c.pixels, c.max_channel_diff, std::string(to_string(r.strategy())).c_str());
        if (c.fraction_within() < 0.995) {
            write_png((out / "full_scene_diff.png").string(),
                      difference_image(actual, read_png(golden_file.string()), 3));
            ADD_FAILURE() << "golden mismatch: " << c.fraction_within() * 100.0 << " % within; see "
                          << out / "full_scene_diff.png";
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
