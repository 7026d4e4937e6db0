// The study tube's geometry and `study analyze` on recordings whose answers are known by construction.
#include <gtest/gtest.h>

#include <cmath>

#include <filesystem>
#include <fstream>

#include "app/commands/study/study_analyze.hpp"
#include "app/scene/study_recording.hpp"
#include "app/scene/study_scene.hpp"
#include "app/scene/tube.hpp"
#include "core/error.hpp"
#include "devices/recording.hpp"
#include "renderer/image/image.hpp"

namespace tridex::app::study {
namespace {

TubeSpec straight_tube() {  // along x from -0.18 to 0.18 m, radius 20 mm
    TubeSpec s;
    s.name = "straight";
    s.spine_m = {Vec3(-0.18, 0, 0.3), Vec3(0.18, 0, 0.3)};
    return s;
}

TEST(Tube, StraightTubeContactAndCaps) {
    const Tube t(straight_tube());
    EXPECT_NEAR(t.length_m(), 0.36, 1e-12);
    EXPECT_DOUBLE_EQ(t.deviation_m(Vec3(0.0, 0.015, 0.3)), 0.0);      // inside
    EXPECT_NEAR(t.deviation_m(Vec3(0.05, 0.026, 0.3)), 0.006, 1e-12);  // 6 mm through the wall
    const Vec3 c = t.collision_point(Vec3(0.05, 0.0, 0.33));
    EXPECT_NEAR(c.z, 0.32, 1e-12);
    EXPECT_NEAR(c.x, 0.05, 1e-12);
    // Entry funnel: the passage widens linearly from 20 mm to 40 mm over 40 mm.
    EXPECT_NEAR(t.passage_radius_m(-0.02), 0.03, 1e-12);
    EXPECT_NEAR(t.deviation_m(Vec3(-0.2, 0.035, 0.3)), 0.005, 1e-9);
    EXPECT_TRUE(t.touches_start_cap(Vec3(-0.222, 0.01, 0.3)));
    EXPECT_FALSE(t.touches_start_cap(Vec3(-0.21, 0.01, 0.3)));
    EXPECT_TRUE(t.touches_end_cap(Vec3(0.222, -0.01, 0.3)));
    EXPECT_NE(tube_id(t.spec()), tube_id(TubeSpec{straight_tube()}) + 1);
}

TEST(Tube, CurvedSpinePassesThroughItsControlPoints) {
    const StudyScene s = read_study_scene(default_study_scene_path());
    const Tube t(s.tube);
    for (const Vec3& p : s.tube.spine_m) EXPECT_LT(t.project(p).distance_m, 1e-9);
    EXPECT_NEAR(t.project(s.tube.spine_m.front()).s_m, 0.0, 1e-9);
    EXPECT_NEAR(t.project(s.tube.spine_m.back()).s_m, t.length_m(), 1e-9);
    EXPECT_DOUBLE_EQ(t.deviation_m(t.point_at(0.1) + 0.019 * glm::normalize(glm::cross(t.tangent_at(0.1), Vec3(0, 1, 0)))), 0.0);
}

// The spline's curvature at its middle control point of three, (-a, 0), (0, h), (a, 0): c' = (a, 0) and
// c'' = (0, -4h) there, so the radius is a^2 / (4h); a straight spine never bends.
TEST(Tube, TightestBendOfASymmetricArc) {
    const SpineBend b = tightest_bend({Vec3(-0.1, 0, 0), Vec3(0, 0.01, 0), Vec3(0.1, 0, 0)});
    EXPECT_NEAR(b.radius_m, 0.1 * 0.1 / (4.0 * 0.01), 1e-9);
    EXPECT_TRUE(std::isinf(tightest_bend({Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.2, 0, 0)}).radius_m));
    const StudyScene scene = read_study_scene(default_study_scene_path());
    EXPECT_GE(tightest_bend(scene.tube.spine_m).radius_m, kMinBendRadii * scene.tube.radius_m);
}

TEST(StudyScene, RefusesBadFields) {
    const auto dir = std::filesystem::temp_directory_path() / "tridex_study_scene_test";
    std::filesystem::create_directories(dir);
    auto refused = [&](const std::string& text, const std::string& what) {
        const auto p = dir / "s.json";
        std::ofstream(p) << text;
        try {
            read_study_scene(p.string());
            ADD_FAILURE() << "accepted " << text;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    refused(R"({"tube": {"spine_m": [[0,0,0]]}})", "field 'tube.spine_m'");
    refused(R"({"tube": {"spine_m": [[0,0,0],[0.1,0,0]], "radius_m": -1}})", "field 'tube.radius_m': must be in");
    refused(R"({"tube": {"spine_m": [[0,0,0],[0.1,0,0]], "colour": 1}})", "field 'tube.colour': unknown field");
    // A bend tighter than 1.5 tube radii would fold the tube's inner wall.
    refused(R"({"tube": {"spine_m": [[0,0,0],[0.03,0.03,0],[0.06,0,0]], "radius_m": 0.02}})",
            "field 'tube.spine_m': the spine bends with a radius of");
    refused(R"({"tube": {"spine_m": [[0,0,0],[0.1,0,0]]}, "protocol": {"test_trials": 1.5}})", "protocol.test_trials");
    refused(R"({"tube": {"spine_m": [[0,0,0],[0.1,0,0]]}, "models": {"test": {"tube": {"felt": 1}}}})",
            "field 'models.test.tube.felt'");
    refused("{", "not valid JSON: parse error at line 1");
    // A number beyond a double's range is placed and its field named, not left to escape as an internal error.
    refused(R"({"tube": {"spine_m": [[0,0,0],[0.1,0,1e400]]}})",
            "not valid JSON: number overflow at line 1, column 38, field 'tube.spine_m[1][2]': '1e400'");
}

// A recording of a wand held upright (top and bottom 20 mm apart in y) pushed from the start cap to the end cap
// along the straight tube, shifted by 15 mm in +y over the middle half of the path: there the top point is
// 5 mm through the wall (deviation 5 mm) and the bottom point inside (0).
devices::Recording synthetic_trial(const TubeSpec& tube, const std::string& participant, const std::string& group,
                                   int trial, int& shifted_ticks, int& analysed_ticks) {
    devices::Recording rec;
    rec.header.device_name = "wand";
    StudyTag tag{participant, group, trial, "test", tube.name, tube_id(tube)};
    rec.header.notes = tag_notes("", tag);
    const double x0 = -0.222, x1 = 0.222;
    const int hold = 100, move = 4000;
    shifted_ticks = analysed_ticks = 0;
    for (int i = 0; i < hold + move + hold; ++i) {
        const int k = std::clamp(i - hold, 0, move);
        const double x = x0 + (x1 - x0) * k / move;
        const bool shifted = x > -0.09 && x < 0.09;
        devices::RecordedTick t;
        t.t_s = 1e-3 * i;
        const double y = shifted ? 0.015 : 0.0;
        t.top_m = Vec3(x, y + 0.01, 0.3);
        t.bottom_m = Vec3(x, y - 0.01, 0.3);
        t.wand_centre_m = Vec3(x, y, 0.3);
        t.top_contact_m = t.top_m;
        t.bottom_contact_m = t.bottom_m;
        rec.ticks.push_back(t);
    }
    // The trial: from the last tick within 5 mm (half the 4 mm cap plus the 3 mm touch tolerance) of the start
    // cap's centre plane to the first within 5 mm of the end cap's.
    int first = 0, last = 0;
    for (int i = 0; i < static_cast<int>(rec.ticks.size()); ++i)
        if (rec.ticks[static_cast<std::size_t>(i)].top_m.x <= x0 + 0.005) first = i;
    for (int i = static_cast<int>(rec.ticks.size()) - 1; i >= 0; --i)
        if (rec.ticks[static_cast<std::size_t>(i)].top_m.x >= x1 - 0.005) last = i;
    for (int i = first; i <= last; ++i) {
        ++analysed_ticks;
        shifted_ticks += rec.ticks[static_cast<std::size_t>(i)].top_m.y > 0.02;
    }
    return rec;
}

TEST(StudyAnalyze, KnownDeviationAndTime) {
    const Tube tube(straight_tube());
    int shifted = 0, n = 0;
    const devices::Recording rec = synthetic_trial(tube.spec(), "P07", "haptic", 2, shifted, n);
    const TrialAnalysis a = analyze_trial(rec, tube, "synthetic.trdx");
    EXPECT_EQ(a.row.participant, "P07");
    EXPECT_EQ(a.row.group, "haptic");
    EXPECT_EQ(a.row.trial, 2);
    EXPECT_NEAR(a.row.time_s, 1e-3 * (n - 1), 1e-9);
    EXPECT_NEAR(a.row.deviation_top_m, 0.005 * shifted / n, 1e-9);
    EXPECT_NEAR(a.row.deviation_bottom_m, 0.0, 1e-12);
    EXPECT_NEAR(a.row.deviation_m, 0.0025 * shifted / n, 1e-9);
    EXPECT_NEAR(a.row.max_deviation_m, 0.005, 1e-9);
    EXPECT_EQ(a.progress.size(), static_cast<std::size_t>(n));
}

TEST(StudyAnalyze, RefusesAnotherTubeAndUntaggedRecordings) {
    const Tube tube(straight_tube());
    TubeSpec other = straight_tube();
    other.name = "other";
    other.radius_m = 0.025;
    int shifted = 0, n = 0;
    const devices::Recording rec = synthetic_trial(other, "P01", "visual", 1, shifted, n);
    try {
        analyze_trial(rec, tube, "other.trdx");
        ADD_FAILURE() << "analysed a recording of another tube";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("other.trdx: recorded against tube 'other'"), std::string::npos) << e.what();
    }
    devices::Recording plain = rec;
    plain.header.notes = R"({"mesh_path": "bunny.off"})";
    EXPECT_THROW(analyze_trial(plain, tube, "plain.trdx"), Error);
    devices::Recording stuck = synthetic_trial(tube.spec(), "P01", "visual", 1, shifted, n);
    stuck.ticks.resize(2000);  // never reaches the end cap
    EXPECT_THROW(analyze_trial(stuck, tube, "stuck.trdx"), Error);
}

TEST(StudyAnalyze, WritesTheTableAndAPlotPerGroup) {
    const auto dir = std::filesystem::temp_directory_path() / "tridex_study_analyze_test";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "rec");
    // The bundled tube is curved: analyse straight-line recordings against a scene file of the straight tube.
    const auto scene_file = dir / "straight.json";
    std::ofstream(scene_file) << nlohmann::json{{"tube", tube_to_json(straight_tube())}}.dump();
    int shifted = 0, n = 0;
    for (const auto& [p, g] : {std::pair<const char*, const char*>{"P01", "haptic"}, {"P02", "visual"}})
        for (int trial : {1, 2})
            devices::write_recording((dir / "rec" / (std::string(p) + "_" + std::to_string(trial) + ".trdx")).string(),
                                     synthetic_trial(straight_tube(), p, g, trial, shifted, n));
    StudyAnalyzeOptions o;
    o.inputs = {(dir / "rec").string()};
    o.scene = scene_file.string();
    o.out = (dir / "out").string();
    const auto trials = run_study_analyze(o);
    ASSERT_EQ(trials.size(), 4u);
    const auto rows = read_trial_csv((dir / "out" / "study_trials.csv").string());
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(rows[0].group, "haptic");
    EXPECT_NEAR(rows[0].max_deviation_m, 0.005, 1e-8);
    for (const char* g : {"haptic", "visual"}) {
        const renderer::Image im = renderer::read_png((dir / "out" / ("deviation_" + std::string(g) + ".png")).string());
        EXPECT_EQ(im.width, 1000);
        EXPECT_EQ(im.height, 560);
    }
    // The bundled (curved) tube is another tube: the same recordings are refused.
    o.scene.clear();
    EXPECT_THROW(run_study_analyze(o), Error);
}

}  // namespace
}  // namespace tridex::app::study
