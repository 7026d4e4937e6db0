// app/commands/export/export.cpp - saved model or scene -> CPU contour -> placed in the world -> STL / OBJ / PLY.
#include "app/commands/export/export.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <vector>

#include "app/scene/reference_objects.hpp"
#include "app/scene/run_scene.hpp"
#include "app/scene/workpiece_source.hpp"
#include "app/support/memory.hpp"
#include "app/support/output_dir.hpp"
#include "app/support/progress.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/mesh_obj_mtl.hpp"
#include "compute/mesh/mesh_write.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {

// What is exported: the workpiece's model with its placement, palette and pose, and a scene's reference objects.
struct ExportSource {
    compute::TriDexel model;
    Mat4 to_world{1.0};  // input mesh units -> world m (the model frame)
    MaterialPalette palette = default_material_palette();
    Pose pose{};  // the model frame -> the world (a scene's workpiece pose)
    std::vector<ReferenceSpec> references;
};

bool is_scene_file(const std::string& path) {
    return path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0;
}

ExportSource load_source(const std::string& path) {
    ExportSource src;
    if (!is_scene_file(path)) {
        ProgressReporter::Step step = progress().step("loading " + path);
        compute::TdxModel saved = compute::load_tdx(path, model_memory_budget_bytes(), step.fn());
        src.model = std::move(saved.model);
        src.to_world = saved.to_world;
        src.palette = saved.palette;
        return src;
    }
    RunScene scene = load_run_scene(path);
    if (scene.study.enabled) throw Error(path + ": a study scene has no workpiece to export");
    SessionSpec& spec = scene.spec;
    Workpiece wp = prepare_session_workpiece(spec);  // a saved model loaded, or the mesh scan-converted
    src.model = std::move(wp.model);
    src.to_world = wp.to_world;
    src.palette = spec.palette;
    src.pose = workpiece_pose(spec);
    src.references = spec.references;
    return src;
}

// A reference's mesh in the world, m (its own-frame mesh placed by its pose, as the session draws it).
TriMesh reference_in_world(const ReferenceSpec& r) {
    TriMesh mesh = load_reference_mesh(r);
    const Pose pose{r.position_m, r.orientation};
    for (Vec3& p : mesh.positions) p = pose.apply(p);
    return mesh;
}

// "ref_<name>" with every byte a material name may not hold replaced by '_', at most kMaterialNameMax bytes.
std::string reference_material_name(const std::string& name) {
    std::string out = "ref_" + name;
    for (char& c : out)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
    return out.substr(0, kMaterialNameMax);
}

// The workpiece and the references as OBJ objects, one material per palette entry and one per reference.
void write_obj(const std::string& out, const TriMesh& mesh, const std::vector<std::uint8_t>& materials,
               const MaterialPalette& palette, const std::vector<ReferenceSpec>& refs,
               const std::vector<TriMesh>& ref_meshes) {
    if (refs.empty()) return compute::write_obj_with_materials(out, mesh, materials, palette);
    std::vector<compute::ObjMaterial> lib;
    for (const PaletteEntry& e : palette.entries) lib.push_back({e.name, e.rgb});
    const std::vector<std::uint8_t> tri = compute::triangle_materials(mesh, materials);
    std::vector<compute::ObjObject> objects{{"workpiece", &mesh, std::vector<std::uint16_t>(tri.begin(), tri.end())}};
    for (std::size_t i = 0; i < refs.size(); ++i) {
        std::string name = reference_material_name(refs[i].name);
        for (int k = 2; std::any_of(lib.begin(), lib.end(), [&](const auto& m) { return m.name == name; }); ++k)
            name = reference_material_name(refs[i].name).substr(0, kMaterialNameMax - 3) + "_" + std::to_string(k);
        lib.push_back({name, {static_cast<float>(refs[i].colour.x), static_cast<float>(refs[i].colour.y),
                              static_cast<float>(refs[i].colour.z)}});
        objects.push_back({name, &ref_meshes[i],
                           std::vector<std::uint16_t>(ref_meshes[i].triangles.size(),
                                                      static_cast<std::uint16_t>(lib.size() - 1))});
    }
    compute::write_obj_objects(out, objects, lib);
}

// `extra` appended to `mesh` (its indices moved past mesh's vertices).
void append_mesh(TriMesh& mesh, const TriMesh& extra) {
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), extra.positions.begin(), extra.positions.end());
    for (auto t : extra.triangles) mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

}  // namespace

ExportResult run_export(const ExportOptions& o) {
    double scale = 1.0;
    if (o.units == "mm") scale = 1e3;
    else if (o.units == "in") scale = 1.0 / 0.0254;  // the international inch, 25.4 mm exactly
    else if (o.units != "m") throw Error("--units: must be m, mm or in, got '" + o.units + "'");
    if (o.frame != "world" && o.frame != "input") throw Error("--frame: must be world or input, got '" + o.frame + "'");
    if (o.objects != "workpiece" && o.objects != "all")
        throw Error("--objects: must be workpiece or all, got '" + o.objects + "'");
    if (o.frame == "input" && o.units != "m")
        throw Error("--units " + o.units + ", --frame input: the input frame keeps the input mesh's own units; choose one");
    const bool all = o.objects == "all";
    if (all && !is_scene_file(o.model))
        throw Error("--objects all: " + o.model + " is a model file, which holds the workpiece alone; give the scene "
                    "(a .json, such as the .scene.json a session saves beside its model)");
    if (all && o.frame == "input")
        throw Error("--objects all, --frame input: the input frame is the workpiece's own mesh's; the objects beside it "
                    "are placed in the world");
    const compute::MeshFileFormat format = compute::mesh_file_format(o.out);  // refuse .xyz before the slow work
    check_output_file(o.out, "OUT");
    if (format == compute::MeshFileFormat::kObj) check_output_file(compute::mtl_path_for(o.out), "OUT's material library");
    ExportSource src = load_source(o.model);
    compute::TriDexel& model = src.model;
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});
    compute::Contourer contourer(model);
    TriMesh mesh;
    {
        ProgressReporter::Step step = progress().step("contouring the model");
        contourer.update(model, step.fn());
        mesh = contourer.mesh();
    }
    const std::vector<std::uint8_t> materials = contourer.mesh_materials();

    ExportResult r;
    r.volume_dexel_m3 = compute::dexel_volume_m3(model);
    r.volume_mesh_m3 = signed_volume(mesh);
    r.vertices = mesh.positions.size();
    r.triangles = mesh.triangles.size();
    r.boundary_edges = edge_stats(mesh).boundary_edges;
    if (r.triangles == 0) throw Error(o.model + ": the model is empty; nothing to export");
    if (o.frame == "input") {  // the model frame -> the input mesh's frame: the inverse of the model's placement
        const Mat4 from_world = glm::inverse(src.to_world);
        for (Vec3& p : mesh.positions) p = Vec3(from_world * glm::dvec4(p, 1.0));
    } else {
        for (Vec3& p : mesh.positions) p = scale * src.pose.apply(p);
    }
    std::vector<ReferenceSpec> refs = all ? src.references : std::vector<ReferenceSpec>{};
    std::vector<TriMesh> ref_meshes;
    for (const ReferenceSpec& ref : refs) {
        ProgressReporter::Step step = progress().step("loading reference '" + ref.name + "'");
        ref_meshes.push_back(reference_in_world(ref));
        for (Vec3& p : ref_meshes.back().positions) p *= scale;
    }
    r.references = refs.size();
    {
        ProgressReporter::Step step = progress().step("writing " + o.out);
        if (format == compute::MeshFileFormat::kObj) {  // OBJ + a material library named from the palette
            write_obj(o.out, mesh, materials, src.palette, refs, ref_meshes);
        } else {
            // PLY: the palette's sRGB colour of each vertex's material, each reference's colour on its vertices.
            std::vector<std::array<std::uint8_t, 3>> colours;
            if (format == compute::MeshFileFormat::kPly)
                for (std::uint8_t m : materials) colours.push_back(srgb8(src.palette[m]));
            for (std::size_t i = 0; i < refs.size(); ++i) {
                append_mesh(mesh, ref_meshes[i]);
                const Vec3& c = refs[i].colour;
                if (format == compute::MeshFileFormat::kPly)
                    colours.insert(colours.end(), ref_meshes[i].positions.size(),
                                   {to_byte(static_cast<float>(c.x)), to_byte(static_cast<float>(c.y)),
                                    to_byte(static_cast<float>(c.z))});
            }
            compute::write_mesh_file(o.out, mesh, colours);
        }
    }
    const bool posed = !src.pose.is_identity() && o.frame == "world";
    std::printf("tridex export: %s -> %s (%zu vertices, %zu triangles, %s%s; volume %.6g m^3, tri-dexel %.6g m^3)%s\n",
                o.model.c_str(), o.out.c_str(), r.vertices, r.triangles,
                o.frame == "input" ? "the input mesh's frame and units"
                : o.units == "mm"  ? "millimetres"
                : o.units == "in"  ? "inches"
                                   : "metres",
                posed ? ", placed by the scene's pose" : "", r.volume_mesh_m3, r.volume_dexel_m3,
                refs.empty() ? "" : (" and " + std::to_string(refs.size()) + " reference object(s)").c_str());
    return r;
}

}  // namespace tridex::app
