// Colours of one's own: a scene names materials' sRGB colours (and is refused, naming the field, when it names them
// wrongly), the session spec carries them through its JSON (journal, recording, saved model), the menu and the desk
// keys choose them, and `tridex export` writes them as PLY vertex colours and as an OBJ with a material library.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

// GCC 12 reports OpenMesh's own PropertyT<VectorT<uchar, 3>>::push_back (the vertex colours) as maybe uninitialised,
// a false positive inside the library's header (as compute/mesh/mesh_write.cpp says).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#pragma GCC diagnostic pop
#include <nlohmann/json.hpp>

#include "app/actions/action_registry.hpp"
#include "app/commands/export/export.hpp"
#include "app/input/key_bindings.hpp"
#include "app/menu/pie_menu.hpp"
#include "app/scene/run_scene.hpp"
#include "app/scene/workpiece_source.hpp"
#include "compute/mesh/mesh_obj_mtl.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

RunScene scene_of(const std::string& text) { return run_scene_from_json(json::parse(text), "scene.json", "."); }

TEST(Colours, ASceneNamesColoursInSrgbAndChoosesOneByName) {
    const RunScene s = scene_of(R"({"op": "paint", "material": "teal",
        "materials": [{"id": 2, "name": "teal", "colour": "#2a9d8f"},
                      {"id": 3, "name": "sand", "colour": [233, 196, 106], "stiffness_n_per_m": 400},
                      {"id": 0, "name": "stone"},
                      {"id": 9, "stiffness_n_per_m": 300}]})");
    EXPECT_EQ(s.spec.material, 2);
    const MaterialPalette& p = s.spec.palette;
    EXPECT_EQ(p[2].name, "teal");
    EXPECT_EQ(srgb8(p[2]), (std::array<std::uint8_t, 3>{0x2a, 0x9d, 0x8f}));
    EXPECT_EQ(p[2].rgb[0], 0x2a / 255.0f);
    EXPECT_EQ(p[3].name, "sand");
    EXPECT_EQ(srgb8(p[3]), (std::array<std::uint8_t, 3>{233, 196, 106}));
    EXPECT_EQ(p[0].name, "stone");  // renamed, its colour kept
    EXPECT_EQ(p[0].rgb, default_material_palette()[0].rgb);
    EXPECT_EQ(p[1], default_material_palette()[1]);
    // Contact entries: id 3 (it has a stiffness) and id 9; the colour-only entries are not contact entries.
    ASSERT_EQ(s.spec.materials.size(), 2u);
    EXPECT_EQ(s.spec.materials[0].id, 3);
    EXPECT_EQ(s.spec.materials[1].id, 9);
    // A scene without materials keeps the default palette and the spec's JSON as it was.
    const RunScene plain = scene_of("{}");
    EXPECT_EQ(plain.spec.palette, default_material_palette());
    EXPECT_EQ(spec_to_json(plain.spec).find("palette"), std::string::npos);
}

TEST(Colours, BadColoursAndNamesAreRefusedNamingTheField) {
    struct Case {
        const char* json;
        const char* says;
    };
    const Case cases[] = {
        {R"({"materials": [{"id": 1, "name": "teal", "colour": "#12"}]})",
         "field 'materials[0].colour': must be \"#rrggbb\" or [r, g, b] with 0..255 (sRGB), got \"#12\""},
        {R"({"materials": [{"id": 1, "name": "teal", "colour": [1, 2, 300]}]})", "'materials[0].colour'"},
        {R"({"materials": [{"id": 1, "name": "teal", "colour": [1, 2]}]})", "'materials[0].colour'"},
        {R"({"materials": [{"id": 1, "colour": "#112233"}]})", "'materials[0].colour': a colour needs a name"},
        {R"({"materials": [{"id": 8, "name": "teal"}]})", "'materials[0].id': a named colour needs a material id 0..7, got 8"},
        {R"({"materials": [{"id": 1, "name": "deep sea"}]})", "'materials[0].name': a material name takes only"},
        {R"({"materials": [{"id": 1, "name": ""}]})", "'materials[0].name'"},
        {R"({"materials": [{"id": 1, "name": "teal"}, {"id": 2, "name": "teal"}]})",
         "field 'materials': the name 'teal' names materials 1 and 2"},
        {R"({"materials": [{"id": 4, "name": "red"}]})", "names materials 1 and 4 (1 by default: rename it too)"},
        {R"({"materials": [{"id": 1, "name": "a"}, {"id": 1, "name": "b"}]})", "'materials[1].id': material 1 is listed twice"},
        {R"({"materials": [{"id": 1, "name": "a", "color": "#112233"}]})", "'materials[0].color': unknown field"},
        {R"({"material": "teal"})", "field 'material': 'teal' is not a material; use red, green"},
        {R"({"material": "clay"})", "'material': 'clay' is the workpiece's own material (0)"},
        {R"({"material": 8})", "'material': must be between 1 and 7"},
    };
    for (const Case& c : cases) {
        const std::string m = error_of([&] { (void)scene_of(c.json); });
        EXPECT_NE(m.find("scene.json"), std::string::npos) << c.json << " -> " << m;
        EXPECT_NE(m.find(c.says), std::string::npos) << c.json << " -> " << m;
    }
}

TEST(Colours, TheSpecJsonCarriesThePaletteBitForBit) {
    RunScene s = scene_of(R"({"materials": [{"id": 5, "name": "Ochre_1", "colour": "#cc7722"}, {"id": 0, "name": "wax"}]})");
    s.spec.palette.entries[6].rgb = {0.1f, 0.2f, 0.30000001f};  // floats kept exactly
    const std::string text = spec_to_json(s.spec);
    EXPECT_NE(text.find("\"palette\""), std::string::npos);
    const SessionSpec back = spec_from_json(text, "journal.tdj");
    EXPECT_EQ(back.palette, s.spec.palette);
    EXPECT_EQ(spec_to_json(back), text);
    // A spec without a palette (older journals and recordings) reads as the default one.
    json j = json::parse(text);
    j.erase("palette");
    EXPECT_EQ(spec_from_json(j.dump(), "old.trdx").palette, default_material_palette());
    // A damaged palette is refused naming the field.
    j = json::parse(text);
    j["palette"][3]["name"] = "wax";
    const std::string m = error_of([&] { (void)spec_from_json(j.dump(), "bad.trdx"); });
    EXPECT_NE(m.find("bad.trdx: settings field 'palette': material 3: the name 'wax' is already material 0's"),
              std::string::npos) << m;
    j = json::parse(text);
    j["palette"].erase(7);
    EXPECT_NE(error_of([&] { (void)spec_from_json(j.dump(), "bad.trdx"); }).find("'palette' must be an array of 8"),
              std::string::npos);
}

TEST(Colours, TheMenuAndTheKeysChooseTheMaterials) {
    MaterialPalette p = default_material_palette();
    p.entries[2].name = "teal";
    const MenuItem root = default_menu(p);
    ASSERT_EQ(root.children.size(), 8u);
    EXPECT_EQ(root.children[0].children.size(), 7u);  // the operations, grab last (subtract still at 12 o'clock)
    EXPECT_EQ(root.children[0].children[0].action, "op.subtract");
    EXPECT_EQ(root.children[0].children[6].action, "op.grab");
    // Placing the workpiece arranges the scene: the View ring's last slice.
    ASSERT_EQ(root.children[5].label, "View");
    EXPECT_EQ(root.children[5].children.back().action, "op.place");
    const MenuItem& tool = root.children[1];
    ASSERT_EQ(tool.label, "Tool");
    ASSERT_EQ(tool.children.size(), 6u);  // larger up and smaller down, as before; Colour right, Symmetry left
    EXPECT_EQ(tool.children[0].action, "tool.larger");
    EXPECT_EQ(tool.children[2].action, "coarseness.finer");
    EXPECT_EQ(tool.children[3].action, "tool.smaller");
    EXPECT_EQ(tool.children[4].action, "coarseness.coarser");
    EXPECT_EQ(tool.children[5].action, "symmetry.toggle");
    ASSERT_EQ(tool.children[1].label, "Colour");
    const MenuItem& colours = tool.children[1];
    ASSERT_EQ(colours.children.size(), 7u);
    EXPECT_EQ(colours.children[1].label, "teal");
    EXPECT_EQ(colours.children[1].action, "material.2");
    EXPECT_EQ(colours.children[1].glyph, "2");
    EXPECT_EQ(colours.children[6].label, "purple");
    for (int m = 1; m <= kMaxMaterialId; ++m) {
        const KeyBinding* k = find_key_binding(static_cast<renderer::Key>(static_cast<int>(renderer::Key::k0) + m),
                                               renderer::modifier::kShift, true);
        ASSERT_TRUE(k) << m;
        EXPECT_EQ(k->action, "material." + std::to_string(m));
        EXPECT_EQ(chord_name(*k), "Shift+" + std::to_string(m));
    }
    EXPECT_EQ(find_key_binding(renderer::Key::k3, 0, true)->action, "op.paint");  // the digits alone stay operations
}

// A bunny painted with materials 2 (a stripe) and 5 (a band), saved with a palette of the test's own colours.
compute::TriDexel painted_bunny(const std::string& path, const MaterialPalette& palette) {
    const char* assets = std::getenv("TRIDEX_ASSETS");
    Workpiece wp = prepare_workpiece((fs::path(assets ? assets : "assets") / "bunny.off").string(), 64, 0.3,
                                     Vec3(0.0, 0.0, 0.3));
    const Aabb box = wp.model.lattice.bounds();
    compute::Sweep s;
    s.tool = compute::SweepTool{ToolKind::kFlatEnd, 0.012, 0.03};
    s.op = ToolOp::kPaint;
    s.material = 2;
    s.path_m = Segment{Vec3(0.0, box.hi.y, 0.3), Vec3(0.0, box.lo.y, 0.3)};
    compute::apply_sweep(wp.model, s);
    s.material = 5;
    s.path_m = Segment{Vec3(box.lo.x, 0.0, 0.3), Vec3(box.hi.x, 0.0, 0.3)};
    compute::apply_sweep(wp.model, s);
    compute::save_tdx(path, wp.model, wp.to_world, "{}", 3, palette);
    return wp.model;
}

MaterialPalette test_palette() {
    MaterialPalette p = default_material_palette();
    p.entries[0] = {"bone", rgb_from_srgb8({0xf0, 0xe6, 0xd2})};
    p.entries[2] = {"teal", rgb_from_srgb8({0x2a, 0x9d, 0x8f})};
    p.entries[5] = {"ochre", rgb_from_srgb8({0xcc, 0x77, 0x22})};
    return p;
}

TEST(Colours, ASceneOnASavedModelNamesItsColoursAndRecoloursThem) {
    const fs::path dir = test::temp_dir("colours_model");
    (void)painted_bunny((dir / "b.tdx").string(), test_palette());
    const RunScene s = run_scene_from_json(json::parse(R"({"workpiece": {"model": "b.tdx"}, "material": "ochre",
        "materials": [{"id": 1, "name": "rose", "colour": "#ff007f"}]})"), "scene.json", dir.string());
    EXPECT_EQ(s.spec.material, 5);
    EXPECT_EQ(s.spec.palette[2], test_palette()[2]);  // the model's
    EXPECT_EQ(s.spec.palette[1].name, "rose");        // the scene's
    EXPECT_EQ(hex_colour(srgb8(s.spec.palette[1])), "#ff007f");
    SessionSpec spec = s.spec;
    (void)prepare_session_workpiece(spec);
    EXPECT_EQ(spec.palette, s.spec.palette);  // the scene's renaming is kept
}

TEST(Colours, PlyVerticesCarryThePalettesSrgbColours) {
    const fs::path dir = test::temp_dir("colours_ply");
    const MaterialPalette palette = test_palette();
    (void)painted_bunny((dir / "b.tdx").string(), palette);
    ExportOptions o;
    o.model = (dir / "b.tdx").string();
    o.out = (dir / "b.ply").string();
    (void)run_export(o);
    OpenMesh::TriMesh_ArrayKernelT<> om;
    om.request_vertex_colors();
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexColor;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(om, o.out, opt));
    ASSERT_TRUE(opt.check(OpenMesh::IO::Options::VertexColor));
    std::map<std::array<int, 3>, std::size_t> seen;
    for (auto v : om.vertices()) {
        const auto c = om.color(v);
        ++seen[{c[0], c[1], c[2]}];
    }
    // Exactly the three materials' colours, each on many vertices.
    ASSERT_EQ(seen.size(), 3u);
    for (const char* hex : {"#f0e6d2", "#2a9d8f", "#cc7722"}) {
        std::array<std::uint8_t, 3> rgb{};
        ASSERT_TRUE(parse_hex_colour(hex, rgb));
        EXPECT_GT((seen[{rgb[0], rgb[1], rgb[2]}]), 50u) << hex;
    }
    std::printf("PLY: %zu bone, %zu teal, %zu ochre vertices\n", seen[{0xf0, 0xe6, 0xd2}], seen[{0x2a, 0x9d, 0x8f}],
                seen[{0xcc, 0x77, 0x22}]);
}

TEST(Colours, ObjGroupsTrianglesUnderTheMaterialLibrarysNamedColours) {
    const fs::path dir = test::temp_dir("colours_obj");
    const MaterialPalette palette = test_palette();
    (void)painted_bunny((dir / "b.tdx").string(), palette);
    ExportOptions o;
    o.model = (dir / "b.tdx").string();
    o.out = (dir / "b.obj").string();
    const ExportResult r = run_export(o);
    // The library: one material per id used, Kd the linear colour.
    std::ifstream mtl(dir / "b.mtl");
    ASSERT_TRUE(mtl.good());
    std::map<std::string, std::array<double, 3>> kd;
    std::string line, current;
    while (std::getline(mtl, line)) {
        std::istringstream in(line);
        std::string key;
        in >> key;
        if (key == "newmtl") in >> current;
        if (key == "Kd") in >> kd[current][0] >> kd[current][1] >> kd[current][2];
    }
    ASSERT_EQ(kd.size(), 3u);
    for (int m : {0, 2, 5})
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(kd[palette[m].name][k], palette[m].rgb[k], 1e-6) << m;
    // The OBJ: mtllib, usemtl groups in id order, every triangle once, each face's material its corners' majority.
    std::ifstream obj(dir / "b.obj");
    std::vector<std::string> groups;
    std::map<std::string, std::size_t> faces;
    bool lib = false;
    while (std::getline(obj, line)) {
        if (line == "mtllib b.mtl") lib = true;
        if (line.rfind("usemtl ", 0) == 0) groups.push_back(line.substr(7));
        if (line.rfind("f ", 0) == 0) ++faces[groups.empty() ? "" : groups.back()];
    }
    EXPECT_TRUE(lib);
    EXPECT_EQ(groups, (std::vector<std::string>{"bone", "teal", "ochre"}));
    EXPECT_EQ(faces["bone"] + faces["teal"] + faces["ochre"], r.triangles);
    EXPECT_GT(faces["teal"], 100u);
    EXPECT_GT(faces["ochre"], 100u);
    std::printf("OBJ: %zu bone, %zu teal, %zu ochre triangles\n", faces["bone"], faces["teal"], faces["ochre"]);
}

TEST(Colours, TriangleMaterialsAreTheirCornersMajority) {
    TriMesh m;
    m.positions.resize(4, Vec3(0.0));
    m.triangles = {{0, 1, 2}, {1, 2, 3}, {0, 1, 3}};
    const std::vector<std::uint8_t> v = {2, 2, 5, 9};  // 9 reads as 0
    EXPECT_EQ(compute::triangle_materials(m, v), (std::vector<std::uint8_t>{2, 0, 2}));
    EXPECT_EQ(compute::mtl_path_for("out/a.b/part.obj"), "out/a.b/part.mtl");
    EXPECT_EQ(compute::mtl_path_for("out/a.b/part"), "out/a.b/part.mtl");
}

}  // namespace
}  // namespace tridex::app
