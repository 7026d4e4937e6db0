// Shading that shows shape: a groove and a ridge of the same size (semicircular, radius 1 cm) across a flat
// plate facing the viewer, rendered in every eye strategy and as a GPU anaglyph. The groove's floor must come
// out darker than its rims and the ridge's crest brighter than its feet, measured in the rendered pixels; with
// the ambient occlusion switched off the floor and the rims (all facing the viewer) are equally bright, which
// shows that the occlusion pass is what tells the two apart.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/tri_mesh.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/output/anaglyph_pass.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr int kW = 480, kH = 360;  // 1200 pixels per metre on the 0.4 m x 0.3 m test screen
constexpr double kRadius = 0.01;   // groove and ridge radius, m
constexpr double kGrooveY = 0.05, kRidgeY = -0.05;
constexpr double kPlateHalfX = 0.15, kPlateHalfY = 0.12;
constexpr double kRimGap = 0.003;  // where rims and feet are measured: this far outside the feature's edge, m

/// Height of the plate (z, m) at y: 0, minus a semicircle of kRadius around kGrooveY, plus one around kRidgeY.
double plate_z(double y) {
    const double g = std::abs(y - kGrooveY), r = std::abs(y - kRidgeY);
    if (g < kRadius) return -std::sqrt(kRadius * kRadius - g * g);
    if (r < kRadius) return std::sqrt(kRadius * kRadius - r * r);
    return 0.0;
}

/// The plate as a height field over x, y (a few columns along x, 0.25 mm rows along y), CCW seen from +z (the
/// renderer shades it with area-weighted vertex normals).
TriMesh groove_and_ridge_plate() {
    TriMesh m;
    constexpr int kCols = 8;
    constexpr double kStep = 0.00025;
    const int rows = static_cast<int>(std::lround(2.0 * kPlateHalfY / kStep));
    for (int j = 0; j <= rows; ++j) {
        const double y = -kPlateHalfY + j * kStep;
        for (int i = 0; i <= kCols; ++i)
            m.positions.emplace_back(-kPlateHalfX + 2.0 * kPlateHalfX * i / kCols, y, plate_z(y));
    }
    const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (kCols + 1) + i); };
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < kCols; ++i) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    return m;
}

/// Mean luma (Rec. 601, 0..255) of the pixels within 2 rows and 40 columns of where the plate point (x = 0, y,
/// plate_z(y)) appears from `eye` on the test screen (the plate does not change along x).
double luma_at(const Image& img, const Vec3& eye, double y) {
    const Screen s = test::small_screen();
    const Vec3 p(0.0, y, plate_z(y));
    const Vec3 on_plane = eye + (p - eye) * (eye.z / (eye.z - p.z));
    const int cx = static_cast<int>(std::lround((on_plane.x - s.lower_left.x) / s.width() * img.width));
    const int cy = static_cast<int>(std::floor((s.upper_left.y - on_plane.y) / s.height() * img.height));
    double sum = 0.0;
    int n = 0;
    for (int py = cy - 2; py <= cy + 2; ++py)
        for (int px = cx - 40; px <= cx + 40; ++px) {
            const std::uint8_t* c = &img.rgba[(static_cast<std::size_t>(py) * img.width + px) * 4];
            sum += 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2];
            ++n;
        }
    return sum / n;
}

struct Shape {
    double floor, rim_above, rim_below, crest, foot_above, foot_below;
};

Shape measure(const Image& img, const Vec3& eye) {
    const double edge = kRadius + kRimGap;
    return Shape{luma_at(img, eye, kGrooveY),        luma_at(img, eye, kGrooveY + edge),
                 luma_at(img, eye, kGrooveY - edge), luma_at(img, eye, kRidgeY),
                 luma_at(img, eye, kRidgeY + edge),  luma_at(img, eye, kRidgeY - edge)};
}

std::string describe(const Shape& s) {
    char b[200];
    std::snprintf(b, sizeof b, "groove floor %.1f, rims %.1f / %.1f; ridge crest %.1f, feet %.1f / %.1f", s.floor,
                  s.rim_above, s.rim_below, s.crest, s.foot_above, s.foot_below);
    return b;
}

// The margin (luma levels of 255) by which the floor must be darker than each rim and the crest brighter than
// each foot: far above rounding noise, well below what the occlusion gives.
constexpr double kMargin = 8.0;

void expect_shape_shown(const Shape& s) {
    SCOPED_TRACE(describe(s));
    EXPECT_LT(s.floor + kMargin, s.rim_above);
    EXPECT_LT(s.floor + kMargin, s.rim_below);
    EXPECT_GT(s.crest, s.foot_above + kMargin);
    EXPECT_GT(s.crest, s.foot_below + kMargin);
}

SceneView plate_scene(const TriMesh& plate) {
    SceneView v;
    v.workpiece = &plate;
    v.show_workspace = false;
    return v;
}

const Pose kHead{Vec3(0.0, 0.0, 0.5), Quat(1.0, 0.0, 0.0, 0.0)};
constexpr double kSeparation = 0.064;

TEST(ShapeShading, GrooveFloorDarkerThanRimRidgeCrestBrighterThanFootInEveryStrategy) {
    gpu::Context ctx = gpu::Context::create({});
    const TriMesh plate = groove_and_ridge_plate();
    const auto eyes = eye_positions(kHead, kSeparation);
    for (EyeStrategy strategy : {EyeStrategy::kPassPerEye, EyeStrategy::kInstancedLayer, EyeStrategy::kMultiview}) {
        SCOPED_TRACE(std::string(to_string(strategy)));
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH, strategy);
        std::printf("asked %s, drawing with %s\n", std::string(to_string(strategy)).c_str(),
                    std::string(to_string(r.strategy())).c_str());
        const StereoImages img = r.render(plate_scene(plate), test::small_screen(), kHead, kSeparation);
        const Shape left = measure(img.left, eyes[0]), right = measure(img.right, eyes[1]);
        std::printf("  left:  %s\n  right: %s\n", describe(left).c_str(), describe(right).c_str());
        expect_shape_shown(left);
        expect_shape_shown(right);
        if (strategy == EyeStrategy::kPassPerEye) {
            write_png("shape_shading_left.png", img.left);
            // Mono draws the one eye's work only and must shade it the same way.
            SceneView mono = plate_scene(plate);
            mono.eye_count = 1;
            const StereoImages one = r.render(mono, test::small_screen(), kHead, kSeparation);
            expect_shape_shown(measure(one.left, eyes[0]));
        }
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(ShapeShading, AnaglyphShowsTheSameShape) {
    gpu::Context ctx = gpu::Context::create({});
    const TriMesh plate = groove_and_ridge_plate();
    OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH, EyeStrategy::kPassPerEye);
    r.render(plate_scene(plate), test::small_screen(), kHead, kSeparation);
    AnaglyphPass pass = AnaglyphPass::create(ctx, kW, kH);
    const Image anaglyph = pass.compose(r, AnaglyphMethod::kGray, false);
    // Sampled where the head centre sees the plate: the eyes' images of it are at most 1.5 px apart.
    const Shape s = measure(anaglyph, kHead.position);
    std::printf("anaglyph: %s\n", describe(s).c_str());
    expect_shape_shown(s);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

// At quarter resolution (one value per 4x4 pixels) the occlusion still shows the groove and the ridge, in both eyes
// and in mono, and the picture stays close to the half-resolution one: the depth-aware upsampling keeps the
// silhouettes, only fine detail softens.
TEST(ShapeShading, QuarterResolutionShowsTheSameShape) {
    gpu::Context ctx = gpu::Context::create({});
    const TriMesh plate = groove_and_ridge_plate();
    const auto eyes = eye_positions(kHead, kSeparation);
    OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH, EyeStrategy::kPassPerEye);
    const StereoImages half = r.render(plate_scene(plate), test::small_screen(), kHead, kSeparation);
    SceneView v = plate_scene(plate);
    v.occlusion_resolution = OcclusionResolution::kQuarter;
    const StereoImages quarter = r.render(v, test::small_screen(), kHead, kSeparation);
    const Shape left = measure(quarter.left, eyes[0]), right = measure(quarter.right, eyes[1]);
    std::printf("quarter resolution left:  %s\n                   right: %s\n", describe(left).c_str(),
                describe(right).c_str());
    expect_shape_shown(left);
    expect_shape_shown(right);
    v.eye_count = 1;
    expect_shape_shown(measure(r.render(v, test::small_screen(), kHead, kSeparation).left, eyes[0]));
    for (const auto& [a, b] : {std::pair{&half.left, &quarter.left}, std::pair{&half.right, &quarter.right}}) {
        const ImageComparison c = compare_images(*a, *b, 24);
        std::printf("quarter vs half: %.3f %% of pixels within 24 levels, max diff %d\n", 100.0 * c.fraction_within(),
                    c.max_channel_diff);
        EXPECT_GT(c.max_channel_diff, 0);  // it is evaluated differently
        EXPECT_GE(c.fraction_within(), 0.99);
    }
    write_png("shape_shading_quarter_left.png", quarter.left);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(ShapeShading, WithoutOcclusionFloorAndRimLookAlike) {
    gpu::Context ctx = gpu::Context::create({});
    const TriMesh plate = groove_and_ridge_plate();
    OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH, EyeStrategy::kPassPerEye);
    SceneView v = plate_scene(plate);
    v.occlusion_strength = 0.0;
    const StereoImages img = r.render(v, test::small_screen(), kHead, kSeparation);
    const Shape s = measure(img.left, eye_positions(kHead, kSeparation)[0]);
    std::printf("no occlusion: %s\n", describe(s).c_str());
    // Floor, rims, crest and feet all face the viewer: the lights alone shade them nearly alike, and the checks
    // of expect_shape_shown() fail.
    EXPECT_FALSE(s.floor + kMargin < s.rim_above);
    EXPECT_FALSE(s.floor + kMargin < s.rim_below);
    EXPECT_FALSE(s.crest > s.foot_above + kMargin);
    EXPECT_FALSE(s.crest > s.foot_below + kMargin);
    SceneView bad = plate_scene(plate);
    bad.occlusion_radius_m = -1.0;
    EXPECT_THROW(r.render(bad, test::small_screen(), kHead, kSeparation), Error);
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
