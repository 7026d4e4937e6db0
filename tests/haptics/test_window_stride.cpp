// Tests of the strided active-surface window: at N=1024 on a 0.3 m workpiece (cell 0.29 mm) a
// window of ActiveSurface::kWindow rays at stride 1 spans only ~9 mm; sized by the tool's extent it must
// let a 10 mm ball's edge points and a +-30 mm wand's points find contact, and on a smooth shape give the
// same contact as stride 1 within a stated bound.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "haptics/god_object.hpp"
#include "haptics/multipoint.hpp"
#include "haptics/tool_points.hpp"
#include "surfaces.hpp"

namespace tridex::haptics {
namespace {

using test::ball_rays;
using test::half_space_rays;
using test::published_surface;

constexpr double kH = 0.3 / 1024.0;  // cell at N=1024 on the 0.3 m bench stock, m
constexpr int kNodes = 1025;
constexpr double kMargin = 0.003;    // motion margin the publisher adds by default, m
constexpr double kDt = 1e-3;
const Vec3 kCentre(0.15, 0.15, 0.15);  // the tool's start (window centre), m

// Reach (m) a window must cover for a tool: its points' distance + ball radius + the motion margin.
double reach_of(const ToolPoints& tool) { return max_point_distance_m(tool) + tool.radius_m + kMargin; }

// Moves the tool from `from` to `to` (tool centre, m; orientation q) in `steps` ticks; returns the last result.
const MultiPointResult& press(MultiPointRenderer& r, const ActiveSurface& s, const Vec3& from, const Vec3& to,
                              const Quat& q, int steps) {
    const MultiPointResult* last = nullptr;
    for (int i = 0; i <= steps; ++i) last = &r.update(s, Pose{from + (to - from) * (double(i) / steps), q}, kDt);
    return *last;
}

TEST(WindowStride, StrideCoversTheToolExtent) {
    EXPECT_EQ(ActiveSurface::stride_for(0.0, kH), 1);
    EXPECT_EQ(ActiveSurface::stride_for(ActiveSurface::kCoverRays * kH, kH), 1);
    EXPECT_EQ(ActiveSurface::stride_for(ActiveSurface::kCoverRays * kH * 1.001, kH), 2);
    // 10 mm ball + 3 mm margin at 0.29 mm cells: 13 mm / (14.5 x 0.29 mm) = 3.06 -> 4.
    EXPECT_EQ(ActiveSurface::stride_for(0.013, kH), 4);
    EXPECT_EQ(ActiveSurface::stride_for(0.013, 0.3 / 128.0), 1);  // coarse lattice: every ray
    for (double reach : {0.004, 0.013, 0.033, 0.1}) {
        const int s = ActiveSurface::stride_for(reach, kH);
        EXPECT_GE(ActiveSurface::kCoverRays * s * kH, reach);
        EXPECT_LT(ActiveSurface::kCoverRays * (s - 1) * kH, reach);
        // Every point within reach of any centre projects inside the placed window.
        for (double g : {400.3, 512.0, 512.5, 600.77}) {
            int count = 0;
            const int first = ActiveSurface::window_first(g, kNodes, s, count);
            EXPECT_EQ(first % s, 0);
            EXPECT_EQ(count, ActiveSurface::kWindow);
            EXPECT_LE(first, g - reach / kH);
            EXPECT_GE(first + s * (count - 1), g + reach / kH);
        }
    }
}

TEST(WindowStride, WindowConversionsRoundTrip) {
    const ToolPoints wand = ToolPoints::wand(0.03);
    auto s = published_surface(kH, kNodes, kCentre, reach_of(wand), half_space_rays(Vec3(0, 0, 1), 0.15, kH, kNodes));
    const int stride = s->sets[2].stride;
    EXPECT_EQ(stride, ActiveSurface::stride_for(0.033, kH));
    EXPECT_GT(stride, 1);
    for (int a = 0; a < 3; ++a) {
        const Vec3 p = s->window_point(a, 7, 11, 512.25);
        const ActiveSurface::WindowCoord c = s->to_window(a, p);
        EXPECT_NEAR(c.fu, 7.0, 1e-9);
        EXPECT_NEAR(c.fv, 11.0, 1e-9);
        EXPECT_NEAR(c.d, 512.25, 1e-9);
        const std::array<int, 2> uv = s->lattice_ray(a, 7, 11);
        EXPECT_EQ(uv[0], s->sets[a].u0 + 7 * stride);
        EXPECT_EQ(uv[1], s->sets[a].v0 + 11 * stride);
    }
}

// A 64-point interaction mesh on a 10 mm ball pressed 1.5 mm into a plane whose normal (1,1,1)/sqrt 3 is
// oblique to every ray set: the points that touch lie ~5.8 mm from the centre along each axis, outside a
// stride-1 window (+-4.2 mm), so this fails without the stride. Every point more than 0.1 mm inside the
// plane must be in contact, with its depth within 0.05 mm of the exact one (a plane is exact on dexels).
TEST(WindowStride, BallEdgePointsTenMillimetresOutFindContactAtN1024) {
    const ToolPoints ball = ToolPoints::sphere_mesh(0.010, 64);
    const Vec3 n = glm::normalize(Vec3(1.0, 1.0, 1.0));
    const double c = glm::dot(n, kCentre) - 0.0085;  // plane 8.5 mm below the centre along n
    auto s = published_surface(kH, kNodes, kCentre, reach_of(ball), half_space_rays(n, c, kH, kNodes));
    MultiPointRenderer r(ball, ContactParams{});
    const Quat q(1.0, 0.0, 0.0, 0.0);
    const MultiPointResult& res = press(r, *s, kCentre + 0.003 * n, kCentre, q, 60);
    int touching = 0;
    for (int i = 0; i < res.points; ++i) {
        const double depth = c - glm::dot(n, res.point[i].world_m);  // exact penetration, m
        if (depth > 1e-4) {
            ++touching;
            EXPECT_TRUE(res.point[i].contact) << "point " << i << " depth " << depth;
            EXPECT_NEAR(res.point[i].depth_m, depth, 5e-5) << "point " << i;
        }
        if (depth < -1e-4) {
            EXPECT_FALSE(res.point[i].contact) << "point " << i << " depth " << depth;
        }
    }
    EXPECT_GE(touching, 2);
    EXPECT_GE(res.in_contact, touching);  // points within 0.1 mm of the plane may touch or not
}

// The 5-DOF wand (points at +-30 mm along the tool's y, yawed 45 degrees) lowered 1 mm into a horizontal
// floor at N=1024: both points must touch with depth 1 mm. At stride 1 neither point projects inside any
// window.
TEST(WindowStride, WandPointsThirtyMillimetresOutAllInContactAtN1024) {
    const ToolPoints wand = ToolPoints::wand(0.03);
    const double floor_z = kCentre.z;
    auto s = published_surface(kH, kNodes, kCentre, reach_of(wand),
                               half_space_rays(Vec3(0, 0, 1), floor_z, kH, kNodes));
    MultiPointRenderer r(wand, ContactParams{});
    // Yawed 45 degrees: the points lie 21 mm out along both x and y, outside every stride-1 window.
    const Quat yaw45 = rotation_from_axis_angle(Vec3(0, 0, 1), M_PI / 4);
    const MultiPointResult& res =
        press(r, *s, kCentre + Vec3(0, 0, 0.002), kCentre - Vec3(0, 0, 0.001), yaw45, 30);
    ASSERT_EQ(res.points, 2);
    EXPECT_EQ(res.in_contact, 2);
    for (int i = 0; i < 2; ++i) {
        EXPECT_TRUE(res.point[i].contact) << "point " << i;
        EXPECT_NEAR(res.point[i].depth_m, 0.001, 1e-6) << "point " << i;
        EXPECT_NEAR(res.point[i].proxy_m.z, floor_z, 1e-6) << "point " << i;
        EXPECT_NEAR(res.point[i].normal.z, 1.0, 1e-9) << "point " << i;
    }
    // Spring 700 N/m x 1 mm plus damping 0.5 N*s/m x 0.1 m/s per point.
    EXPECT_NEAR(res.wrench.force_n.z, 2 * (700.0 * 0.001 + 0.5 * 0.1), 1e-6);
}

// Same contact at stride 1 and at a strided window on a smooth shape: a 2 mm ball (inside a stride-1
// window with its motion) pressed along an oblique
// direction into a 20 mm sphere. Bound: strided and stride-1 force-shaded normals within 1 degree of each
// other (each within 3 degrees of the exact normal), depths within 0.03 mm (a tenth of a lattice cell; the
// exact depth is 1 mm), proxies within 0.05 mm.
TEST(WindowStride, StridedWindowMatchesStrideOneOnASphere) {
    const Vec3 sphere_c = kCentre;
    const double R = 0.020, r_ball = 0.002;
    const Vec3 d = glm::normalize(Vec3(0.3, 0.5, 0.81));
    const Vec3 start = sphere_c + (R + r_ball + 0.002) * d, end = sphere_c + (R + r_ball - 0.001) * d;
    ContactResult res[2];
    int strides[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        const double reach = k == 0 ? 0.0 : 0.013;  // stride 1, then the 10 mm ball's stride (4)
        auto s = published_surface(kH, kNodes, end, reach, ball_rays(sphere_c, R, kH));
        strides[k] = s->sets[2].stride;
        ContactParams p;
        p.tool_radius_m = r_ball;
        GodObject g(p);
        for (int i = 0; i <= 40; ++i) res[k] = g.update(*s, start + (end - start) * (i / 40.0), kDt);
    }
    EXPECT_EQ(strides[0], 1);
    EXPECT_EQ(strides[1], 4);
    for (const ContactResult& c : res) {
        ASSERT_TRUE(c.contact);
        EXPECT_NEAR(c.depth_m, 0.001, 3e-5);
        EXPECT_GT(glm::dot(c.normal, d), std::cos(3.0 * M_PI / 180.0));
    }
    EXPECT_GT(glm::dot(res[0].normal, res[1].normal), std::cos(1.0 * M_PI / 180.0));
    EXPECT_NEAR(res[0].depth_m, res[1].depth_m, 3e-5);
    EXPECT_LT(glm::length(res[0].proxy_m - res[1].proxy_m), 5e-5);
}

}  // namespace
}  // namespace tridex::haptics
