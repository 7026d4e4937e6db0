// The study scene's objects as a session shows and feels them: meshes, contact, colours per model, the felt
// walls as a tri-dexel solid, and the scripted participant driven through the real haptic loop.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "app/scene/study_objects.hpp"
#include "app/scene/study_participant.hpp"
#include "app/scene/study_scene.hpp"
#include "app/commands/study/study_sim.hpp"
#include "app/scene/study_walls.hpp"
#include "app/scene/tube.hpp"
#include "core/error.hpp"

namespace tridex::app::study {
namespace {

// Whether world point p lies inside the solid by the Z ray nearest it.
bool solid_at(const compute::TriDexel& m, const Vec3& p) {
    const Vec3 g = m.lattice.to_grid(p);
    const int u = static_cast<int>(std::lround(g.x)), v = static_cast<int>(std::lround(g.y));
    if (u < 0 || v < 0 || u >= m.sets[2].nu || v >= m.sets[2].nv) return false;
    for (const compute::Interval& iv : m.sets[2].ray(u, v))
        if (g.z >= iv.enter && g.z <= iv.exit) return true;
    return false;
}

// A unit vector across the spine at s.
Vec3 across(const Tube& t, double s) {
    Vec3 u, v;
    plane_axes(t.tangent_at(s), u, v);
    return v;
}

TEST(StudyObjects, MeshesFaceOutwardAndCapsAreClosed) {
    const StudyScene scene = read_study_scene(default_study_scene_path());
    const Tube tube(scene.tube);
    const StudyObjectMeshes m = study_object_meshes(tube);
    ASSERT_GT(m.tube.triangles.size(), 1000u);
    // Tube and funnel triangles face away from the spine, on a straight tube and on the bundled curved one (whose
    // bends are wider than the tube's radius, so no inner side folds).
    auto outward_share = [](const Tube& t, const StudyObjectMeshes& mm) {
        std::size_t out = 0, all = 0;
        for (const TriMesh* mesh : {&mm.tube, &mm.entry_funnel, &mm.exit_funnel})
            for (const auto& tri : mesh->triangles) {
                const Vec3 a = mesh->positions[tri[0]], b = mesh->positions[tri[1]], c = mesh->positions[tri[2]];
                const Vec3 mid = (a + b + c) / 3.0;
                out += glm::dot(glm::cross(b - a, c - a), mid - t.project(mid).centre_m) > 0.0;
                ++all;
            }
        return static_cast<double>(out) / static_cast<double>(all);
    };
    TubeSpec straight;
    straight.spine_m = {Vec3(-0.18, 0, 0.3), Vec3(0.0, 0.0, 0.3), Vec3(0.18, 0, 0.3)};
    const Tube st(straight);
    EXPECT_EQ(outward_share(st, study_object_meshes(st)), 1.0);
    EXPECT_EQ(outward_share(tube, m), 1.0);
    for (const TriMesh* cap : {&m.start_cap, &m.end_cap}) {
        const EdgeStats e = edge_stats(*cap);
        EXPECT_EQ(e.boundary_edges, 0u);
        EXPECT_EQ(e.misoriented_edges, 0u);
        const TubeSpec& sp = scene.tube;
        EXPECT_NEAR(signed_volume(*cap), sp.cap_size_m * sp.cap_size_m * sp.cap_thickness_m, 1e-9);
    }
    // The funnels run from the mouth's square to the tube's diameter.
    EXPECT_EQ(m.entry_funnel.positions.size(), 9u * 4u);
    EXPECT_THROW(study_object_meshes(tube, 4), Error);
}

TEST(StudyObjects, ContactOfTheWandsTwoPoints) {
    const StudyScene scene = read_study_scene(default_study_scene_path());
    const Tube tube(scene.tube);
    const double s = 0.5 * tube.length_m(), r = scene.tube.radius_m;
    const Vec3 c = tube.point_at(s), n = across(tube, s);
    // Both points well inside: nothing touched.
    StudyContact k = study_contact(tube, c + 0.005 * n, c - 0.005 * n, 0.003);
    EXPECT_FALSE(k.tube || k.funnels || k.start_cap || k.end_cap);
    // One point at the wall (its ball reaches it): the tube is touched.
    k = study_contact(tube, c + (r - 0.003) * n, c, 0.003);
    EXPECT_TRUE(k.tube);
    EXPECT_FALSE(k.funnels);
    // A point in the entry funnel at its wall.
    const double sf = -0.5 * scene.tube.funnel_length_m;
    k = study_contact(tube, tube.point_at(sf) + tube.passage_radius_m(sf) * across(tube, sf), tube.point_at(sf), 0.0);
    EXPECT_TRUE(k.funnels);
    EXPECT_FALSE(k.tube);
    // A cap needs both points on it.
    const Vec3 sc = tube.point_at(tube.start_cap_s_m());
    EXPECT_TRUE(study_contact(tube, sc + 0.01 * across(tube, 0), sc - 0.01 * across(tube, 0), 0.003).start_cap);
    EXPECT_FALSE(study_contact(tube, sc, c, 0.003).start_cap);
    EXPECT_TRUE(study_contact(tube, tube.point_at(tube.end_cap_s_m()), tube.point_at(tube.end_cap_s_m()), 0.0).end_cap);
    // Non-finite points touch nothing.
    EXPECT_FALSE(study_contact(tube, Vec3(NAN), c, 0.0).tube);
}

TEST(StudyObjects, ColoursAndVisibilityFollowTheModels) {
    const StudyScene scene = read_study_scene(default_study_scene_path());
    const StudyObjectMeshes m = study_object_meshes(Tube(scene.tube));
    StudyContact none, tube_touched;
    tube_touched.tube = true;
    // Haptic training: the tube is not drawn; funnels and caps are.
    EXPECT_EQ(study_scene_objects(m, scene.haptic_training, none).size(), 4u);
    // Visual training: the tube is drawn, green, and red while touched.
    const auto free = study_scene_objects(m, scene.visual_training, none);
    ASSERT_EQ(free.size(), 5u);
    EXPECT_EQ(free[0].mesh, &m.tube);
    EXPECT_GT(free[0].colour.g, 0.5f);
    EXPECT_LT(free[0].colour.r, 0.3f);
    const auto touched = study_scene_objects(m, scene.visual_training, tube_touched);
    EXPECT_GT(touched[0].colour.r, 0.8f);
    EXPECT_LT(touched[0].colour.g, 0.3f);
    EXPECT_LT(touched[0].colour.a, 1.0f);  // translucent: the wand inside stays visible
    // Test: no tube; a cap turns red when both points touch it.
    const auto test_free = study_scene_objects(m, scene.test, none);
    EXPECT_EQ(test_free.size(), 4u);
    StudyContact on_cap;
    on_cap.start_cap = true;
    EXPECT_GT(study_object_colour(StudyObject::kStartCap, scene.test, on_cap).r, 0.8f);
    EXPECT_LT(study_object_colour(StudyObject::kEndCap, scene.test, on_cap).r, 0.3f);
    EXPECT_THROW(study_model(scene, "haptic", "model"), Error);
}

TEST(StudyWalls, EachModelFeelsItsOwnObjects) {
    const StudyScene scene = read_study_scene(default_study_scene_path());
    const Tube tube(scene.tube);
    const double s = 0.5 * tube.length_m(), r = scene.tube.radius_m, sf = -0.5 * scene.tube.funnel_length_m;
    const Vec3 wall = tube.point_at(s) + (r + 0.004) * across(tube, s);  // in the middle of the tube's 8 mm wall
    const Vec3 passage = tube.point_at(s) + 0.5 * r * across(tube, s);
    const Vec3 funnel_wall = tube.point_at(sf) + (tube.passage_radius_m(sf) + 0.004) * across(tube, sf);
    const Workpiece haptic = felt_walls(tube, scene.haptic_training, "t");
    EXPECT_TRUE(solid_at(haptic.model, wall));
    EXPECT_FALSE(solid_at(haptic.model, passage));
    EXPECT_TRUE(solid_at(haptic.model, funnel_wall));
    EXPECT_FALSE(solid_at(haptic.model, tube.point_at(sf)));
    EXPECT_GT(haptic.volume_dexel_m3, 0.0);
    const Workpiece test = felt_walls(tube, scene.test, "t");
    EXPECT_FALSE(solid_at(test.model, wall));
    EXPECT_TRUE(solid_at(test.model, funnel_wall));
    const Workpiece visual = felt_walls(tube, scene.visual_training, "t");
    EXPECT_EQ(visual.volume_dexel_m3, 0.0);
    WallOptions bad;
    bad.cell_m = 0.02;
    EXPECT_THROW(felt_walls(tube, scene.test, "t", bad), Error);
}

TEST(StudySim, FeltWallsHoldTheScriptedHandInsideTheTube) {
    const StudyScene scene = read_study_scene(default_study_scene_path());
    const Tube tube(scene.tube);
    // The same participant (seed) through the haptic and the visual training model of the real loop.
    const SimulatedPass haptic = simulate_pass(scene, "haptic_training", 11, 1);
    const SimulatedPass visual = simulate_pass(scene, "visual_training", 11, 1);
    ASSERT_GT(haptic.ticks, 3000u);
    EXPECT_EQ(haptic.ticks, visual.ticks);
    EXPECT_GT(haptic.contact_ticks, 0u);    // the walls were felt ...
    EXPECT_EQ(visual.contact_ticks, 0u);    // ... and the visual tube has no force
    EXPECT_GT(visual.tube_touch_ticks, 0u);  // but turned red
    EXPECT_GT(haptic.max_force_n, 0.1);
    EXPECT_LE(haptic.max_force_n, 20.0);
    // Deviation through the reference tube's wall: the felt walls push the wand back.
    auto max_dev = [&](const SimulatedPass& p) {
        double d = 0.0;
        for (const auto& t : p.recording.ticks) d = std::max({d, tube.deviation_m(t.top_m), tube.deviation_m(t.bottom_m)});
        return d;
    };
    EXPECT_LT(max_dev(haptic), max_dev(visual));
    // The wand starts on the start cap and ends on the end cap.
    EXPECT_TRUE(tube.touches_start_cap(haptic.recording.ticks.front().bottom_m));
    EXPECT_TRUE(tube.touches_end_cap(visual.recording.ticks.back().bottom_m));
    // Deterministic: the same inputs give the same ticks.
    const SimulatedPass again = simulate_pass(scene, "haptic_training", 11, 1);
    ASSERT_EQ(again.recording.ticks.size(), haptic.recording.ticks.size());
    EXPECT_EQ(again.recording.ticks.back().top_m, haptic.recording.ticks.back().top_m);
}

TEST(StudySim, TheTestModelsFunnelsAreFelt) {
    const StudyScene scene = read_study_scene(default_study_scene_path());
    const Tube tube(scene.tube);
    // A hand that enters the entry funnel 25 mm off the spine and keeps that offset into the tube (radius 20 mm):
    // the funnel's narrowing wall is in its way.
    ParticipantPath p;
    Vec3 u, v;
    plane_axes(tube.tangent_at(0.0), u, v);
    const double s0 = tube.start_cap_s_m(), s1 = 0.05;
    for (int i = 0; i <= 100; ++i) {
        const double f = i / 100.0, s = s0 + std::clamp(2.0 * f - 0.5, 0.0, 1.0) * (s1 - s0);
        p.t_s.push_back(3.0 * f);
        p.centre_m.push_back(tube.point_at(s) + 0.025 * u);
    }
    const SimulatedPass test = simulate_pass(scene, "test", 1, 1, &p);
    const SimulatedPass visual = simulate_pass(scene, "visual_training", 1, 1, &p);
    EXPECT_GT(test.contact_ticks, 100u);
    EXPECT_GT(test.max_force_n, 1.0);
    EXPECT_EQ(visual.contact_ticks, 0u);
    // Held back by the funnel's wall: the points go less far through it than without walls.
    auto max_funnel_dev = [&](const SimulatedPass& pass) {
        double d = 0.0;
        for (const auto& t : pass.recording.ticks)
            for (const Vec3& q : {t.top_m, t.bottom_m}) {
                const double s = tube.project(q).s_m;
                if (s >= -scene.tube.funnel_length_m && s <= 0.0) d = std::max(d, tube.deviation_m(q));
            }
        return d;
    };
    EXPECT_GT(max_funnel_dev(visual), 0.003);
    EXPECT_LT(max_funnel_dev(test), 0.6 * max_funnel_dev(visual));
}

}  // namespace
}  // namespace tridex::app::study
