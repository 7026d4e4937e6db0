// Tests of SceneNavigation (the Wand): translate, rotate and scale about a pivot, wand drag, mouse gains.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/camera/scene_navigation.hpp"

namespace tridex::renderer {
namespace {

const double kPi = std::acos(-1.0);
constexpr double kTol = 1e-12;

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

Vec3 apply(const Mat4& m, const Vec3& p) { return Vec3(m * glm::dvec4(p, 1.0)); }

TEST(SceneNavigation, StartsAtItsPoseAndScaleAndMatricesAgree) {
    const Pose start{Vec3(0.1, 0.2, -0.3), glm::angleAxis(0.7, glm::normalize(Vec3(1.0, 2.0, 3.0)))};
    SceneNavigation nav(start, 2.0);
    const Vec3 p(0.01, -0.02, 0.03);
    expect_vec(nav.to_world(p), start.apply(2.0 * p), kTol);
    expect_vec(apply(nav.world_from_scene(), p), nav.to_world(p), kTol);
    expect_vec(nav.to_scene(nav.to_world(p)), p, kTol);
    expect_vec(apply(nav.scene_from_world(), nav.to_world(p)), p, kTol);
    const Mat4 id = nav.scene_from_world() * nav.world_from_scene();
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(id[c][r], c == r ? 1.0 : 0.0, kTol);
}

TEST(SceneNavigation, RotateAndScaleKeepThePivotFixed) {
    SceneNavigation nav;
    const Vec3 pivot(0.5, 0.0, 0.0);
    nav.rotate(Vec3(0.0, 0.0, 2.0), kPi / 2, pivot);  // axis normalised
    expect_vec(nav.to_world(pivot), pivot, kTol);
    expect_vec(nav.to_world(Vec3(1.5, 0.0, 0.0)), Vec3(0.5, 1.0, 0.0), kTol);  // 1 m along x turns to +y
    const double applied = nav.scale(3.0, pivot);
    EXPECT_DOUBLE_EQ(applied, 3.0);
    EXPECT_DOUBLE_EQ(nav.scale(), 3.0);
    expect_vec(nav.to_world(pivot), pivot, kTol);
    expect_vec(nav.to_world(Vec3(1.5, 0.0, 0.0)), Vec3(0.5, 3.0, 0.0), kTol);
    nav.translate(Vec3(0.0, 0.0, -1.0));
    expect_vec(nav.to_world(pivot), Vec3(0.5, 0.0, -1.0), kTol);
    nav.reset();
    expect_vec(nav.to_world(Vec3(1.5, 0.0, 0.0)), Vec3(1.5, 0.0, 0.0), 0.0);
}

TEST(SceneNavigation, ScaleIsClampedToItsLimits) {
    SceneNavigation nav(Pose{}, 1.0, 0.5, 4.0);
    const Vec3 pivot(0.0, 1.0, 0.0);
    EXPECT_DOUBLE_EQ(nav.scale(10.0, pivot), 4.0);
    EXPECT_DOUBLE_EQ(nav.scale(), 4.0);
    EXPECT_DOUBLE_EQ(nav.scale(1e-6, pivot), 0.125);
    EXPECT_DOUBLE_EQ(nav.scale(), 0.5);
    expect_vec(nav.to_world(pivot), pivot, kTol);
    EXPECT_THROW(nav.scale(0.0, pivot), Error);
    EXPECT_THROW(nav.scale(-2.0, pivot), Error);
    EXPECT_THROW(SceneNavigation(Pose{}, 5.0, 0.5, 4.0), Error);
    EXPECT_THROW(SceneNavigation(Pose{}, 1.0, 2.0, 1.5), Error);
}

TEST(SceneNavigation, WandDragCarriesTheSceneRigidly) {
    SceneNavigation nav(Pose{}, 2.0);
    const Pose before{Vec3(0.2, 1.0, 0.5), glm::angleAxis(0.3, Vec3(1.0, 0.0, 0.0))};
    const Pose after{Vec3(-0.1, 1.2, 0.4), glm::angleAxis(1.1, glm::normalize(Vec3(0.0, 1.0, 1.0)))};
    // A scene point held at a fixed place in the wand's frame stays there.
    const Vec3 in_wand(0.05, -0.02, -0.3);
    const Vec3 scene_point = nav.to_scene(before.apply(in_wand));
    nav.wand_drag(before, after);
    expect_vec(nav.to_world(scene_point), after.apply(in_wand), kTol);
    EXPECT_DOUBLE_EQ(nav.scale(), 2.0);
    EXPECT_THROW(nav.wand_drag(before, Pose{Vec3(0.0), Quat(0.0, 0.0, 0.0, 0.0)}), Error);
    EXPECT_THROW(nav.translate(Vec3(std::nan(""))), Error);
    EXPECT_THROW(nav.rotate(Vec3(0.0), 1.0, Vec3(0.0)), Error);
}

TEST(SceneNavigation, MouseDragsFollowTheScreenAxes) {
    const Screen screen = Screen::desktop_monitor();
    const MouseNavigation mouse = MouseNavigation::for_screen(screen, 1060);  // 0.5 mm per pixel
    EXPECT_DOUBLE_EQ(mouse.metres_per_pixel, 0.53 / 1060);
    expect_vec(mouse.pivot_m, Vec3(0.0), kTol);
    SceneNavigation nav;
    mouse_pan(nav, mouse, 100.0, 40.0);  // right 100 px, down 40 px
    expect_vec(nav.to_world(Vec3(0.0)), Vec3(0.05, -0.02, 0.0), kTol);
    nav.reset();
    // Drag right by pi/2 worth of pixels: the scene's front (+z) turns to the right (+x).
    mouse_orbit(nav, mouse, (kPi / 2) / mouse.radians_per_pixel, 0.0);
    expect_vec(nav.to_world(Vec3(0.0, 0.0, 0.1)), Vec3(0.1, 0.0, 0.0), kTol);
    nav.reset();
    // Drag down: the top (+y) tips towards the viewer (+z).
    mouse_orbit(nav, mouse, 0.0, (kPi / 2) / mouse.radians_per_pixel);
    expect_vec(nav.to_world(Vec3(0.0, 0.1, 0.0)), Vec3(0.0, 0.0, 0.1), kTol);
    nav.reset();
    EXPECT_NEAR(mouse_zoom(nav, mouse, 2.0), 1.21, kTol);
    EXPECT_NEAR(nav.scale(), 1.21, kTol);
    EXPECT_THROW(mouse_pan(nav, mouse, std::nan(""), 0.0), Error);
    EXPECT_THROW(MouseNavigation::for_screen(Screen{}, 100), Error);
}

}  // namespace
}  // namespace tridex::renderer
