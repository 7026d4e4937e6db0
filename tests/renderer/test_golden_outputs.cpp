// Golden images on lavapipe for every stereo output and for a head far off-centre, and the zero-disparity check:
// a point on the screen plane lands on the same pixel for both eyes, points off the plane where the off-axis
// projection (Kooima) predicts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "gpu/context.hpp"
#include "renderer/output/frame_sequencer.hpp"
#include "renderer/image/image.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/output/stereo_output.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr int kW = 96, kH = 72;
constexpr double kEyeSeparation = 0.065;
// Golden tolerance (as for the stereo golden): every channel within 3 (of 255) on at least 99.5 % of the pixels.
constexpr int kChannelTolerance = 3;
constexpr double kMinFractionWithin = 0.995;

std::filesystem::path output_dir() {
    const auto dir = std::filesystem::current_path() / "renderer_out" / "outputs";
    std::filesystem::create_directories(dir);
    return dir;
}

std::filesystem::path golden_dir() {
    const char* data = std::getenv("TRIDEX_TEST_DATA");
    return std::filesystem::path(data ? data : "tests/data") / "golden" / "outputs";
}

/// Compares `actual` with golden/outputs/<name>.png. Always writes <name>_actual.png to the output folder (the
/// candidate when a golden is missing), and <name>_diff.png when the comparison fails.
void expect_golden(const Image& actual, const std::string& name) {
    SCOPED_TRACE(name);
    const auto out = output_dir();
    const auto actual_file = out / (name + "_actual.png");
    write_png(actual_file.string(), actual);
    const auto golden_file = golden_dir() / (name + ".png");
    if (!std::filesystem::exists(golden_file)) {
        ADD_FAILURE() << "missing golden " << golden_file << "; candidate written to " << actual_file;
        return;
    }
    const Image golden = read_png(golden_file.string());
    if (golden.width != actual.width || golden.height != actual.height) {
        ADD_FAILURE() << "golden is " << golden.width << "x" << golden.height << ", image is " << actual.width << "x"
                      << actual.height << "; see " << actual_file;
        return;
    }
    const ImageComparison c = compare_images(actual, golden, kChannelTolerance);
    std::printf("[golden] %-44s %zu/%zu pixels within %d, max channel diff %d\n", name.c_str(), c.within, c.pixels,
                kChannelTolerance, c.max_channel_diff);
    if (c.fraction_within() < kMinFractionWithin) {
        const auto diff_file = out / (name + "_diff.png");
        write_png(diff_file.string(), difference_image(actual, golden, kChannelTolerance));
        ADD_FAILURE() << "golden mismatch: " << c.fraction_within() * 100.0 << " % within tolerance; see " << diff_file;
    }
}

/// A head far off-centre: 0.25 m right of, 0.1 m below the screen centre, 0.45 m out, turned 25 degrees to the left
/// (so the eyes are at different distances from the screen).
Pose off_centre_head() {
    const double deg = std::acos(-1.0) / 180.0;
    return Pose{Vec3(0.25, -0.1, 0.45), glm::angleAxis(25.0 * deg, Vec3(0.0, 1.0, 0.0))};
}

TEST(GoldenOutputs, EveryStereoOutputOfTheTestScene) {
    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
        const TriMesh cube = test::test_cube();
        const SceneView scene = test::test_scene(cube);
        const StereoImages eyes = r.render(scene, test::small_screen(), test::test_head(), kEyeSeparation);

        for (StereoOutput o : {StereoOutput::kSideBySide, StereoOutput::kSideBySideHalf, StereoOutput::kTopBottom,
                               StereoOutput::kTopBottomHalf, StereoOutput::kAnaglyph})
            expect_golden(compose(o, eyes.left, eyes.right), std::string(to_string(o)));
        for (AnaglyphMethod m : {AnaglyphMethod::kColour, AnaglyphMethod::kGray})
            expect_golden(compose(StereoOutput::kAnaglyph, eyes.left, eyes.right, {.anaglyph = m}),
                          "anaglyph-" + std::string(to_string(m)));
        // Quad: one image per swapchain layer.
        for (int layer = 0; layer < 2; ++layer)
            expect_golden(compose(StereoOutput::kQuad, eyes.left, eyes.right, {.eye_slot = layer}),
                          "quad-layer" + std::to_string(layer));
        // Frame-sequential: what presents 0 and 1 show; the sequence then repeats with period 2.
        FrameSequencer seq(120.0);
        std::vector<Image> presents;
        for (int n = 0; n < 4; ++n) {
            const int shutter = seq.shutter_for_present(seq.presents());
            const int eye = seq.present();
            const Image shown =
                compose(StereoOutput::kFrameSequential, eyes.left, eyes.right, {.eye_slot = shutter});
            EXPECT_EQ(shown.rgba, (eye == 0 ? eyes.left : eyes.right).rgba) << "present " << n;
            presents.push_back(shown);
        }
        expect_golden(presents[0], "frame-sequential-present0");
        expect_golden(presents[1], "frame-sequential-present1");
        EXPECT_EQ(presents[2].rgba, presents[0].rgba);
        EXPECT_EQ(presents[3].rgba, presents[1].rgba);

        // Mono: one view from the head centre (eye separation 0); only that image is used.
        const StereoImages centre = r.render(scene, test::small_screen(), test::test_head(), 0.0);
        EXPECT_EQ(centre.left.rgba, centre.right.rgba);
        const Image mono = compose(StereoOutput::kMono, centre.left, Image{});
        expect_golden(mono, "mono");
        // The mono view lies between the eyes: it differs from both.
        EXPECT_GT(compare_images(mono, eyes.left, 0).pixels - compare_images(mono, eyes.left, 0).within, 20u);
        EXPECT_GT(compare_images(mono, eyes.right, 0).pixels - compare_images(mono, eyes.right, 0).within, 20u);
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(GoldenOutputs, HeadFarOffCentre) {
    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
        const TriMesh cube = test::test_cube();
        const StereoImages eyes =
            r.render(test::test_scene(cube), test::small_screen(), off_centre_head(), kEyeSeparation);
        expect_golden(compose(StereoOutput::kSideBySide, eyes.left, eyes.right), "off-centre-side-by-side");
        expect_golden(compose(StereoOutput::kAnaglyph, eyes.left, eyes.right), "off-centre-anaglyph");
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

/// Centroid (pixel centres, x right, y down) of the pixels that differ from the clear colour; count in `n`.
glm::dvec2 centroid_of_drawn(const Image& img, std::size_t& n) {
    const std::uint8_t* clear = img.at(0, 0);  // the corners stay clear in these scenes
    const std::uint8_t c0 = clear[0], c1 = clear[1], c2 = clear[2];
    glm::dvec2 sum(0.0);
    n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const std::uint8_t* p = img.at(x, y);
            if (p[0] != c0 || p[1] != c1 || p[2] != c2) {
                sum += glm::dvec2(x + 0.5, y + 0.5);
                ++n;
            }
        }
    return n ? sum / static_cast<double>(n) : sum;
}

/// Where `p` appears on a width x height image of the z = 0 test screen seen from `eye` (Kooima: the off-axis
/// frustum maps the screen rectangle onto the image; p projects along the ray from the eye onto the plane).
glm::dvec2 expected_pixel(const Vec3& eye, const Vec3& p, int width, int height) {
    const Screen s = test::small_screen();
    const Vec3 on_plane = eye + (p - eye) * (eye.z / (eye.z - p.z));
    return glm::dvec2((on_plane.x - s.lower_left.x) / s.width() * width,
                      (s.upper_left.y - on_plane.y) / s.height() * height);
}

TEST(GoldenOutputs, ScreenPlanePointHasZeroDisparityOffPlanePointsDoNot) {
    constexpr int kBigW = 384, kBigH = 288;  // 960 pixels per metre on the 0.4 m x 0.3 m screen
    // Centroid tolerance: rasterising a rectangle moves each edge by < 0.5 px, so its centroid by < 0.5 px.
    constexpr double kCentroidTolerancePx = 0.5;
    gpu::Context ctx = gpu::Context::create({});
    {
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kBigW, kBigH);
        const Pose head = off_centre_head();
        const auto eyes_m = eye_positions(head, kEyeSeparation);
        const Vec3 centre(-0.03, 0.02, 0.0);
        for (double z : {0.0, 0.04, -0.04}) {
            SCOPED_TRACE("marker at z = " + std::to_string(z) + " m");
            // A flat, unlit 2 cm square (the workspace box squashed to zero depth) at depth z.
            SceneView v;
            v.workspace_m.add(centre + Vec3(-0.01, -0.01, z));
            v.workspace_m.add(centre + Vec3(0.01, 0.01, z));
            const StereoImages e = r.render(v, test::small_screen(), head, kEyeSeparation);
            std::size_t nl = 0, nr = 0;
            const glm::dvec2 cl = centroid_of_drawn(e.left, nl), cr = centroid_of_drawn(e.right, nr);
            EXPECT_GT(nl, 200u);
            EXPECT_GT(nr, 200u);
            const glm::dvec2 el = expected_pixel(eyes_m[0], centre + Vec3(0.0, 0.0, z), kBigW, kBigH);
            const glm::dvec2 er = expected_pixel(eyes_m[1], centre + Vec3(0.0, 0.0, z), kBigW, kBigH);
            std::printf("[disparity] z = %+.2f m: left centroid (%.3f, %.3f) expected (%.3f, %.3f); right (%.3f, %.3f) "
                        "expected (%.3f, %.3f); disparity %.3f px (expected %.3f)\n",
                        z, cl.x, cl.y, el.x, el.y, cr.x, cr.y, er.x, er.y, cr.x - cl.x, er.x - el.x);
            EXPECT_NEAR(cl.x, el.x, kCentroidTolerancePx);
            EXPECT_NEAR(cl.y, el.y, kCentroidTolerancePx);
            EXPECT_NEAR(cr.x, er.x, kCentroidTolerancePx);
            EXPECT_NEAR(cr.y, er.y, kCentroidTolerancePx);
            if (z == 0.0) {
                // On the screen plane both frusta meet: identical images, pixel for pixel.
                const ImageComparison c = compare_images(e.left, e.right, 0);
                EXPECT_EQ(c.within, c.pixels);
            } else {
                // In front of the screen crossed disparity (right image left of the left one), behind uncrossed.
                EXPECT_GT(std::abs(er.x - el.x), 4.0);
                EXPECT_EQ(cr.x - cl.x < 0.0, z > 0.0);
            }
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
