// A shared session's presence travels in the shared workpiece's model frame: a site whose workpiece is posed sends its
// tool and head with its pose undone, and a site draws the others through its own pose, so a tool touching a point of
// the model at one site is drawn at that point of the model at another, however differently each placed it.
#include <gtest/gtest.h>

#include <vector>

#include "app/session/view/presence_view.hpp"

namespace tridex::app {
namespace {

Vec3 translation(const glm::mat4& m) { return Vec3(m[3][0], m[3][1], m[3][2]); }

TEST(PresenceFrame, AToolOnAPointOfTheModelIsDrawnOnThatPointAtAnotherSite) {
    // Site A turned the bunny 90 degrees about y and moved it; site B left it where the lattice is.
    const Pose at_a{Vec3(0.05, -0.02, 0.1), glm::angleAxis(glm::radians(90.0), Vec3(0.0, 1.0, 0.0))};
    const Pose at_b{Vec3(-0.03, 0.0, 0.02), glm::angleAxis(glm::radians(-30.0), Vec3(1.0, 0.0, 0.0))};
    const Vec3 nose_model(0.031, 0.012, -0.004);  // a point of the model's surface
    FrameShown shown;
    shown.workpiece_pose = at_a;
    shown.proxy_m = at_a.apply(nose_model);  // A's tool rests there, in A's scene
    shown.tool_m = shown.proxy_m + Vec3(0.0, 0.003, 0.0);
    shown.tool.radius_m = 0.003;
    const SitePresence sent = presence_of(shown, 1, "Ann", Vec3(0.8, 0.2, 0.2));
    EXPECT_NEAR(glm::length(sent.tool.position - nose_model), 0.0, 1e-15);
    // B draws the ball at the nose of its own bunny; A's scene position would be 0.1 m off.
    PresenceView view;
    std::vector<renderer::SceneObject> objects;
    view.append({sent}, objects, Vec3(0.0, 0.0, 1.0), at_b);
    ASSERT_GE(objects.size(), 1u);
    const Vec3 drawn = translation(objects[0].world_from_model);
    EXPECT_NEAR(glm::length(drawn - at_b.apply(nose_model)), 0.0, 1e-6);  // the matrix is single precision
    EXPECT_GT(glm::length(drawn - shown.proxy_m), 0.05);
    // Unposed on both sides: drawn where it was, as before.
    FrameShown plain = shown;
    plain.workpiece_pose = Pose{};
    plain.proxy_m = nose_model;
    objects.clear();
    view.append({presence_of(plain, 1, "Ann", Vec3(0.5))}, objects, Vec3(0.0, 0.0, 1.0));
    EXPECT_NEAR(glm::length(translation(objects[0].world_from_model) - nose_model), 0.0, 1e-6);
}

}  // namespace
}  // namespace tridex::app
