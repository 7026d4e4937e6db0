// A rigid reference object is felt through its signed distance field: the penetration of the tool's points along the
// field's gradient, turned by the object's pose; nothing outside its grid or for a bad pose; the haptic loop adds its
// force beside the workpiece's, caps its stiffness and checks it.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include "core/error.hpp"
#include "haptics/haptic_loop.hpp"
#include "haptics/reference_object.hpp"
#include "loop_fixture.hpp"

namespace tridex::haptics {
namespace {

// The exact signed distance of a ball of radius r about the grid's frame origin, on a 1 mm grid 30 mm each side.
std::shared_ptr<const DistanceGrid> ball_field(double r) {
    auto g = std::make_shared<DistanceGrid>();
    g->cell_m = 0.001;
    g->origin_m = Vec3(-0.03);
    g->nodes = {61, 61, 61};
    g->distance_m.resize(61 * 61 * 61);
    for (int k = 0; k < 61; ++k)
        for (int j = 0; j < 61; ++j)
            for (int i = 0; i < 61; ++i)
                g->distance_m[g->index(i, j, k)] =
                    static_cast<float>(glm::length(g->origin_m + g->cell_m * Vec3(i, j, k)) - r);
    return g;
}

ReferenceObject ball_object(const Vec3& at, double r = 0.02) {
    ReferenceObject o;
    o.grid = ball_field(r);
    o.pose.position = at;
    o.stiffness_n_per_m = 500.0;
    return o;
}

TEST(ReferenceObject, APointIsPushedOutAlongTheFieldsGradientTurnedByThePose) {
    const ReferenceObject o = ball_object(Vec3(0.1, 0.0, 0.0));
    const ToolPoints ball = ToolPoints::single(0.004);
    Pose tool;
    tool.position = Vec3(0.1, 0.0225, 0.0);  // 22.5 mm above the centre: the 4 mm ball reaches 1.5 mm in
    const ElasticContacts c = reference_contacts(o, ball, tool);
    ASSERT_EQ(c.count, 1);
    EXPECT_NEAR(c.contact[0].depth_m, 0.0015, 2e-5);  // the trilinear field of a sphere, 1 mm cells
    EXPECT_NEAR(c.contact[0].normal.y, 1.0, 1e-3);
    EXPECT_NEAR(c.contact[0].surface_m.y, 0.02, 2e-5);
    const Vec3 f = penetration_force(o.stiffness_n_per_m, c, 10.0);
    EXPECT_NEAR(f.y, 500.0 * 0.0015, 0.02);
    // Capped at the device's limit.
    EXPECT_NEAR(glm::length(penetration_force(o.stiffness_n_per_m, c, 0.3)), 0.3, 1e-12);
    // A box field turned a quarter about z: its local +x face now faces +y.
    auto slab = std::make_shared<DistanceGrid>();
    slab->cell_m = 0.002;
    slab->origin_m = Vec3(-0.02);
    slab->nodes = {21, 21, 21};
    slab->distance_m.resize(21 * 21 * 21);
    for (int k = 0; k < 21; ++k)
        for (int j = 0; j < 21; ++j)
            for (int i = 0; i < 21; ++i) slab->distance_m[slab->index(i, j, k)] = static_cast<float>(-0.02 + 0.002 * i - 0.01);
    ReferenceObject turned;
    turned.grid = slab;
    turned.pose.orientation = glm::angleAxis(glm::radians(90.0), Vec3(0.0, 0.0, 1.0));
    tool.position = Vec3(0.0, 0.012, 0.0);  // local x = 0.012: 2 mm above the face at x = 0.01, the ball 4 mm
    const ElasticContacts t = reference_contacts(turned, ball, tool);
    ASSERT_EQ(t.count, 1);
    EXPECT_NEAR(t.contact[0].depth_m, 0.002, 1e-6);
    EXPECT_NEAR(t.contact[0].normal.y, 1.0, 1e-9);
    EXPECT_NEAR(t.contact[0].normal.x, 0.0, 1e-9);
}

TEST(ReferenceObject, NothingOutsideItsGridForAFreeToolOrABadPose) {
    const ReferenceObject o = ball_object(Vec3(0.0));
    const ToolPoints ball = ToolPoints::single(0.004);
    Pose tool;
    tool.position = Vec3(0.0, 0.05, 0.0);  // beyond the grid's 30 mm
    EXPECT_EQ(reference_contacts(o, ball, tool).count, 0);
    tool.position = Vec3(0.0, 0.025, 0.0);  // inside the grid, 1 mm clear of the ball
    EXPECT_EQ(reference_contacts(o, ball, tool).count, 0);
    tool.position = Vec3(std::nan(""), 0.0, 0.0);
    EXPECT_EQ(reference_contacts(o, ball, tool).count, 0);
    tool.position = Vec3(0.0);
    tool.orientation.w = std::nan("");
    EXPECT_EQ(reference_contacts(o, ball, tool).count, 0);
    ReferenceObject empty;
    EXPECT_EQ(reference_contacts(empty, ball, Pose{}).count, 0);
}

TEST(ReferenceObject, TheLoopFeelsItCapsItsStiffnessAndChecksIt) {
    TripleBuffer<ActiveSurface> surface;  // no workpiece snapshot: only the reference is felt
    SpscRing<ToolSample> ring(4096);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg;
    cfg.contact = ContactParams{700.0, 0.0, 0.004};
    cfg.op = ToolOp::kNone;
    cfg.workspace.mode = WorkspaceMode::kScaling;
    cfg.ewma_alpha = 0.0;
    cfg.safety.ramp_s = 0.0;
    cfg.request_realtime = false;
    const Vec3 centre(0.0, 0.0, 0.05);
    cfg.reference_objects.push_back(ball_object(centre));
    {
        HapticLoop loop(dev, surface, ring, cfg);
        dev.state.pose.position = Vec3(0.0);
        const TickRecord first = loop.step(0.0);
        const Vec3 target = centre + Vec3(0.0, 0.0225, 0.0);
        dev.state.pose.position += target - first.hip_m;
        TickRecord r;
        for (int t = 1; t < 5; ++t) r = loop.step(t * 1e-3);
        EXPECT_TRUE(r.contact);
        EXPECT_NEAR(r.force_n.y, 500.0 * 0.0015, 0.02);
        EXPECT_NEAR(r.object_force_n.y, r.force_n.y, 1e-12);
        dev.state.pose.position.y += 0.01;
        for (int t = 5; t < 10; ++t) r = loop.step(t * 1e-3);
        EXPECT_FALSE(r.contact);
        EXPECT_EQ(glm::length(r.force_n), 0.0);
    }
    HapticLoopConfig stiff = cfg;
    stiff.reference_objects[0].stiffness_n_per_m = 1e5;
    {
        HapticLoop loop(dev, surface, ring, stiff);
        EXPECT_TRUE(loop.stiffness_capped());
        EXPECT_LE(loop.config().reference_objects[0].stiffness_n_per_m, dev.profile().max_stiffness_n_per_m);
    }
    HapticLoopConfig bad = cfg;
    bad.reference_objects[0].pose.orientation = Quat(2.0, 0.0, 0.0, 0.0);
    try {
        HapticLoop loop(dev, surface, ring, bad);
        FAIL() << "a quaternion of length 2 was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("reference_objects[0]: field 'pose'"), std::string::npos) << e.what();
    }
    bad = cfg;
    bad.reference_objects[0].grid = nullptr;
    EXPECT_THROW(HapticLoop(dev, surface, ring, bad), Error);
    HapticLoopConfig many = cfg;
    many.reference_objects.assign(kMaxReferenceObjects + 1, ball_object(centre));
    EXPECT_THROW(HapticLoop(dev, surface, ring, many), Error);
}

}  // namespace
}  // namespace tridex::haptics
