// The pixel rectangle a world box covers (renderer/stereo/screen_region.hpp), which bounds where the ambient
// occlusion runs: it must hold every pixel the box's projection reaches, and fall back to the whole image when
// the box reaches the eye's plane.
#include <gtest/gtest.h>

#include "renderer/camera/off_axis.hpp"
#include "renderer/stereo/screen_region.hpp"
#include "test_scene.hpp"

namespace tridex::renderer {
namespace {

constexpr int kW = 400, kH = 300;  // 1000 pixels per metre on the 0.4 m x 0.3 m test screen

Mat4 clip_from_world(const Vec3& eye) {
    const EyeView v = off_axis_view(test::small_screen(), eye, 0.05, 20.0);
    return v.projection * v.view;
}

TEST(ScreenRegion, BoxOnTheScreenPlaneMapsToItsPixelsWidenedByOne) {
    // A box in the screen plane (z = 0) projects onto itself whatever the eye: 1000 px per metre, y down.
    const Aabb box{Vec3(-0.05, 0.0, 0.0), Vec3(0.05, 0.1, 0.0)};
    for (const Vec3& eye : {Vec3(0.0, 0.0, 0.5), Vec3(0.1, -0.05, 0.4)}) {
        const PixelRect r = project_box(clip_from_world(eye), box, kW, kH);
        EXPECT_NEAR(r.x0, 150 - 1, 1);
        EXPECT_NEAR(r.x1, 250 + 1, 1);
        EXPECT_NEAR(r.y0, 50 - 1, 1);   // y = 0.1 m is 0.05 m below the top edge
        EXPECT_NEAR(r.y1, 150 + 1, 1);  // y = 0 is the middle row
    }
}

TEST(ScreenRegion, NearerBoxesGrowAndOutsideOnesVanish) {
    const Mat4 m = clip_from_world(Vec3(0.0, 0.0, 0.5));
    const Aabb far{Vec3(-0.02, -0.02, -0.1), Vec3(0.02, 0.02, -0.1)};
    const Aabb near{Vec3(-0.02, -0.02, 0.2), Vec3(0.02, 0.02, 0.2)};
    const PixelRect rf = project_box(m, far, kW, kH), rn = project_box(m, near, kW, kH);
    EXPECT_LT(rf.x1 - rf.x0, rn.x1 - rn.x0);
    EXPECT_NEAR(0.5 * (rn.x0 + rn.x1), 200.0, 1.0);  // centred on the eye's line of sight
    // Wholly to the right of the image: empty; an empty box: empty.
    EXPECT_TRUE(project_box(m, Aabb{Vec3(1.0, 0.0, 0.0), Vec3(1.1, 0.1, 0.0)}, kW, kH).empty());
    EXPECT_TRUE(project_box(m, Aabb{}, kW, kH).empty());
    // Reaching the eye's plane (z = 0.5) or behind it: the whole image, as a projection cannot bound it.
    const PixelRect whole = project_box(m, Aabb{Vec3(-0.01, -0.01, 0.3), Vec3(0.01, 0.01, 0.6)}, kW, kH);
    EXPECT_EQ(whole.x0, 0);
    EXPECT_EQ(whole.y0, 0);
    EXPECT_EQ(whole.x1, kW);
    EXPECT_EQ(whole.y1, kH);
}

TEST(ScreenRegion, UniteIgnoresEmptyRectangles) {
    const PixelRect a{10, 20, 30, 40}, b{5, 25, 12, 50};
    const PixelRect u = unite(a, b);
    EXPECT_EQ(u.x0, 5);
    EXPECT_EQ(u.y0, 20);
    EXPECT_EQ(u.x1, 30);
    EXPECT_EQ(u.y1, 50);
    const PixelRect e = unite(PixelRect{}, a);
    EXPECT_EQ(e.x0, a.x0);
    EXPECT_EQ(e.y1, a.y1);
    EXPECT_TRUE(unite(PixelRect{}, PixelRect{}).empty());
}

}  // namespace
}  // namespace tridex::renderer
