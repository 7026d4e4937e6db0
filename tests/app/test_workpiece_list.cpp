// A scene of several workpieces, in parts: "workpieces" read into the spec (the first as the spec's own, the rest in
// more_workpieces), refused by name when wrong; the settings JSON keeps them (and a one-workpiece spec's JSON is as
// before); each workpiece's own spec and files; a recording's marks per workpiece; a further workpiece's mesh split by
// material for drawing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "app/scene/run_scene.hpp"
#include "app/scene/saved_scene.hpp"
#include "app/scene/workpiece_list.hpp"
#include "app/session/record/session_recording.hpp"
#include "app/session/view/more_view.hpp"
#include "core/error.hpp"
#include "cube_off.hpp"
#include "error_of.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using test::error_of;

struct SceneDir {
    fs::path dir = fs::temp_directory_path() / "tridex-test-workpiece-list";
    SceneDir() {
        fs::remove_all(dir);
        fs::create_directories(dir);
        test::write_cube_off(dir / "cube.off");
    }
    RunScene read(const std::string& text) const {
        return run_scene_from_json(json::parse(text), (dir / "scene.json").string(), dir.string());
    }
};

TEST(WorkpieceList, AScenesWorkpiecesAreTheFirstAndTheMore) {
    const SceneDir d;
    const RunScene s = d.read(R"({"workpieces": [{"mesh": "cube.off", "resolution": 40, "centre_m": [-0.1, 0, 0.05]},
                                                  {"mesh": "cube.off", "resolution": 48, "stock_m": 0.05,
                                                   "centre_m": [0.1, 0, 0.05], "axis": [0, 1, 0], "angle_deg": 90}],
                                  "stroke": {"workpiece": 1}})");
    EXPECT_EQ(workpiece_count(s.spec), 2u);
    EXPECT_EQ(s.spec.resolution, 40);
    EXPECT_EQ(s.spec.workpiece_centre_m, Vec3(-0.1, 0.0, 0.05));
    ASSERT_EQ(s.spec.more_workpieces.size(), 1u);
    const WorkpieceSpec& w = s.spec.more_workpieces[0];
    EXPECT_EQ(w.resolution, 48);
    EXPECT_DOUBLE_EQ(w.stock_m, 0.05);
    EXPECT_EQ(fs::path(w.mesh_path).filename(), "cube.off");
    EXPECT_TRUE(fs::path(w.mesh_path).is_absolute());
    EXPECT_NEAR(w.turn.w, std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(w.turn.y, std::sqrt(0.5), 1e-12);
    EXPECT_EQ(s.stroke_workpiece, 1u);
    // The second's own spec: its fields in the first's places, no further workpieces, the rest as the session's.
    const SessionSpec one = spec_for_workpiece(s.spec, 1);
    EXPECT_EQ(one.resolution, 48);
    EXPECT_TRUE(one.more_workpieces.empty());
    EXPECT_EQ(one.tool.radius_m, s.spec.tool.radius_m);
    EXPECT_NEAR(workpiece_pose(one).apply(w.centre_m).x, 0.1, 1e-12);  // it turns about its own centre
    EXPECT_NO_THROW(validate_spec(s.spec, "scene"));
    // A single "workpiece" is as before: no further workpieces.
    EXPECT_TRUE(d.read(R"({"workpiece": {"mesh": "cube.off"}})").spec.more_workpieces.empty());
}

TEST(WorkpieceList, TheBundledSceneOfTwoReads) {
    const char* assets = std::getenv("TRIDEX_ASSETS");
    const RunScene s = load_run_scene((fs::path(assets ? assets : "assets") / "two_workpieces_scene.json").string());
    EXPECT_EQ(workpiece_count(s.spec), 2u);
    EXPECT_EQ(s.stroke_workpiece, 1u);
    EXPECT_EQ(s.spec.references.size(), 1u);
    EXPECT_NO_THROW(validate_spec(s.spec, "two_workpieces_scene.json"));
}

TEST(WorkpieceList, BadListsAreRefusedByName) {
    const SceneDir d;
    const auto refused = [&](const std::string& text, const std::string& what) {
        const std::string e = error_of([&] { (void)d.read(text); });
        EXPECT_NE(e.find(what), std::string::npos) << text << "\n" << e;
    };
    refused(R"({"workpiece": {}, "workpieces": [{}]})", "field 'workpieces': not with \"workpiece\"");
    refused(R"({"workpieces": []})", "field 'workpieces': must be an array of 1 to 8 workpiece objects");
    refused(R"({"workpieces": [{}, {}, {}, {}, {}, {}, {}, {}, {}]})", "must be an array of 1 to 8");
    refused(R"({"workpieces": [{}, {"mesh": "nothing.off"}]})", "field 'workpieces[1].mesh': no such file");
    refused(R"({"workpieces": [{}, {"resolution": 3}]})", "field 'workpieces[1].resolution'");
    refused(R"({"workpieces": [{}, {"colour": 1}]})", "workpieces[1].colour");
    refused(R"({"workpieces": [{}, {"position_m": [0, 0, 0]}]})",
            "field 'workpieces[1].position_m': only with workpieces[1].model");
    refused(R"({"workpieces": [{}, {}], "stroke": {"workpiece": 2}})", "field 'stroke.workpiece'");
    // A spec read from a file is checked workpiece by workpiece.
    SessionSpec s = d.read(R"({"workpieces": [{}, {}]})").spec;
    s.more_workpieces[0].stock_m = -1.0;
    EXPECT_NE(error_of([&] { validate_spec(s, "rec.trdx"); }).find("rec.trdx: workpieces[1]: settings field 'stock_m'"),
              std::string::npos);
    s.more_workpieces.assign(8, s.more_workpieces[0]);
    EXPECT_NE(error_of([&] { validate_spec(s, "rec.trdx"); }).find("at most 8, got 9"), std::string::npos);
}

TEST(WorkpieceList, TheSettingsKeepThemAndOneWorkpieceReadsAsBefore) {
    const SceneDir d;
    const SessionSpec two = d.read(R"({"workpieces": [{}, {"mesh": "cube.off", "centre_m": [0.2, 0, 0],
                                                          "axis": [1, 0, 0], "angle_deg": 30}]})").spec;
    const SessionSpec back = spec_from_json(spec_to_json(two), "rec");
    ASSERT_EQ(back.more_workpieces.size(), 1u);
    const WorkpieceSpec &a = two.more_workpieces[0], &b = back.more_workpieces[0];
    EXPECT_EQ(a.mesh_path, b.mesh_path);
    EXPECT_EQ(a.centre_m, b.centre_m);
    EXPECT_EQ(a.turn, b.turn);  // floats exact: the pose decides where samples land
    EXPECT_EQ(a.shift_m, b.shift_m);
    EXPECT_EQ(spec_to_json(back), spec_to_json(two));
    const SessionSpec one = d.read("{}").spec;
    EXPECT_EQ(json::parse(spec_to_json(one)).count("more_workpieces"), 0u);  // journals of one workpiece as before
    json bad = json::parse(spec_to_json(one));
    bad["more_workpieces"] = json::parse(R"([{"mesh_path": 1}])");
    EXPECT_NE(error_of([&] { (void)spec_from_json(bad.dump(), "rec"); }).find("rec: settings field 'more_workpieces[0].mesh_path'"),
              std::string::npos);
}

TEST(WorkpieceList, EachWorkpieceHasItsOwnFilesAndSavedSceneEntry) {
    EXPECT_EQ(path_for_workpiece("out/session.tdj", 0), "out/session.tdj");
    EXPECT_EQ(path_for_workpiece("out/session.tdj", 1), "out/session-wp2.tdj");
    EXPECT_EQ(path_for_workpiece("carved.tdx", 3), "carved-wp4.tdx");
    EXPECT_EQ(path_for_workpiece("", 2), "");
    const SceneDir d;
    const SessionSpec s = d.read(R"({"workpieces": [{}, {"mesh": "cube.off", "centre_m": [0.2, 0, 0]}]})").spec;
    EXPECT_TRUE(needs_saved_scene(s, Pose{}));
    Pose moved;
    moved.position = Vec3(0.0, 0.1, 0.0);
    const json j = saved_scene_json(json::object(), d.dir.string(), (d.dir / "carved.tdx").string(), s, Pose{}, {moved});
    EXPECT_FALSE(j.contains("workpiece"));
    ASSERT_EQ(j["workpieces"].size(), 2u);
    EXPECT_EQ(j["workpieces"][0], json({{"model", "carved.tdx"}}));
    EXPECT_EQ(j["workpieces"][1]["model"], "carved-wp2.tdx");
    EXPECT_NEAR(j["workpieces"][1]["position_m"][1].get<double>(), 0.1, 1e-12);  // its centre where the hand left it
    EXPECT_NEAR(j["workpieces"][1]["position_m"][0].get<double>(), 0.2, 1e-12);
}

TEST(WorkpieceList, ARecordingKeepsEachWorkpiecesMarksInOneOrder) {
    const std::vector<SculptMark> first{{10, SculptRequest::kEndStroke}, {30, SculptRequest::kUndo}};
    const std::vector<std::vector<SculptMark>> more{{{10, SculptRequest::kEndStroke}, {20, SculptRequest::kRedo}}};
    const std::vector<devices::RecordedMark> all = recorded_marks(first, more);
    ASSERT_EQ(all.size(), 4u);
    EXPECT_EQ(all[0].workpiece, 0);
    EXPECT_EQ(all[1].workpiece, 1);  // the same count: the first workpiece's first
    EXPECT_EQ(all[2].after_samples, 20u);
    EXPECT_EQ(all[3].kind, "undo");
    devices::RecordingHeader h;
    h.marks = all;
    const auto mine = sculpt_marks(h, 1);
    ASSERT_TRUE(mine.has_value());
    ASSERT_EQ(mine->size(), 2u);
    EXPECT_EQ((*mine)[1].request, SculptRequest::kRedo);
    EXPECT_EQ(sculpt_marks(h, 0)->size(), 2u);
    EXPECT_TRUE(sculpt_marks(h, 2)->empty());
}

TEST(WorkpieceList, AFurtherWorkpiecesMeshIsDrawnInItsMaterials) {
    TriMesh m;
    m.positions = {Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0), Vec3(1.0, 1.0, 0.0)};
    m.triangles = {{0, 1, 2}, {3, 2, 1}};
    const std::vector<std::uint8_t> materials{0, 0, 3, 3};
    const TriMesh clay = triangles_of_material(m, materials, 0);
    ASSERT_EQ(clay.triangles.size(), 1u);
    EXPECT_EQ(clay.positions.size(), 3u);
    const TriMesh blue = triangles_of_material(m, materials, 3);
    ASSERT_EQ(blue.triangles.size(), 1u);
    EXPECT_EQ(blue.positions[blue.triangles[0][0]], Vec3(1.0, 1.0, 0.0));
    EXPECT_TRUE(triangles_of_material(m, materials, 5).triangles.empty());
    EXPECT_EQ(triangles_of_material(m, {}, 0).triangles.size(), 2u);  // no materials: all the workpiece's own
}

}  // namespace
}  // namespace tridex::app
