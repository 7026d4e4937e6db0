// Tests of haptics/elastic_object (Popescu, Burdea, Bouzit 3.3): the squeeze sequence of an elastic ball (the
// dent grows with the press and vanishes on release), the force from the undeformed reference, and the falloff.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "core/primitives.hpp"
#include "haptics/elastic_object.hpp"
#include "haptics/tool_points.hpp"

namespace tridex::haptics {
namespace {

ElasticSphere ball() {
    ElasticSphere s;
    s.centre_m = Vec3(0.0, 0.0, 0.3);
    s.radius_m = 0.03;
    s.stiffness_n_per_m = 300.0;
    s.influence_m = 0.015;
    return s;
}

// The tool centre pressed `depth_m` into the ball's top (a ball tool of radius rho, its bottom at the surface
// for depth 0).
Pose pressed(const ElasticSphere& s, double rho, double depth_m) {
    Pose p;
    p.position = s.centre_m + Vec3(0.0, s.radius_m + rho - depth_m, 0.0);
    return p;
}

TEST(ElasticObject, SqueezeSequenceGrowsThenSpringsBack) {
    // Popescu et al. Fig. 4: a ball squeezed deeper and deeper, then let go.
    const ElasticSphere s = ball();
    const TriMesh reference = icosphere_mesh(s.centre_m, s.radius_m, 4);
    const ToolPoints mesh = ToolPoints::sphere_mesh(0.006, 32);
    TriMesh drawn;
    double last = 0.0;
    for (int step = 1; step <= 6; ++step) {
        const double depth = 0.0015 * step;
        const ElasticContacts c = elastic_contacts(s, mesh, pressed(s, 0.006, depth));
        ASSERT_GT(c.count, 0);
        deform_elastic_mesh(reference, c, s.influence_m, drawn);
        const double shown = max_vertex_displacement_m(reference, drawn);
        EXPECT_GT(shown, last + 1e-4) << "step " << step;  // grows with every step of the press
        EXPECT_LE(shown, c.max_depth_m() + 1e-12);           // never beyond the deepest interaction point
        EXPECT_GT(shown, 0.7 * depth);  // the vertex under the tool follows it (icosphere vertex spacing ~ 2 mm)
        last = shown;
    }
    // Released: the tool well outside the ball.
    const ElasticContacts none = elastic_contacts(s, mesh, pressed(s, 0.006, -0.01));
    EXPECT_EQ(none.count, 0);
    deform_elastic_mesh(reference, none, s.influence_m, drawn);
    EXPECT_LT(max_vertex_displacement_m(reference, drawn), 1e-12);
}

TEST(ElasticObject, ForceIsStiffnessTimesPenetrationIntoTheUndeformedSurface) {
    const ElasticSphere s = ball();
    const ToolPoints hip = ToolPoints::single(0.006);
    for (double depth : {0.0005, 0.002, 0.005}) {
        const ElasticContacts c = elastic_contacts(s, hip, pressed(s, 0.006, depth));
        ASSERT_EQ(c.count, 1);
        const Vec3 f = elastic_force(s, c, 100.0);
        EXPECT_NEAR(f.y, s.stiffness_n_per_m * depth, 1e-9) << depth;
        EXPECT_NEAR(f.x, 0.0, 1e-12);
        EXPECT_NEAR(f.z, 0.0, 1e-12);
    }
    // The drawn dent does not soften the object: the same pose gives the same force however deformed it is shown.
    const ElasticContacts c = elastic_contacts(s, hip, pressed(s, 0.006, 0.004));
    TriMesh drawn;
    deform_elastic_mesh(icosphere_mesh(s.centre_m, s.radius_m, 3), c, s.influence_m, drawn);
    EXPECT_NEAR(glm::length(elastic_force(s, c, 100.0)), 300.0 * 0.004, 1e-9);
    // Sideways into the ball's flank: along the reference normal there.
    Pose side;
    side.position = s.centre_m + Vec3(s.radius_m + 0.006 - 0.003, 0.0, 0.0);
    const Vec3 fs = elastic_force(s, elastic_contacts(s, hip, side), 100.0);
    EXPECT_NEAR(fs.x, 0.9, 1e-9);
    EXPECT_NEAR(fs.y, 0.0, 1e-12);
}

TEST(ElasticObject, InteractionMeshForceResistsThePressAndIsBounded) {
    const ElasticSphere s = ball();
    const ToolPoints mesh = ToolPoints::sphere_mesh(0.006, 32);
    const ElasticContacts c = elastic_contacts(s, mesh, pressed(s, 0.006, 0.003));
    EXPECT_GT(c.count, 3);
    const Vec3 f = elastic_force(s, c, 100.0);
    // k times the deepest point's penetration, whatever the number of points in contact; out of the ball.
    EXPECT_NEAR(glm::length(f), s.stiffness_n_per_m * c.max_depth_m(), 1e-9);
    EXPECT_GT(c.max_depth_m(), 0.0025);
    EXPECT_GT(f.y, 0.95 * glm::length(f));
    // A point deep inside: the device limit holds; a bad limit or pose gives nothing.
    const Pose deep = pressed(s, 0.006, 0.05);
    EXPECT_NEAR(glm::length(elastic_force(s, elastic_contacts(s, mesh, deep), 3.3)), 3.3, 1e-9);
    EXPECT_EQ(glm::length(elastic_force(s, elastic_contacts(s, mesh, deep), 0.0)), 0.0);
    Pose bad;
    bad.position = Vec3(std::nan(""), 0.0, 0.0);
    EXPECT_EQ(elastic_contacts(s, mesh, bad).count, 0);
    // The tool centre exactly at the ball's centre: a defined direction, not NaN.
    Pose centre;
    centre.position = s.centre_m;
    const Vec3 fc = elastic_force(s, elastic_contacts(s, ToolPoints::single(0.006), centre), 100.0);
    EXPECT_TRUE(is_finite(fc));
    EXPECT_NEAR(glm::length(fc), 300.0 * 0.036, 1e-9);
}

TEST(ElasticObject, FalloffWithinTheRadiusOfInfluence) {
    const ElasticSphere s = ball();
    const TriMesh reference = icosphere_mesh(s.centre_m, s.radius_m, 5);
    const ElasticContacts c = elastic_contacts(s, ToolPoints::single(0.0), pressed(s, 0.0, 0.004));
    ASSERT_EQ(c.count, 1);
    TriMesh drawn;
    deform_elastic_mesh(reference, c, s.influence_m, drawn);
    ASSERT_EQ(drawn.triangles.size(), reference.triangles.size());
    for (std::size_t v = 0; v < reference.positions.size(); ++v) {
        const double d = glm::length(reference.positions[v] - c.contact[0].surface_m);
        const double k = d < s.influence_m ? 1.0 - (d / s.influence_m) * (d / s.influence_m) : 0.0;
        const Vec3 u = drawn.positions[v] - reference.positions[v];
        EXPECT_NEAR(u.y, -0.004 * k, 1e-12) << v;  // along -n at the interaction point (n = +y)
        EXPECT_NEAR(u.x, 0.0, 1e-12);
        EXPECT_NEAR(u.z, 0.0, 1e-12);
    }
}

TEST(ElasticObject, RefusesBadFieldsNamingThem) {
    ElasticSphere s = ball();
    s.influence_m = 0.05;
    try {
        validate(s, "scene.json: objects[0]");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("scene.json: objects[0]: field 'influence_radius_m'"), std::string::npos)
            << e.what();
    }
    s = ball();
    s.stiffness_n_per_m = -1.0;
    EXPECT_THROW(validate(s, "x"), Error);
    s = ball();
    s.radius_m = std::nan("");
    EXPECT_THROW(validate(s, "x"), Error);
    EXPECT_THROW(max_vertex_displacement_m(icosphere_mesh(Vec3(0.0), 1.0, 1), icosphere_mesh(Vec3(0.0), 1.0, 2)), Error);
}

}  // namespace
}  // namespace tridex::haptics
