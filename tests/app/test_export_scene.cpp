// `tridex export SCENE.json`: a scene's workpiece written where the scene's pose places it, vertex for vertex the
// model's contour moved by the pose; with --objects all, its reference objects beside it in one file (an OBJ object
// and material each), each where the session draws it; a scene of two workpieces as one mesh each or all in one; bad
// combinations refused in one line.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands/export/export.hpp"
#include "app/scene/reference_objects.hpp"
#include "app/scene/run_scene.hpp"
#include "app/scene/workpiece_list.hpp"
#include "app/scene/workpiece_source.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

std::string asset(const std::string& name) {
    const char* assets = std::getenv("TRIDEX_ASSETS");
    return fs::absolute(fs::path(assets ? assets : "assets") / name).string();
}

// The bunny at 48 cells (0.1 m stock), a groove carved across it, saved to dir/b.tdx; and a scene on it that moves
// and turns it and puts a turned bar beside it.
std::string write_posed_scene(const fs::path& dir) {
    Workpiece wp = prepare_workpiece(asset("bunny.off"), 48, 0.1, Vec3(0.0, 0.0, 0.05));
    const Aabb box = wp.model.lattice.bounds();
    compute::Sweep s;
    s.tool = compute::SweepTool{ToolKind::kBall, 0.008, 0.0};
    s.path_m = Segment{Vec3(box.lo.x, 0.0, 0.07), Vec3(box.hi.x, 0.01, 0.07)};
    compute::apply_sweep(wp.model, s);
    compute::save_tdx((dir / "b.tdx").string(), wp.model, wp.to_world, "{}");
    const std::string path = (dir / "scene.json").string();
    std::ofstream(path) << R"({
  "workpiece": { "model": "b.tdx", "position_m": [0.03, 0.01, 0.06], "axis": [0, 0, 1], "angle_deg": 45 },
  "references": [ { "name": "a stand", "mesh": ")" << asset("bar.off") << R"(", "size_m": 0.05,
                    "position_m": [0.1, 0.0, 0.05], "axis": [1, 0, 0], "angle_deg": 30, "colour": [0.2, 0.4, 0.6] } ]
})";
    return path;
}

// An OBJ file's objects: per `o` name its vertices in order; and each `usemtl` group's face count.
struct ObjFile {
    std::map<std::string, std::vector<Vec3>> vertices;
    std::vector<std::string> order;
    std::map<std::string, std::size_t> faces;
};

ObjFile read_obj(const std::string& path) {
    ObjFile f;
    std::ifstream in(path);
    std::string line, object, material;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string key;
        words >> key;
        if (key == "o") {
            object = line.substr(2);
            f.order.push_back(object);
        } else if (key == "v") {
            Vec3 p;
            words >> p.x >> p.y >> p.z;
            f.vertices[object].push_back(p);
        } else if (key == "usemtl") {
            words >> material;
        } else if (key == "f") {
            ++f.faces[material];
        }
    }
    return f;
}

// The largest distance between `a` and `b`, vertex by vertex (infinite when their counts differ).
double largest_gap(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    if (a.size() != b.size()) return 1e300;
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, glm::length(a[i] - b[i]));
    return worst;
}

TEST(ExportScene, TheWorkpieceIsWhereItsPosePlacesItAndTheReferencesBesideIt) {
    const fs::path dir = test::temp_dir("export_scene");
    const std::string scene_path = write_posed_scene(dir);
    // What the session would draw: the model's contour through the scene's pose, the reference through its own.
    RunScene scene = load_run_scene(scene_path);
    Workpiece wp = prepare_session_workpiece(scene.spec);
    const Pose pose = workpiece_pose(scene.spec);
    ASSERT_FALSE(pose.is_identity());
    compute::Contourer contourer(wp.model);
    contourer.update(wp.model);
    std::vector<Vec3> want_workpiece;
    for (const Vec3& p : contourer.mesh().positions) want_workpiece.push_back(pose.apply(p));
    const ReferenceSpec& ref = scene.spec.references.at(0);
    std::vector<Vec3> want_ref;
    for (const Vec3& p : load_reference_mesh(ref).positions) want_ref.push_back(ref.position_m + ref.orientation * p);

    ExportOptions o;
    o.model = scene_path;
    o.out = (dir / "all.obj").string();
    o.objects = "all";
    const ExportResult r = run_export(o);
    EXPECT_EQ(r.references, 1u);
    EXPECT_EQ(r.boundary_edges, 0u);
    const ObjFile f = read_obj(o.out);
    EXPECT_EQ(f.order, (std::vector<std::string>{"workpiece", "ref_a_stand"}));
    // OBJ keeps 9 significant digits: 1e-10 m on this 0.1 m scene.
    const double gap_wp = largest_gap(f.vertices.at("workpiece"), want_workpiece);
    const double gap_ref = largest_gap(f.vertices.at("ref_a_stand"), want_ref);
    EXPECT_LT(gap_wp, 1e-8);
    EXPECT_LT(gap_ref, 1e-8);
    EXPECT_EQ(f.faces.at("ref_a_stand"), load_reference_mesh(ref).triangles.size());
    std::ifstream mtl(dir / "all.mtl");
    std::stringstream text;
    text << mtl.rdbuf();
    EXPECT_NE(text.str().find("newmtl ref_a_stand\n# material 8, sRGB #336699\nKa 0 0 0\nKd 0.200000 0.400000 0.600000"),
              std::string::npos)
        << text.str();
    std::printf("workpiece: %zu vertices, at most %.3g m from the posed contour; reference: %zu vertices, %.3g m\n",
                want_workpiece.size(), gap_wp, want_ref.size(), gap_ref);

    // The model file alone is the model frame: the same vertices before the pose.
    o.model = (dir / "b.tdx").string();
    o.out = (dir / "model.obj").string();
    o.objects = "workpiece";
    (void)run_export(o);
    const ObjFile m = read_obj(o.out);
    EXPECT_LT(largest_gap(m.vertices.at(""), contourer.mesh().positions), 1e-8);
    EXPECT_GT(largest_gap(m.vertices.at(""), want_workpiece), 0.01);  // so the check above can fail

    // The input frame ignores the pose: the scene's export there is the model file's.
    o.model = scene_path;
    o.frame = "input";
    o.out = (dir / "scene_input.obj").string();
    (void)run_export(o);
    o.model = (dir / "b.tdx").string();
    o.out = (dir / "model_input.obj").string();
    (void)run_export(o);
    EXPECT_EQ(largest_gap(read_obj((dir / "scene_input.obj").string()).vertices.at(""),
                          read_obj((dir / "model_input.obj").string()).vertices.at("")),
              0.0);

    // PLY and STL, all in one: one mesh with every object's vertices.
    o.model = scene_path;
    o.frame = "world";
    o.objects = "all";
    o.out = (dir / "all.ply").string();
    (void)run_export(o);
    std::ifstream ply(o.out);
    std::string line, header;
    while (std::getline(ply, line) && line != "end_header") header += line + "\n";
    EXPECT_NE(header.find("element vertex " + std::to_string(want_workpiece.size() + want_ref.size()) + "\n"),
              std::string::npos)
        << header;
    fs::remove_all(dir);
}

TEST(ExportScene, ASceneOfTwoWorkpiecesExportsOneMeshEachOrAllInOne) {
    const fs::path dir = test::temp_dir("export_two");
    (void)write_posed_scene(dir);  // b.tdx
    const std::string scene_path = (dir / "two.json").string();
    std::ofstream(scene_path) << R"({"workpieces": [
        {"model": "b.tdx"},
        {"mesh": ")" << asset("bunny.off") << R"(", "resolution": 32, "stock_m": 0.08, "centre_m": [0.2, 0, 0.05],
         "axis": [0, 1, 0], "angle_deg": 90}]})";
    // What the session draws of the second: its contour through its own pose.
    RunScene scene = load_run_scene(scene_path);
    std::vector<Workpiece> more = prepare_more_workpieces(scene.spec);
    ASSERT_EQ(more.size(), 1u);
    const Pose pose = workpiece_pose(spec_for_workpiece(scene.spec, 1));
    compute::Contourer contourer(more[0].model);
    contourer.update(more[0].model);
    std::vector<Vec3> want;
    for (const Vec3& p : contourer.mesh().positions) want.push_back(pose.apply(p));

    ExportOptions o;
    o.model = scene_path;
    o.out = (dir / "two.obj").string();
    const ExportResult r = run_export(o);  // one mesh per workpiece: two.obj and two-wp2.obj
    EXPECT_EQ(r.workpieces, 2u);
    ASSERT_TRUE(fs::exists(dir / "two-wp2.obj"));
    ASSERT_TRUE(fs::exists(dir / "two-wp2.mtl"));
    EXPECT_LT(largest_gap(read_obj((dir / "two-wp2.obj").string()).vertices.at(""), want), 1e-8);
    o.objects = "all";
    o.out = (dir / "all.obj").string();
    (void)run_export(o);
    const ObjFile f = read_obj(o.out);
    EXPECT_EQ(f.order, (std::vector<std::string>{"workpiece", "workpiece_2"}));
    EXPECT_LT(largest_gap(f.vertices.at("workpiece_2"), want), 1e-8);
    EXPECT_GT(largest_gap(f.vertices.at("workpiece_2"), contourer.mesh().positions), 0.05);  // it was placed
    fs::remove_all(dir);
}

TEST(ExportScene, ChoicesThatCannotBeMetAreRefusedInOneLine) {
    const fs::path dir = test::temp_dir("export_scene_bad");
    const std::string scene_path = write_posed_scene(dir);
    const auto refusal = [&](ExportOptions o) {
        try {
            (void)run_export(o);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(no refusal)");
    };
    ExportOptions o;
    o.model = (dir / "b.tdx").string();
    o.out = (dir / "x.obj").string();
    o.objects = "all";
    EXPECT_NE(refusal(o).find("is a model file, which holds the workpiece alone"), std::string::npos) << refusal(o);
    o.model = scene_path;
    o.frame = "input";
    EXPECT_NE(refusal(o).find("--objects all, --frame input"), std::string::npos) << refusal(o);
    o.frame = "world";
    o.objects = "some";
    EXPECT_NE(refusal(o).find("--objects: must be workpiece or all, got 'some'"), std::string::npos) << refusal(o);
    o.objects = "workpiece";
    o.model = asset("study_test.json");
    EXPECT_NE(refusal(o).find("a study scene has no workpiece to export"), std::string::npos) << refusal(o);
    EXPECT_FALSE(fs::exists(dir / "x.obj"));
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
