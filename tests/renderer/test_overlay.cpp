// The 2D overlay: its text, the glyph quads (stb_easy_font), and that it lands on the same pixels in both eyes.
#include <gtest/gtest.h>

#include <limits>

#include "core/error.hpp"
#include "gpu/context.hpp"
#include "renderer/image/image_compare.hpp"
#include "renderer/scene/overlay_content.hpp"
#include "renderer/scene/overlay_text.hpp"
#include "renderer/stereo/stereo_renderer.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr double kEyeSeparation = 0.065;

TEST(Overlay, ContentLines) {
    OverlayNumbers n;
    n.haptic_rate_hz = 999.6;
    n.sculpt_rate_hz = 59.94;
    n.frame_ms = 16.66;
    EXPECT_EQ(overlay_content(n), "haptic 1000 Hz  sculpt 60 Hz\nframe 16.7 ms");
    n.has_tiles = true;
    n.tiles[0] = {120, 30};
    n.tiles[1] = {118, 32};
    EXPECT_EQ(overlay_content(n), "haptic 1000 Hz  sculpt 60 Hz\nframe 16.7 ms\n"
                                  "tiles L 120 drawn 30 skipped\ntiles R 118 drawn 32 skipped");
    OverlayNumbers unknown;
    unknown.sculpt_rate_hz = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(overlay_content(unknown), "haptic -- Hz  sculpt -- Hz\nframe -- ms");
}

TEST(Overlay, TextQuadsScaleAboutTheOriginAndStayInsideTheExtent) {
    const std::string text = "frame 16.7 ms\ntiles L 3";
    const TriMesh one = overlay_text_mesh(text, 0.0, 0.0, 1.0);
    const TriMesh two = overlay_text_mesh(text, 10.0, 20.0, 2.0);
    ASSERT_GT(one.triangles.size(), 20u);
    EXPECT_EQ(one.triangles.size() % 2, 0u);              // quads
    EXPECT_EQ(one.positions.size(), one.triangles.size() * 2);  // 4 vertices per 2 triangles
    ASSERT_EQ(two.positions.size(), one.positions.size());
    for (std::size_t i = 0; i < one.positions.size(); ++i) {
        EXPECT_EQ(two.positions[i], Vec3(10.0, 20.0, 0.0) + 2.0 * one.positions[i]) << i;
    }
    const TextExtent e1 = overlay_text_extent(text, 1.0), e2 = overlay_text_extent(text, 2.0);
    EXPECT_EQ(e2.width_px, 2.0 * e1.width_px);
    EXPECT_EQ(e2.height_px, 2.0 * e1.height_px);
    const Aabb b = one.bounds();
    EXPECT_GE(b.lo.x, 0.0);
    EXPECT_GE(b.lo.y, 0.0);
    EXPECT_LE(b.hi.x, e1.width_px);
    EXPECT_LE(b.hi.y, e1.height_px + 1.0);  // glyphs with descent sit one unit lower
    // Two lines: about 12 font units apart.
    EXPECT_GT(e1.height_px, 12.0);
    // Empty text, unprintable characters (drawn as spaces: no quads), bad scale.
    EXPECT_TRUE(overlay_text_mesh("", 0.0, 0.0, 1.0).triangles.empty());
    EXPECT_TRUE(overlay_text_mesh("\x01\x7f\xff", 0.0, 0.0, 1.0).triangles.empty());
    EXPECT_EQ(overlay_text_extent("\x01\x7f", 1.0).width_px, overlay_text_extent("  ", 1.0).width_px);
    EXPECT_THROW(overlay_text_mesh("a", 0.0, 0.0, 0.0), Error);
    EXPECT_THROW(overlay_text_mesh("a", std::numeric_limits<double>::infinity(), 0.0, 1.0), Error);
    EXPECT_THROW(overlay_text_extent("a", -1.0), Error);
    // The overlay's scale: a unit per 360 rows shown; in a smaller image scaled up, the same size shown while the
    // strokes stay a pixel wide.
    EXPECT_EQ(overlay_scale_for(540, 540), 1.0);
    EXPECT_EQ(overlay_scale_for(1080, 1080), 3.0);
    EXPECT_EQ(overlay_scale_for(810, 1080), 2.25);
    EXPECT_EQ(overlay_scale_for(405, 540), 1.0);
    EXPECT_EQ(overlay_scale_for(100, 200), 1.0);
    EXPECT_THROW(overlay_scale_for(0, 540), Error);
    EXPECT_THROW(overlay_scale_for(540, 0), Error);
    const TriMesh r = overlay_rectangle(1.0, 2.0, 5.0, 7.0);
    EXPECT_EQ(r.triangles.size(), 2u);
    EXPECT_EQ(r.bounds().lo, Vec3(1.0, 2.0, 0.0));
    EXPECT_EQ(r.bounds().hi, Vec3(5.0, 7.0, 0.0));
}

std::size_t bright_pixels(const Image& img, int x0, int y0, int x1, int y1) {
    std::size_t n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) n += img.at(x, y)[0] > 150 && img.at(x, y)[1] > 150 ? 1 : 0;
    return n;
}

TEST(Overlay, SamePixelsInBothEyesWhileOffPlaneObjectsDiffer) {
    gpu::Context ctx = gpu::Context::create({});
    {
        constexpr int kW = 200, kH = 120;
        OffscreenStereoRenderer r = OffscreenStereoRenderer::create(ctx, kW, kH);
        SceneView v;
        v.show_workspace = false;
        v.show_overlay = true;
        v.haptic_rate_hz = 1000.0;
        v.sculpt_rate_hz = 60.0;
        v.frame_time_ms = 12.5;
        v.overlay_scale = 1.0;
        // A ball 10 cm in front of the screen, lower right: different pixels in the two eyes.
        v.tool_centre_m = Vec3(0.1, -0.07, 0.1);
        v.tool_radius_m = 0.03;
        const StereoImages e = r.render(v, test::small_screen(), test::test_head(), kEyeSeparation);
        // The panel: margin 6 px, padding 3 px around the text extent.
        const TextExtent t = overlay_text_extent("haptic 1000 Hz  sculpt 60 Hz\nframe 12.5 ms", 1.0);
        const int x1 = static_cast<int>(9 + t.width_px), y1 = static_cast<int>(9 + t.height_px);
        std::size_t differing = 0;
        for (int y = 0; y < y1; ++y)
            for (int x = 0; x < x1; ++x)
                for (int c = 0; c < 4; ++c) differing += e.left.at(x, y)[c] != e.right.at(x, y)[c] ? 1 : 0;
        EXPECT_EQ(differing, 0u);
        EXPECT_GT(bright_pixels(e.left, 0, 0, x1, y1), 60u);  // text was drawn
        EXPECT_EQ(bright_pixels(e.left, x1 + 2, 0, kW, kH), 0u);
        const ImageComparison whole = compare_images(e.left, e.right, 0);
        EXPECT_GT(whole.pixels - whole.within, 50u);  // the ball differs between the eyes

        // Without the overlay the panel area is the clear colour.
        v.show_overlay = false;
        const StereoImages plain = r.render(v, test::small_screen(), test::test_head(), kEyeSeparation);
        EXPECT_EQ(bright_pixels(plain.left, 0, 0, x1, y1), 0u);
        EXPECT_EQ(plain.left.at(3, 3)[0], 20);  // clear colour red channel, round(0.08 * 255)
    }
    EXPECT_EQ(ctx.validation_messages(), 0u);
}

}  // namespace
}  // namespace tridex::renderer
