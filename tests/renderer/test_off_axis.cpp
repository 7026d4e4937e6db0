// Tests of renderer/camera/off_axis: Kooima off-axis frusta in Vulkan clip conventions, and eye positions.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "renderer/camera/off_axis.hpp"

namespace tridex::renderer {
namespace {

constexpr double kTol = 1e-12;  // double rounding of a few products on numbers of order 1

// Normalised device coordinates (x right, y down, depth) of a world point seen by `v`.
glm::dvec3 ndc(const EyeView& v, const Vec3& p) {
    const glm::dvec4 c = v.projection * v.view * glm::dvec4(p, 1.0);
    return glm::dvec3(c) / c.w;
}

void expect_corners_on_ndc_square(const Screen& s, const Vec3& eye) {
    const EyeView v = off_axis_view(s, eye, 0.05, 20.0);
    const Vec3 upper_right = s.lower_right + (s.upper_left - s.lower_left);
    const struct { Vec3 p; double x, y; } corners[4] = {
        {s.lower_left, -1.0, 1.0}, {s.lower_right, 1.0, 1.0}, {s.upper_left, -1.0, -1.0}, {upper_right, 1.0, -1.0}};
    for (const auto& c : corners) {
        const glm::dvec3 q = ndc(v, c.p);
        EXPECT_NEAR(q.x, c.x, kTol);
        EXPECT_NEAR(q.y, c.y, kTol);
        EXPECT_GT(q.z, 0.0);
        EXPECT_LT(q.z, 1.0);
    }
}

TEST(Screen, PowerwallIsTenBySevenAndAHalfFeet) {
    const Screen s = Screen::powerwall();
    EXPECT_NEAR(s.width(), 3.048, 1e-15);
    EXPECT_NEAR(s.height(), 2.286, 1e-15);
    EXPECT_EQ(s.lower_left, Vec3(-1.524, -1.143, 0.0));
    EXPECT_EQ(s.lower_right, Vec3(1.524, -1.143, 0.0));
    EXPECT_EQ(s.upper_left, Vec3(-1.524, 1.143, 0.0));
}

TEST(Screen, FittedToAnAspectKeepsItsCentreAndPlaneAndContainsItself) {
    const Screen s = Screen::desktop_monitor();  // 0.53 x 0.30 m
    const Screen wide = s.fitted_to_aspect(2.8);
    EXPECT_NEAR(wide.width() / wide.height(), 2.8, 1e-12);
    EXPECT_NEAR(wide.height(), s.height(), 1e-12);  // widened: the height is kept
    const Screen tall = s.fitted_to_aspect(1.0);
    EXPECT_NEAR(tall.width(), s.width(), 1e-12);    // heightened: the width is kept
    EXPECT_NEAR(tall.height(), s.width(), 1e-12);
    for (const Screen& f : {wide, tall}) {
        const Vec3 c0 = s.lower_left + 0.5 * (s.lower_right - s.lower_left) + 0.5 * (s.upper_left - s.lower_left);
        const Vec3 c1 = f.lower_left + 0.5 * (f.lower_right - f.lower_left) + 0.5 * (f.upper_left - f.lower_left);
        EXPECT_NEAR(glm::length(c1 - c0), 0.0, 1e-12);
        EXPECT_NEAR(f.lower_left.z, 0.0, 1e-12);  // the same plane
        EXPECT_NEAR(f.upper_left.z, 0.0, 1e-12);
    }
    // Bad aspects change nothing.
    EXPECT_EQ(s.fitted_to_aspect(0.0).lower_left, s.lower_left);
    EXPECT_EQ(s.fitted_to_aspect(std::numeric_limits<double>::quiet_NaN()).upper_left, s.upper_left);
}

TEST(OffAxis, CornersMapToNdcSquareForCentredEye) {
    expect_corners_on_ndc_square(Screen::powerwall(), Vec3(0.0, 0.0, 2.0));
}

TEST(OffAxis, CornersMapToNdcSquareForOffCentreEye) {
    expect_corners_on_ndc_square(Screen::powerwall(), Vec3(0.7, -0.4, 1.3));
    expect_corners_on_ndc_square(Screen::powerwall(), Vec3(-2.5, 1.9, 0.4));  // outside the screen's extent
}

TEST(OffAxis, CornersMapToNdcSquareForATiltedScreen) {
    // A 2 m x 1 m screen in the x = 1 plane facing -x (right = +z, up = +y, normal = z cross y = -x),
    // the eye near the origin in front of it.
    const Screen s{Vec3(1.0, -0.5, -1.0), Vec3(1.0, -0.5, 1.0), Vec3(1.0, 0.5, -1.0)};
    expect_corners_on_ndc_square(s, Vec3(0.1, 0.2, 0.3));
}

TEST(OffAxis, ProjectionMatchesHandComputedFrustum) {
    // Eye (0.7, -0.4, 1.3), PowerWall: d = 1.3; l, r = (-1.524 - 0.7, 1.524 - 0.7) n/d; b, t = (-1.143 + 0.4,
    // 1.143 + 0.4) n/d. Then P00 = 2n/(r-l) = 2d/W, P20 = (r+l)/(r-l) = -2*0.7/W, P11 = -2d/H,
    // P21 = -(t+b)/(t-b) = -2*0.4/H, P22 = f/(n-f), P32 = nf/(n-f), P23 = -1.
    const double n = 0.05, f = 20.0, d = 1.3, W = 3.048, H = 2.286;
    const EyeView v = off_axis_view(Screen::powerwall(), Vec3(0.7, -0.4, 1.3), n, f);
    EXPECT_NEAR(v.projection[0][0], 2.0 * d / W, kTol);
    EXPECT_NEAR(v.projection[2][0], -1.4 / W, kTol);
    EXPECT_NEAR(v.projection[1][1], -2.0 * d / H, kTol);
    EXPECT_NEAR(v.projection[2][1], -0.8 / H, kTol);
    EXPECT_NEAR(v.projection[2][2], f / (n - f), kTol);
    EXPECT_NEAR(v.projection[3][2], n * f / (n - f), kTol);
    EXPECT_EQ(v.projection[2][3], -1.0);
    EXPECT_EQ(v.projection[3][3], 0.0);
    // View: screen axes are the world axes here, so it is a pure translation by -eye.
    EXPECT_NEAR(v.view[3][0], -0.7, kTol);
    EXPECT_NEAR(v.view[3][1], 0.4, kTol);
    EXPECT_NEAR(v.view[3][2], -1.3, kTol);
    EXPECT_EQ(v.eye_m, Vec3(0.7, -0.4, 1.3));
}

TEST(OffAxis, DepthIsZeroAtNearAndOneAtFar) {
    const double n = 0.1, f = 10.0;
    const EyeView v = off_axis_view(Screen::powerwall(), Vec3(0.2, 0.1, 2.0), n, f);
    EXPECT_NEAR(ndc(v, Vec3(0.2, 0.1, 2.0 - n)).z, 0.0, kTol);
    EXPECT_NEAR(ndc(v, Vec3(0.2, 0.1, 2.0 - f)).z, 1.0, 1e-12);
    // At eye distance z: depth = f (z - n) / (z (f - n)); z = 1 m -> 10 * 0.9 / 9.9.
    EXPECT_NEAR(ndc(v, Vec3(0.2, 0.1, 2.0 - 1.0)).z, 9.0 / 9.9, kTol);
}

TEST(OffAxis, ScreenPlanePointsHaveZeroDisparity) {
    const Screen s = Screen::powerwall();
    const Pose head{Vec3(0.3, 0.2, 1.8), Quat(1.0, 0.0, 0.0, 0.0)};
    const auto eyes = eye_positions(head, 0.065);
    const EyeView l = off_axis_view(s, eyes[0], 0.05, 20.0);
    const EyeView r = off_axis_view(s, eyes[1], 0.05, 20.0);
    for (const Vec3& p : {Vec3(0.0), Vec3(0.4, -0.3, 0.0), Vec3(-1.2, 0.9, 0.0)}) {
        const glm::dvec3 a = ndc(l, p), b = ndc(r, p);
        EXPECT_NEAR(a.x, b.x, kTol);
        EXPECT_NEAR(a.y, b.y, kTol);
        // and both equal the point's own place on the screen
        EXPECT_NEAR(a.x, 2.0 * (p.x + 1.524) / 3.048 - 1.0, kTol);
        EXPECT_NEAR(a.y, -(2.0 * (p.y + 1.143) / 2.286 - 1.0), kTol);
    }
}

TEST(OffAxis, PointInFrontOfScreenHasCrossedDisparity) {
    // Eye at height y_e, distance D: a point p at z projects to the screen at e + (p - e) * D / (D - p.z).
    const Screen s = Screen::powerwall();
    const auto eyes = eye_positions(Pose{Vec3(0.0, 0.0, 2.0), Quat(1.0, 0.0, 0.0, 0.0)}, 0.064);
    const Vec3 p(0.1, 0.05, 0.5);
    double x_ndc[2];
    for (int e = 0; e < 2; ++e) {
        const EyeView v = off_axis_view(s, eyes[e], 0.05, 20.0);
        const double k = 2.0 / (2.0 - p.z);
        const Vec3 on_screen = eyes[e] + (p - eyes[e]) * k;
        const glm::dvec3 q = ndc(v, p);
        EXPECT_NEAR(q.x, 2.0 * (on_screen.x + 1.524) / 3.048 - 1.0, kTol);
        EXPECT_NEAR(q.y, -(2.0 * (on_screen.y + 1.143) / 2.286 - 1.0), kTol);
        x_ndc[e] = q.x;
    }
    // Crossed (negative) parallax: the left eye sees the point further right than the right eye does,
    // by separation * (k - 1) on the screen = 0.064 * 0.5 / 1.5 m.
    EXPECT_NEAR((x_ndc[0] - x_ndc[1]) * 3.048 / 2.0, 0.064 * (2.0 / 1.5 - 1.0), kTol);
}

TEST(OffAxis, RejectsBadInput) {
    const Screen s = Screen::powerwall();
    EXPECT_THROW(off_axis_view(s, Vec3(0.0, 0.0, 0.0), 0.05, 20.0), Error);   // on the plane
    EXPECT_THROW(off_axis_view(s, Vec3(0.0, 0.0, -1.0), 0.05, 20.0), Error);  // behind
    EXPECT_THROW(off_axis_view(s, Vec3(0.0, 0.0, 2.0), 0.0, 20.0), Error);
    EXPECT_THROW(off_axis_view(s, Vec3(0.0, 0.0, 2.0), 1.0, 1.0), Error);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(off_axis_view(s, Vec3(nan, 0.0, 2.0), 0.05, 20.0), Error);
    EXPECT_THROW(off_axis_view(Screen{}, Vec3(0.0, 0.0, 2.0), 0.05, 20.0), Error);  // degenerate
    const Screen skew{Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.5, 1.0, 0.0)};
    EXPECT_THROW(off_axis_view(skew, Vec3(0.0, 0.0, 2.0), 0.05, 20.0), Error);
}

TEST(EyePositions, SplitAlongHeadRightAxis) {
    const auto e = eye_positions(Pose{Vec3(0.0, 1.6, 2.0), Quat(1.0, 0.0, 0.0, 0.0)}, 0.065);
    EXPECT_EQ(e[0], Vec3(-0.0325, 1.6, 2.0));
    EXPECT_EQ(e[1], Vec3(0.0325, 1.6, 2.0));
    // Head turned 90 degrees to the left (about +y): its right axis +x becomes -z.
    const Quat turn = glm::angleAxis(std::acos(-1.0) / 2.0, Vec3(0.0, 1.0, 0.0));
    const auto t = eye_positions(Pose{Vec3(1.0, 1.6, 2.0), turn}, 0.06);
    EXPECT_NEAR(glm::length(t[0] - Vec3(1.0, 1.6, 2.03)), 0.0, 1e-15);
    EXPECT_NEAR(glm::length(t[1] - Vec3(1.0, 1.6, 1.97)), 0.0, 1e-15);
    const auto z = eye_positions(Pose{}, 0.0);
    EXPECT_EQ(z[0], z[1]);
    EXPECT_THROW(eye_positions(Pose{}, -0.01), Error);
    EXPECT_THROW(eye_positions(Pose{}, std::numeric_limits<double>::infinity()), Error);
}

}  // namespace
}  // namespace tridex::renderer
