// The haptic loop feels a scene's elastic spheres beside the workpiece: the force of the tool's contact points
// against each undeformed sphere, capped like the contact, and nothing once the tool leaves them.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "haptics/elastic_object.hpp"
#include "haptics/haptic_loop.hpp"
#include "loop_fixture.hpp"

namespace tridex::haptics {
namespace {

HapticLoopConfig ball_config(double radius_m) {
    HapticLoopConfig cfg;
    cfg.contact = ContactParams{700.0, 0.0, radius_m};
    cfg.op = ToolOp::kNone;
    cfg.workspace.mode = WorkspaceMode::kScaling;
    cfg.ewma_alpha = 0.0;         // no filter: the tick's force is the contact's
    cfg.safety.ramp_s = 0.0;      // full force from the first tick
    cfg.request_realtime = false;
    return cfg;
}

ElasticSphere ball_at(const Vec3& centre) {
    ElasticSphere e;
    e.centre_m = centre;
    e.radius_m = 0.02;
    e.stiffness_n_per_m = 300.0;
    e.influence_m = 0.01;
    return e;
}

TEST(LoopElastic, TheToolFeelsTheUndeformedSphereAndNothingOnceItLeaves) {
    TripleBuffer<ActiveSurface> surface;  // no workpiece snapshot: only the sphere is felt
    SpscRing<ToolSample> ring(4096);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg = ball_config(0.004);
    const Vec3 centre(0.0, 0.0, 0.05);
    cfg.elastic_objects.push_back(ball_at(centre));
    HapticLoop loop(dev, surface, ring, cfg);
    dev.state.pose.position = Vec3(0.0);
    const TickRecord first = loop.step(0.0);
    // The tool centre 22 mm above the sphere's centre: the 4 mm ball reaches 2 mm into the 20 mm sphere.
    const Vec3 target = centre + Vec3(0.0, 0.022, 0.0);
    dev.state.pose.position += target - first.hip_m;
    TickRecord r;
    for (int t = 1; t < 5; ++t) r = loop.step(t * 1e-3);
    ASSERT_NEAR(glm::length(r.hip_m - target), 0.0, 1e-9);
    EXPECT_TRUE(r.contact);
    EXPECT_EQ(r.points_in_contact, 1);
    // k * depth along the sphere's outward normal (+y): 300 N/m * 2 mm.
    EXPECT_NEAR(r.force_n.y, 300.0 * 0.002, 1e-6);
    EXPECT_NEAR(r.force_n.x, 0.0, 1e-9);
    EXPECT_NEAR(r.force_n.z, 0.0, 1e-9);
    // Away from the sphere: no contact, no force.
    dev.state.pose.position.y += 0.01;
    for (int t = 5; t < 10; ++t) r = loop.step(t * 1e-3);
    EXPECT_FALSE(r.contact);
    EXPECT_EQ(glm::length(r.force_n), 0.0);
}

TEST(LoopElastic, AStifferSphereThanTheDeviceAllowsIsCappedAndTheConfigIsChecked) {
    TripleBuffer<ActiveSurface> surface;
    SpscRing<ToolSample> ring(64);
    test::PoseDevice dev(devices::DeviceProfile::phantom_omni());
    HapticLoopConfig cfg = ball_config(0.004);
    cfg.elastic_objects.push_back(ball_at(Vec3(0.0, 0.0, 0.05)));
    cfg.elastic_objects[0].stiffness_n_per_m = 1e5;
    {
        HapticLoop loop(dev, surface, ring, cfg);
        EXPECT_TRUE(loop.stiffness_capped());
        EXPECT_LE(loop.config().elastic_objects[0].stiffness_n_per_m, dev.profile().max_stiffness_n_per_m);
    }
    HapticLoopConfig bad = cfg;
    bad.elastic_objects[0].radius_m = std::nan("");
    try {
        HapticLoop loop(dev, surface, ring, bad);
        FAIL() << "a NaN radius was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("elastic_objects[0]"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("radius_m"), std::string::npos) << e.what();
    }
    HapticLoopConfig many = cfg;
    many.elastic_objects.assign(kMaxElasticObjects + 1, ball_at(Vec3(0.0, 0.0, 0.05)));
    EXPECT_THROW(HapticLoop(dev, surface, ring, many), Error);
}

}  // namespace
}  // namespace tridex::haptics
